//! AC3D (`.ac`), the text model format of the AC3D modeller, used by FlightGear.
//!
//! ```text
//! AC3Db
//! MATERIAL "grey" rgb 0.5 0.5 0.5  amb 0.2 0.2 0.2  emis 0 0 0  spec 0 0 0  shi 10  trans 0
//! OBJECT world
//! kids 1
//! OBJECT poly
//! name "box"
//! loc 1 0 0
//! numvert 4
//! 0 0 0
//! ...
//! numsurf 1
//! SURF 0x10
//! mat 0
//! refs 4
//! 0 0 0
//! 1 1 0
//! ...
//! kids 0
//! ```
//!
//! The file starts with an `AC3D` line whose next character is the version (`b` is known;
//! anything after it, as in `AC3DbS`, is ignored). `MATERIAL` lines are skipped. An `OBJECT`
//! block is a list of keyword lines ended by `kids n`, after which its `n` child objects
//! follow. Of an object's lines, `rot` (a 3x3 matrix, row by row), `loc` (x y z), `numvert n`
//! (then `n` lines of x y z; anything after the three numbers is ignored) and `numsurf n`
//! (then `n` surfaces) are read; `data n` is followed by `n` bytes of free text, which may
//! span lines, and is skipped with the rest of the line it ends on; every other line (`name`, `texture`, `texrep`, `texoff`,
//! `crease`, `url`, `hidden`, ...) is ignored. A surface is `SURF <hex flags>`, an optional
//! `mat k` and `refs m` followed by `m` lines `index u v`; the surface type is `flags & 0xF`:
//! 0 is a polygon (fan-triangulated when it has 3 corners or more), 1 and 2 are closed and open
//! lines (skipped). Indices are 0-based into the object's own vertices.
//!
//! An object's vertices are transformed by its `rot` then `loc`, composed with those of its
//! parents (a child is placed relative to its parent), and all objects are merged into one
//! mesh. Objects may nest at most [`MAX_DEPTH`] deep (deeper is `TooLarge`). Lines are read as
//! UTF-8 with invalid bytes replaced (names in old files are often Latin-1), so
//! `InvalidUtf8` is never returned. The mesh has no normals.

use glam::{DMat3, DVec3, Vec3};

use super::{
    Format, Limits, Location, ReadError, check_limit, finish, malformed, push_fan, vertex_limit,
};
use crate::geometry::mesh::Mesh;

const F: Format = Format::Ac3d;

/// The deepest nesting of `OBJECT`s accepted (the top-level object is depth 1).
pub const MAX_DEPTH: usize = 64;

/// The input as lines, with a byte position so that `data` blocks can be skipped by length.
struct Lines<'a> {
    bytes: &'a [u8],
    pos: usize,
    /// The 1-based number of the line last returned (0 before the first).
    line: usize,
}

impl<'a> Lines<'a> {
    fn loc(&self) -> Location {
        Location::Line(self.line)
    }

    fn eof(&self) -> ReadError {
        ReadError::Truncated {
            format: F,
            offset: self.bytes.len() as u64,
            expected: 1,
        }
    }

    /// The next line, without its line end; `None` at the end of the input.
    fn next_line(&mut self) -> Option<std::borrow::Cow<'a, str>> {
        if self.pos >= self.bytes.len() {
            return None;
        }
        let rest = &self.bytes[self.pos..];
        let (line, used) = match rest.iter().position(|&b| b == b'\n') {
            Some(i) => (&rest[..i], i + 1),
            None => (rest, rest.len()),
        };
        self.pos += used;
        self.line += 1;
        let line = line.strip_suffix(b"\r").unwrap_or(line);
        Some(String::from_utf8_lossy(line))
    }

    /// The next line that is not blank, split into tokens; `Truncated` at the end.
    fn tokens(&mut self) -> Result<Vec<String>, ReadError> {
        loop {
            let Some(l) = self.next_line() else {
                return Err(self.eof());
            };
            let t: Vec<String> = l.split_ascii_whitespace().map(str::to_owned).collect();
            if !t.is_empty() {
                return Ok(t);
            }
        }
    }

    /// Skips the `n` bytes of a `data` block, then the rest of the line they end on.
    fn skip_data(&mut self, n: u64) -> Result<(), ReadError> {
        let left = (self.bytes.len() - self.pos) as u64;
        if n > left {
            return Err(ReadError::Truncated {
                format: F,
                offset: self.bytes.len() as u64,
                expected: n - left,
            });
        }
        let end = self.pos + n as usize;
        self.line += self.bytes[self.pos..end]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        self.pos = end;
        if n == 0 || self.bytes[end - 1] == b'\n' {
            return Ok(()); // nothing to skip, or the count included the line end
        }
        // Skip the rest of the line: some writers count the text short (`data 7` followed
        // by a 10-character name in FlightGear's liferaft models), and the text ends with
        // its line whatever the count says.
        self.next_line();
        Ok(())
    }
}

fn number<T: std::str::FromStr>(
    tokens: &[String],
    i: usize,
    what: &str,
    at: Location,
) -> Result<T, ReadError> {
    let Some(t) = tokens.get(i) else {
        return Err(malformed(F, at, format!("missing {what}")));
    };
    t.parse()
        .map_err(|_| malformed(F, at, format!("`{t}` is not a valid {what}")))
}

/// Three finite numbers from `tokens[first..]`.
fn vec3(tokens: &[String], first: usize, at: Location) -> Result<DVec3, ReadError> {
    let mut c = [0f64; 3];
    for (k, v) in c.iter_mut().enumerate() {
        *v = number(tokens, first + k, "coordinate", at.clone())?;
    }
    let v = DVec3::from_array(c);
    if !v.is_finite() || !v.as_vec3().is_finite() {
        return Err(ReadError::NonFinite {
            format: F,
            location: at,
        });
    }
    Ok(v)
}

struct Reader<'a, 'l> {
    lines: Lines<'a>,
    limits: &'l Limits,
    positions: Vec<Vec3>,
    faces: Vec<[u32; 3]>,
    corners: Vec<u32>,
}

impl Reader<'_, '_> {
    /// Reads one `OBJECT` block (its first line already read) and its children, placing its
    /// vertices with the parent's transform `(m, t)`.
    fn object(&mut self, depth: usize, m: DMat3, t: DVec3) -> Result<(), ReadError> {
        if depth > MAX_DEPTH {
            return Err(ReadError::TooLarge {
                format: F,
                what: "object nesting depth",
                value: depth as u64,
                limit: MAX_DEPTH as u64,
            });
        }
        let mut rot = DMat3::IDENTITY;
        let mut loc = DVec3::ZERO;
        // This object's vertices, in its own coordinates until `kids`.
        let base = self.positions.len();
        let mut local: Vec<DVec3> = Vec::new();
        let mut have_vertices = false;
        loop {
            let tok = self.lines.tokens()?;
            let at = self.lines.loc();
            match tok[0].as_str() {
                "rot" => {
                    let mut r = [0f64; 9];
                    for (k, v) in r.iter_mut().enumerate() {
                        *v = number(&tok, 1 + k, "rotation entry", at.clone())?;
                        if !v.is_finite() {
                            return Err(ReadError::NonFinite {
                                format: F,
                                location: at,
                            });
                        }
                    }
                    // Given row by row; glam matrices are built from columns.
                    rot = DMat3::from_cols_array(&r).transpose();
                }
                "loc" => loc = vec3(&tok, 1, at)?,
                "data" => {
                    let n: u64 = number(&tok, 1, "data length", at)?;
                    self.lines.skip_data(n)?;
                }
                "numvert" => {
                    if have_vertices {
                        return Err(malformed(F, at, "a second `numvert` in the object"));
                    }
                    have_vertices = true;
                    let n: u64 = number(&tok, 1, "vertex count", at)?;
                    check_limit(
                        F,
                        "vertex count",
                        (base as u64).saturating_add(n),
                        vertex_limit(self.limits),
                    )?;
                    // Each vertex line takes at least 6 bytes ("0 0 0\n").
                    let left = self.lines.bytes.len() - self.lines.pos;
                    local.reserve((n as usize).min(left / 6));
                    for _ in 0..n {
                        let v = self.lines.tokens()?;
                        local.push(vec3(&v, 0, self.lines.loc())?);
                    }
                }
                "numsurf" => {
                    let n: u64 = number(&tok, 1, "surface count", at)?;
                    for _ in 0..n {
                        self.surface(base, local.len())?;
                    }
                }
                "kids" => {
                    let kids: u64 = number(&tok, 1, "child count", at)?;
                    // A child point p lands at m (rot p + loc) + t.
                    let t = m * loc + t;
                    let m = m * rot;
                    for p in &local {
                        let w = (m * *p + t).as_vec3();
                        if !w.is_finite() {
                            return Err(ReadError::NonFinite {
                                format: F,
                                location: self.lines.loc(),
                            });
                        }
                        self.positions.push(w);
                    }
                    drop(local);
                    for _ in 0..kids {
                        let tok = self.lines.tokens()?;
                        if tok[0] != "OBJECT" {
                            return Err(malformed(
                                F,
                                self.lines.loc(),
                                format!("`{}` where a child `OBJECT` was expected", tok[0]),
                            ));
                        }
                        self.object(depth + 1, m, t)?;
                    }
                    return Ok(());
                }
                "OBJECT" | "SURF" | "refs" | "MATERIAL" => {
                    return Err(malformed(
                        F,
                        at,
                        format!("unexpected `{}` (the object has no `kids` line)", tok[0]),
                    ));
                }
                _ => {} // name, texture, texrep, texoff, crease, url, hidden, ...
            }
        }
    }

    /// Reads one `SURF` block; `base` is where the object's vertices start in the mesh and
    /// `count` how many it has.
    fn surface(&mut self, base: usize, count: usize) -> Result<(), ReadError> {
        let tok = self.lines.tokens()?;
        let at = self.lines.loc();
        if tok[0] != "SURF" {
            return Err(malformed(
                F,
                at,
                format!("`{}` where `SURF` was expected", tok[0]),
            ));
        }
        let Some(flags_token) = tok.get(1) else {
            return Err(malformed(F, at, "`SURF` needs flags"));
        };
        let hex = flags_token
            .strip_prefix("0x")
            .or_else(|| flags_token.strip_prefix("0X"))
            .unwrap_or(flags_token);
        let flags = u32::from_str_radix(hex, 16).map_err(|_| {
            malformed(
                F,
                at.clone(),
                format!("`{flags_token}` is not hexadecimal surface flags"),
            )
        })?;
        let kind = flags & 0xF;
        if kind > 2 {
            return Err(malformed(F, at, format!("unknown surface type {kind}")));
        }
        let refs: u64 = loop {
            let tok = self.lines.tokens()?;
            let at = self.lines.loc();
            match tok[0].as_str() {
                "mat" => {
                    number::<u64>(&tok, 1, "material index", at)?;
                }
                "refs" => break number(&tok, 1, "corner count", at)?,
                other => {
                    return Err(malformed(
                        F,
                        at,
                        format!("`{other}` where `mat` or `refs` was expected"),
                    ));
                }
            }
        };
        self.corners.clear();
        for _ in 0..refs {
            let tok = self.lines.tokens()?;
            let at = self.lines.loc();
            let i: u32 = number(&tok, 0, "vertex index", at.clone())?;
            for k in 1..3 {
                number::<f64>(&tok, k, "texture coordinate", at.clone())?;
            }
            if i as usize >= count {
                return Err(ReadError::IndexOutOfRange {
                    format: F,
                    location: at,
                    what: "vertices",
                    index: i as i64,
                    count,
                });
            }
            if kind == 0 {
                self.corners.push((base + i as usize) as u32);
            }
        }
        let corners = std::mem::take(&mut self.corners);
        let r = push_fan(F, &corners, &mut self.faces, self.limits);
        self.corners = corners;
        r
    }
}

pub(super) fn read(bytes: &[u8], limits: &Limits) -> Result<Mesh, ReadError> {
    let bytes = bytes.strip_prefix("\u{feff}".as_bytes()).unwrap_or(bytes);
    let mut r = Reader {
        lines: Lines {
            bytes,
            pos: 0,
            line: 0,
        },
        limits,
        positions: Vec::new(),
        faces: Vec::new(),
        corners: Vec::new(),
    };
    let Some(header) = r.lines.next_line() else {
        return Err(ReadError::Empty { format: F });
    };
    let header = header.trim();
    let Some(version) = header.strip_prefix("AC3D") else {
        return Err(malformed(F, Location::Line(1), "missing the `AC3D` header"));
    };
    if !version.starts_with('b') {
        return Err(ReadError::Unsupported {
            format: F,
            what: format!("version `{version}` (`b` is known)"),
        });
    }
    while let Some(l) = r.lines.next_line() {
        let mut tok = l.split_ascii_whitespace();
        match tok.next() {
            None | Some("MATERIAL") => {}
            Some("OBJECT") => r.object(1, DMat3::IDENTITY, DVec3::ZERO)?,
            Some(other) => {
                return Err(malformed(
                    F,
                    r.lines.loc(),
                    format!("unexpected `{other}` outside an object"),
                ));
            }
        }
    }
    finish(F, r.positions, Vec::new(), r.faces)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nested_objects_are_placed() {
        let s = "AC3Db\nMATERIAL \"m\" rgb 1 1 1\nOBJECT world\nkids 1\nOBJECT group\nloc 10 0 0\nrot 0 -1 0 1 0 0 0 0 1\nkids 1\nOBJECT poly\nname \"a\"\ndata 5\nab\ncd\nloc 0 1 0\nnumvert 4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\nnumsurf 2\nSURF 0x10\nmat 0\nrefs 4\n0 0 0\n1 1 0\n2 1 1\n3 0 1\nSURF 0x2\nrefs 2\n0 0 0\n1 0 0\nkids 0\n";
        let m = read(s.as_bytes(), &Limits::default()).unwrap();
        assert_eq!(m.faces, vec![[0, 1, 2], [0, 2, 3]]);
        // rot maps (x, y) to (-y, x): the child's loc (0, 1) becomes (-1, 0), plus (10, 0).
        assert_eq!(m.positions[0], Vec3::new(9.0, 0.0, 0.0));
        assert_eq!(m.positions[1], Vec3::new(9.0, 1.0, 0.0));
    }
}
