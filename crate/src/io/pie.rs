//! PIE, the text model format of Warzone 2100 (versions 2, 3 and 4).
//!
//! ```text
//! PIE 3
//! TYPE 10200
//! TEXTURE 0 page-16-droid-drives.png 0 0
//! LEVELS 1
//! LEVEL 1
//! POINTS 4
//!     0 0 0
//!     ...
//! POLYGONS 2
//!     200 3 0 1 2 <texture coordinates>
//!     ...
//! ```
//!
//! Each `LEVEL` (numbered 1, 2, ... up to the `LEVELS` count) has a `POINTS n` block of `n`
//! coordinate triples (integers in PIE 2 files, decimals in later ones) and a `POLYGONS n`
//! block whose polygons are `flags k i0 .. ik-1`, the flags in hexadecimal and the indices
//! 0-based into that level's points. Flag 0x4000 (animated texture) adds 4 numbers after the
//! indices and flag 0x200 (textured) adds `2k` texture coordinates; these are checked to be
//! numbers and skipped. The blocks are read as whitespace-separated numbers, so they may span
//! lines, but a block must end at the end of a line. Polygons are fan-triangulated and all
//! levels are merged into one mesh (each level's indices offset by the points before it).
//!
//! Every other line (`TYPE`, `TEXTURE`, `NORMALMAP`, `CONNECTORS` and its points,
//! `ANIMOBJECT`, `NORMALS`, `SHADOWPOINTS`, `EVENT`, ...) is ignored, so the mesh has no
//! normals.

use glam::Vec3;

use super::{
    Format, Limits, Location, ReadError, check_limit, finish, malformed, push_fan, vertex_limit,
};
use crate::geometry::mesh::Mesh;

const F: Format = Format::Pie;

const FLAG_TEXTURED: u32 = 0x200;
const FLAG_ANIMATED: u32 = 0x4000;

/// Lines of text, read either line by line (keywords) or token by token (blocks of numbers).
struct Text<'a> {
    lines: std::iter::Enumerate<std::str::Lines<'a>>,
    /// The tokens left on the current line.
    rest: std::str::SplitAsciiWhitespace<'a>,
    /// The current line, 1-based (0 before the first).
    line: usize,
    len: u64,
}

impl<'a> Text<'a> {
    fn new(text: &'a str) -> Self {
        Text {
            lines: text.lines().enumerate(),
            rest: "".split_ascii_whitespace(),
            line: 0,
            len: text.len() as u64,
        }
    }

    /// Moves to the next line; false at the end of the text.
    fn advance(&mut self) -> bool {
        match self.lines.next() {
            Some((i, l)) => {
                self.line = i + 1;
                self.rest = l.split_ascii_whitespace();
                true
            }
            None => false,
        }
    }

    fn loc(&self) -> Location {
        Location::Line(self.line)
    }

    /// The next token, on this line or a later one.
    fn token(&mut self) -> Result<&'a str, ReadError> {
        loop {
            if let Some(t) = self.rest.next() {
                return Ok(t);
            }
            if !self.advance() {
                return Err(ReadError::Truncated {
                    format: F,
                    offset: self.len,
                    expected: 1,
                });
            }
        }
    }

    fn number<T: std::str::FromStr>(&mut self, what: &str) -> Result<T, ReadError> {
        let t = self.token()?;
        t.parse()
            .map_err(|_| malformed(F, self.loc(), format!("`{t}` is not a valid {what}")))
    }

    /// A count on a keyword line (the token after the keyword).
    fn count(&mut self, keyword: &str) -> Result<u64, ReadError> {
        let Some(t) = self.rest.next() else {
            return Err(malformed(
                F,
                self.loc(),
                format!("`{keyword}` needs a count"),
            ));
        };
        t.parse()
            .map_err(|_| malformed(F, self.loc(), format!("`{keyword} {t}`: not a count")))
    }

    /// Fails if anything is left on the current line.
    fn line_ends(&mut self, after: &str) -> Result<(), ReadError> {
        match self.rest.next() {
            Some(t) => Err(malformed(
                F,
                self.loc(),
                format!("unexpected `{t}` after {after}"),
            )),
            None => Ok(()),
        }
    }
}

/// The state of the level being read.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Stage {
    /// Before the first `LEVEL`.
    NoLevel,
    /// After `LEVEL`, before `POINTS`.
    Level,
    /// After `POINTS`, before `POLYGONS`.
    Points,
    /// After `POLYGONS`.
    Done,
}

pub(super) fn read(bytes: &[u8], limits: &Limits) -> Result<Mesh, ReadError> {
    let text = super::utf8(F, bytes)?;
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut t = Text::new(text);

    // The header: `PIE <version>` on the first line that is not blank.
    loop {
        if !t.advance() {
            return Err(ReadError::Empty { format: F });
        }
        if let Some(first) = t.rest.next() {
            if first != "PIE" {
                return Err(malformed(F, t.loc(), "missing the `PIE` header"));
            }
            break;
        }
    }
    let version = t.count("PIE")?;
    if !(2..=4).contains(&version) {
        return Err(ReadError::Unsupported {
            format: F,
            what: format!("version {version} (2 to 4 are known)"),
        });
    }

    let max_vertices = vertex_limit(limits);
    let mut positions: Vec<Vec3> = Vec::new();
    let mut faces: Vec<[u32; 3]> = Vec::new();
    let mut corners: Vec<u32> = Vec::new();
    // (declared count, its line)
    let mut levels: Option<(u64, usize)> = None;
    let mut level = 0u64;
    let mut stage = Stage::NoLevel;
    // Where the current level's points start, and how many it has.
    let mut base = 0usize;
    let mut level_points = 0usize;

    while t.advance() {
        let Some(keyword) = t.rest.next() else {
            continue;
        };
        match keyword {
            "LEVELS" => {
                if levels.is_some() {
                    return Err(malformed(F, t.loc(), "a second `LEVELS`"));
                }
                levels = Some((t.count("LEVELS")?, t.line));
                t.line_ends("the level count")?;
            }
            "LEVEL" => {
                let Some((declared, _)) = levels else {
                    return Err(malformed(F, t.loc(), "`LEVEL` before `LEVELS`"));
                };
                let k = t.count("LEVEL")?;
                if k != level + 1 || k > declared {
                    return Err(malformed(
                        F,
                        t.loc(),
                        format!(
                            "`LEVEL {k}` where level {} of {declared} was expected",
                            level + 1
                        ),
                    ));
                }
                if !matches!(stage, Stage::NoLevel | Stage::Done) {
                    return Err(malformed(
                        F,
                        t.loc(),
                        format!("level {level} has no `POLYGONS`"),
                    ));
                }
                t.line_ends("the level number")?;
                level = k;
                stage = Stage::Level;
            }
            "POINTS" => {
                if stage != Stage::Level {
                    return Err(malformed(
                        F,
                        t.loc(),
                        "`POINTS` outside a `LEVEL` or repeated",
                    ));
                }
                let n = t.count("POINTS")?;
                check_limit(
                    F,
                    "vertex count",
                    (positions.len() as u64).saturating_add(n),
                    max_vertices,
                )?;
                t.line_ends("the point count")?;
                base = positions.len();
                level_points = n as usize;
                // Each point takes at least 6 bytes ("0 0 0\n").
                positions.reserve(level_points.min(bytes.len() / 6));
                for _ in 0..n {
                    let mut c = [0f32; 3];
                    for v in &mut c {
                        *v = t.number("coordinate")?;
                    }
                    let p = Vec3::from_array(c);
                    if !p.is_finite() {
                        return Err(ReadError::NonFinite {
                            format: F,
                            location: t.loc(),
                        });
                    }
                    positions.push(p);
                }
                t.line_ends("the last point")?;
                stage = Stage::Points;
            }
            "POLYGONS" => {
                if stage != Stage::Points {
                    return Err(malformed(
                        F,
                        t.loc(),
                        "`POLYGONS` without `POINTS` before it in the level",
                    ));
                }
                let n = t.count("POLYGONS")?;
                // Each polygon is at least one triangle.
                check_limit(F, "polygon count", n, limits.max_faces as u64)?;
                t.line_ends("the polygon count")?;
                for _ in 0..n {
                    let flags_token = t.token()?;
                    let flags = u32::from_str_radix(flags_token, 16).map_err(|_| {
                        malformed(
                            F,
                            t.loc(),
                            format!("`{flags_token}` is not hexadecimal polygon flags"),
                        )
                    })?;
                    let k: u32 = t.number("corner count")?;
                    if k < 3 {
                        return Err(malformed(
                            F,
                            t.loc(),
                            format!("a polygon needs 3 corners, this one has {k}"),
                        ));
                    }
                    corners.clear();
                    for _ in 0..k {
                        let i: u32 = t.number("point index")?;
                        if i as usize >= level_points {
                            return Err(ReadError::IndexOutOfRange {
                                format: F,
                                location: t.loc(),
                                what: "vertices",
                                index: i as i64,
                                count: level_points,
                            });
                        }
                        corners.push((base + i as usize) as u32);
                    }
                    let mut extra = 0u64;
                    if flags & FLAG_ANIMATED != 0 {
                        extra += 4;
                    }
                    if flags & FLAG_TEXTURED != 0 {
                        extra += 2 * k as u64;
                    }
                    for _ in 0..extra {
                        t.number::<f64>("texture number")?;
                    }
                    push_fan(F, &corners, &mut faces, limits)?;
                }
                t.line_ends("the last polygon")?;
                stage = Stage::Done;
            }
            _ => {} // other sections and their data lines
        }
    }
    if let Some((declared, line)) = levels
        && (level != declared || stage != Stage::Done)
    {
        return Err(malformed(
            F,
            Location::Line(line),
            format!("{declared} levels declared, level {level} is the last (complete) one"),
        ));
    }
    finish(F, positions, Vec::new(), faces)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_levels_and_a_quad() {
        let s = "PIE 3\nTYPE 10200\nLEVELS 2\nLEVEL 1\nPOINTS 4\n 0 0 0\n 1 0 0\n 1 1 0\n 0 1 0\nPOLYGONS 1\n 200 4 0 1 2 3 0 0 1 0 1 1 0 1\nLEVEL 2\nPOINTS 3\n0 0 1\n1 0 1\n0 1 1\nPOLYGONS 1\n4200 3 2 1 0 1 1 8 8 0 0 1 0 1 1\nCONNECTORS 1\n 0 0 5\n";
        let m = read(s.as_bytes(), &Limits::default()).unwrap();
        assert_eq!(m.positions.len(), 7);
        assert_eq!(m.faces, vec![[0, 1, 2], [0, 2, 3], [6, 5, 4]]);
    }
}
