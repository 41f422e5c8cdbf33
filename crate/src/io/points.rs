//! Plain point lists: `.xyz`, `.pts`, `.csv`, `.txt`.
//!
//! One point per line; values separated by whitespace, commas or semicolons; the first three
//! numbers are x y z and further columns (intensity, colour, ...) are ignored, except:
//! - **Normals**: when *every* point line has exactly 6 numbers and every `(n4, n5, n6)` has
//!   a length between 0.9 and 1.1, columns 4-6 are read as normals. (A `x y z r g b` file
//!   with 0-255 colours thus never gets normals.)
//! - **Count lines** (PTS): a line holding a single integer is a point count and skipped.
//! - **Header** (CSV): the first non-comment line is skipped when it has a token that is not
//!   a number (e.g. `x,y,z`).
//! - Empty lines and lines starting with `#` or `//` are skipped.

use glam::Vec3;

use super::{Format, Limits, Location, ReadError, check_limit, finish, malformed, vertex_limit};
use crate::geometry::mesh::Mesh;

const F: Format = Format::Points;

fn split(line: &str) -> impl Iterator<Item = &str> {
    line.split(|c: char| c.is_ascii_whitespace() || c == ',' || c == ';')
        .filter(|t| !t.is_empty())
}

fn is_comment(line: &str) -> bool {
    line.is_empty() || line.starts_with('#') || line.starts_with("//")
}

pub(super) fn read(bytes: &[u8], limits: &Limits) -> Result<Mesh, ReadError> {
    let text = super::utf8(F, bytes)?;
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let vmax = vertex_limit(limits);
    let mut positions: Vec<Vec3> = Vec::new();
    let mut normals: Vec<Vec3> = Vec::new();
    let mut normals_possible = true;
    let mut first = true;
    let mut vals: Vec<f32> = Vec::with_capacity(8);
    for (i, line) in text.lines().enumerate() {
        let loc = || Location::Line(i + 1);
        let line = line.trim();
        if is_comment(line) {
            continue;
        }
        let was_first = std::mem::replace(&mut first, false);
        let tokens: Vec<&str> = split(line).take(64).collect();
        if tokens.len() == 1 && tokens[0].parse::<u64>().is_ok() {
            continue; // a PTS point count
        }
        vals.clear();
        let mut bad = None;
        for t in &tokens {
            match t.parse::<f32>() {
                Ok(v) => vals.push(v),
                Err(_) => {
                    bad = Some(*t);
                    break;
                }
            }
        }
        if let Some(t) = bad {
            if was_first {
                continue; // a header line
            }
            return Err(malformed(F, loc(), format!("`{t}` is not a number")));
        }
        if vals.len() < 3 {
            return Err(malformed(
                F,
                loc(),
                format!("a point needs 3 coordinates, this line has {}", vals.len()),
            ));
        }
        let p = Vec3::new(vals[0], vals[1], vals[2]);
        if !p.is_finite() {
            return Err(ReadError::NonFinite {
                format: F,
                location: loc(),
            });
        }
        check_limit(F, "point count", positions.len() as u64 + 1, vmax)?;
        positions.push(p);
        if normals_possible {
            let n = (vals.len() == 6).then(|| Vec3::new(vals[3], vals[4], vals[5]));
            match n {
                Some(n) if (0.9..=1.1).contains(&n.length()) => normals.push(n),
                _ => {
                    normals_possible = false;
                    normals = Vec::new();
                }
            }
        }
    }
    finish(F, positions, normals, Vec::new())
}

/// True when the first lines are numbers (after an optional header line).
pub(super) fn looks_like_points(text: &str) -> bool {
    let mut data_lines = 0;
    let mut lines = text
        .lines()
        .map(str::trim)
        .filter(|l| !is_comment(l))
        .peekable();
    let mut first = true;
    while let Some(line) = lines.next() {
        let is_last = lines.peek().is_none();
        let nums = split(line).filter(|t| t.parse::<f32>().is_ok()).count();
        let all = split(line).count();
        if nums == all && nums >= 3 {
            data_lines += 1;
        } else if nums == all && nums == 1 {
            // count line
        } else if !(first || is_last) {
            return false;
        }
        first = false;
    }
    data_lines > 0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn r(s: &str) -> Mesh {
        read(s.as_bytes(), &Limits::default()).unwrap()
    }

    #[test]
    fn variants() {
        assert_eq!(r("1 2 3\n4 5 6\n").positions.len(), 2);
        let m = r("# c\n1 2 3 0 0 1\n4 5 6 0 1 0\n");
        assert_eq!(m.normals, vec![Vec3::Z, Vec3::Y]);
        let m = r("1 2 3 255 0 0\n");
        assert!(m.normals.is_empty());
        let m = r("2\n1 2 3 10 1 2 3\n4 5 6 10 1 2 3\n");
        assert_eq!(m.positions[1], Vec3::new(4.0, 5.0, 6.0));
        let m = r("x,y,z\n1,2,3\n// c\n4;5;6\n");
        assert_eq!(m.positions.len(), 2);
        assert!(looks_like_points("x,y,z\n1,2,3\n"));
        assert!(!looks_like_points("hello world\nfoo bar\nbaz\n"));
    }
}
