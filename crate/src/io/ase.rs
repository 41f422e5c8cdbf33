//! ASE (`.ase`), the ASCII scene export of 3ds Max, also written by Q3Map2 for Quake III map
//! models (nexuiz, openarena).
//!
//! ```text
//! *3DSMAX_ASCIIEXPORT 200
//! *GEOMOBJECT {
//!     *NODE_NAME "Cone01"
//!     *NODE_TM { ... *TM_POS -68.5 58.9 0.0 }
//!     *MESH {
//!         *MESH_NUMVERTEX 44
//!         *MESH_NUMFACES 84
//!         *MESH_VERTEX_LIST {
//!             *MESH_VERTEX 0 -68.5099 58.8903 0.0000
//!             ...
//!         }
//!         *MESH_FACE_LIST {
//!             *MESH_FACE 0: A: 0 B: 2 C: 1 AB: 0 BC: 1 CA: 0 *MESH_SMOOTHING 1 *MESH_MTLID 1
//!             ...
//!         }
//!     }
//! }
//! ```
//!
//! The file is `*KEYWORD value...` tokens and `{ }` blocks (a block belongs to the keyword
//! before it); quoted strings are single tokens. Every `*GEOMOBJECT`, at the top level or in
//! `*GROUP` blocks (at most [`MAX_DEPTH`] deep), contributes the first `*MESH` block directly
//! inside it; `*MESH_ANIMATION` (later frames), `*NODE_TM` and every other block are skipped.
//! A mesh declares `*MESH_NUMVERTEX` and `*MESH_NUMFACES` before its lists; the vertex list
//! holds `*MESH_VERTEX i x y z` numbered from 0 in order, the face list `*MESH_FACE i: A: a
//! B: b C: c ...` (the colon after `i` is optional, Q3Map2 leaves it out; whatever follows
//! `C:` is ignored). Both lists must hold exactly the declared counts.
//!
//! ASE vertices are already in world space: `*NODE_TM` is the node's placement, which the
//! exporter has applied (in the real files the first vertex of a cone sits at its `*TM_POS`),
//! so it is not applied again. Coordinates are kept as written (3ds Max and Quake are +Z up).
//! Faces wind counter-clockwise as written. All objects are merged into one mesh. Normals
//! (`*MESH_NORMALS`, per face corner in 3ds Max files) are not read: the mesh has none.

use glam::Vec3;

use super::tokens::{Token, Tokens, parse};
use super::{Format, Limits, ReadError, check_limit, finish, malformed, vertex_limit};
use crate::geometry::mesh::Mesh;

const F: Format = Format::Ase;

/// The deepest nesting of `*GROUP` blocks accepted.
pub const MAX_DEPTH: usize = 64;

struct Reader<'a, 'l> {
    t: Tokens<'a>,
    limits: &'l Limits,
    positions: Vec<Vec3>,
    faces: Vec<[u32; 3]>,
}

fn is_keyword(t: &Token) -> bool {
    t.text.first() == Some(&b'*')
}

impl Reader<'_, '_> {
    /// Reads the contents of a block (its `{` already read) up to its `}`, or to the end of
    /// the input for the top level (`depth` 0).
    fn block(&mut self, depth: usize) -> Result<(), ReadError> {
        let mut last: Option<Token> = None;
        loop {
            let Some(tok) = self.t.next() else {
                if depth == 0 {
                    return Ok(());
                }
                return Err(self.t.eof());
            };
            if tok.is("}") {
                if depth == 0 {
                    return Err(malformed(F, tok.loc(), "`}` without a block to close"));
                }
                return Ok(());
            }
            if tok.is("{") {
                match last.map(|k| k.text) {
                    Some(b"*GEOMOBJECT") => self.geomobject()?,
                    Some(b"*GROUP") => {
                        if depth + 1 > MAX_DEPTH {
                            return Err(ReadError::TooLarge {
                                format: F,
                                what: "group nesting depth",
                                value: (depth + 1) as u64,
                                limit: MAX_DEPTH as u64,
                            });
                        }
                        self.block(depth + 1)?;
                    }
                    _ => self.t.skip_block()?,
                }
                last = None;
                continue;
            }
            if is_keyword(&tok) {
                last = Some(tok);
            }
        }
    }

    /// Reads a `*GEOMOBJECT` block (its `{` already read).
    fn geomobject(&mut self) -> Result<(), ReadError> {
        let mut last: Option<Token> = None;
        let mut have_mesh = false;
        loop {
            let tok = self.t.expect_any()?;
            if tok.is("}") {
                return Ok(());
            }
            if tok.is("{") {
                if !have_mesh && last.is_some_and(|k| k.is("*MESH")) {
                    have_mesh = true;
                    self.mesh()?;
                } else {
                    self.t.skip_block()?;
                }
                last = None;
                continue;
            }
            if is_keyword(&tok) {
                last = Some(tok);
            }
        }
    }

    /// Reads a `*MESH` block (its `{` already read).
    fn mesh(&mut self) -> Result<(), ReadError> {
        let base = self.positions.len();
        let mut vertex_count: Option<usize> = None;
        let mut face_count: Option<u64> = None;
        let mut listed_vertices: Option<usize> = None;
        let mut listed_faces: Option<u64> = None;
        let mut last: Option<Token> = None;
        loop {
            let tok = self.t.expect_any()?;
            if tok.is("}") {
                break;
            }
            if tok.is("{") {
                let key = last.take();
                match key.map(|k| k.text) {
                    Some(b"*MESH_VERTEX_LIST") => {
                        let key = key.unwrap();
                        let Some(n) = vertex_count else {
                            return Err(malformed(
                                F,
                                key.loc(),
                                "`*MESH_VERTEX_LIST` before `*MESH_NUMVERTEX`",
                            ));
                        };
                        if listed_vertices.is_some() {
                            return Err(malformed(F, key.loc(), "a second `*MESH_VERTEX_LIST`"));
                        }
                        listed_vertices = Some(self.vertex_list(n)?);
                    }
                    Some(b"*MESH_FACE_LIST") => {
                        let key = key.unwrap();
                        let (Some(nv), Some(nf)) = (vertex_count, face_count) else {
                            return Err(malformed(
                                F,
                                key.loc(),
                                "`*MESH_FACE_LIST` before `*MESH_NUMVERTEX` and `*MESH_NUMFACES`",
                            ));
                        };
                        if listed_faces.is_some() {
                            return Err(malformed(F, key.loc(), "a second `*MESH_FACE_LIST`"));
                        }
                        listed_faces = Some(self.face_list(base, nv, nf)?);
                    }
                    _ => self.t.skip_block()?,
                }
                continue;
            }
            if tok.is("*MESH_NUMVERTEX") {
                if vertex_count.is_some() {
                    return Err(malformed(F, tok.loc(), "a second `*MESH_NUMVERTEX`"));
                }
                let n: u64 = self.t.number("vertex count")?;
                check_limit(
                    F,
                    "vertex count",
                    (base as u64).saturating_add(n),
                    vertex_limit(self.limits),
                )?;
                vertex_count = Some(n as usize);
            } else if tok.is("*MESH_NUMFACES") {
                if face_count.is_some() {
                    return Err(malformed(F, tok.loc(), "a second `*MESH_NUMFACES`"));
                }
                let n: u64 = self.t.number("face count")?;
                check_limit(
                    F,
                    "triangle count",
                    (self.faces.len() as u64).saturating_add(n),
                    self.limits.max_faces as u64,
                )?;
                face_count = Some(n);
            } else if is_keyword(&tok) {
                last = Some(tok);
            }
        }
        // A mesh that declares vertices or faces must list them all.
        let end = self.t.loc_here();
        if let Some(n) = vertex_count.filter(|&n| n > 0)
            && listed_vertices != Some(n)
        {
            return Err(malformed(
                F,
                end.clone(),
                format!(
                    "{} vertices listed, {n} declared",
                    listed_vertices.unwrap_or(0)
                ),
            ));
        }
        if let Some(n) = face_count.filter(|&n| n > 0)
            && listed_faces != Some(n)
        {
            return Err(malformed(
                F,
                end,
                format!("{} faces listed, {n} declared", listed_faces.unwrap_or(0)),
            ));
        }
        Ok(())
    }

    /// Reads a `*MESH_VERTEX_LIST` block of at most `n` vertices; returns how many it held.
    fn vertex_list(&mut self, n: usize) -> Result<usize, ReadError> {
        // Each vertex line takes at least 20 bytes ("*MESH_VERTEX 0 0 0 0").
        self.positions.reserve(n.min(self.t.remaining() / 20));
        let mut k = 0usize;
        loop {
            let tok = self.t.expect_any()?;
            if tok.is("}") {
                return Ok(k);
            }
            if !tok.is("*MESH_VERTEX") {
                return Err(malformed(
                    F,
                    tok.loc(),
                    format!("`{}` in the vertex list", tok.show()),
                ));
            }
            let i: u64 = self.t.number("vertex number")?;
            if i != k as u64 {
                return Err(malformed(
                    F,
                    tok.loc(),
                    format!("vertex {k} is numbered {i}"),
                ));
            }
            if k >= n {
                return Err(malformed(
                    F,
                    tok.loc(),
                    format!("more vertices than the {n} declared"),
                ));
            }
            let x = self.t.coordinate()?;
            let y = self.t.coordinate()?;
            let z = self.t.coordinate()?;
            self.positions.push(Vec3::new(x as f32, y as f32, z as f32));
            k += 1;
        }
    }

    /// Reads a `*MESH_FACE_LIST` block of at most `n` faces over `count` vertices starting at
    /// `base`; returns how many it held.
    fn face_list(&mut self, base: usize, count: usize, n: u64) -> Result<u64, ReadError> {
        self.faces
            .reserve((n as usize).min(self.t.remaining() / 24));
        let mut k = 0u64;
        loop {
            let tok = self.t.expect_any()?;
            if tok.is("}") {
                return Ok(k);
            }
            if tok.is("{") {
                self.t.skip_block()?;
                continue;
            }
            if !tok.is("*MESH_FACE") {
                continue; // AB: 1, *MESH_SMOOTHING 1,2, *MESH_MTLID 0, ...
            }
            if k >= n {
                return Err(malformed(
                    F,
                    tok.loc(),
                    format!("more faces than the {n} declared"),
                ));
            }
            let number = self.t.expect_any()?;
            let digits = number.text.strip_suffix(b":").unwrap_or(number.text);
            let i: u64 = parse(
                F,
                &Token {
                    text: digits,
                    ..number
                },
                "face number",
            )?;
            if i != k {
                return Err(malformed(F, tok.loc(), format!("face {k} is numbered {i}")));
            }
            let mut face = [0u32; 3];
            for (slot, label) in face.iter_mut().zip(["A:", "B:", "C:"]) {
                let t = self.t.expect_any()?;
                // "A: 5", or "A:5" written together.
                let value = if t.is(label) {
                    self.t.expect_any()?
                } else if t.text.starts_with(label.as_bytes()) {
                    Token {
                        text: &t.text[2..],
                        ..t
                    }
                } else {
                    return Err(malformed(
                        F,
                        t.loc(),
                        format!("`{}` where `{label}` was expected", t.show()),
                    ));
                };
                let v: u64 = parse(F, &value, "vertex index")?;
                if v >= count as u64 {
                    return Err(ReadError::IndexOutOfRange {
                        format: F,
                        location: value.loc(),
                        what: "vertices",
                        index: i64::try_from(v).unwrap_or(i64::MAX),
                        count,
                    });
                }
                *slot = (base as u64 + v) as u32;
            }
            self.faces.push(face);
            k += 1;
        }
    }
}

pub(super) fn read(bytes: &[u8], limits: &Limits) -> Result<Mesh, ReadError> {
    let bytes = bytes.strip_prefix("\u{feff}".as_bytes()).unwrap_or(bytes);
    let mut r = Reader {
        t: Tokens::new(F, bytes, b"{}", false),
        limits,
        positions: Vec::new(),
        faces: Vec::new(),
    };
    let Some(first) = r.t.next() else {
        return Err(ReadError::Empty { format: F });
    };
    if !first.is("*3DSMAX_ASCIIEXPORT") {
        return Err(malformed(
            F,
            first.loc(),
            "missing the `*3DSMAX_ASCIIEXPORT` header",
        ));
    }
    r.block(0)?;
    finish(F, r.positions, Vec::new(), r.faces)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn groups_colons_and_animation() {
        let s = "*3DSMAX_ASCIIEXPORT\t200\n*SCENE {\n\t*SCENE_FILENAME \"a { b\"\n}\n*GROUP \"g\" {\n*GEOMOBJECT {\n\t*NODE_TM {\n\t\t*TM_POS 9 9 9\n\t}\n\t*MESH {\n\t\t*MESH_NUMVERTEX 3\n\t\t*MESH_NUMFACES 1\n\t\t*MESH_VERTEX_LIST {\n\t\t\t*MESH_VERTEX 0 0 0 0\n\t\t\t*MESH_VERTEX 1 1 0 0\n\t\t\t*MESH_VERTEX 2 0 1 0\n\t\t}\n\t\t*MESH_FACE_LIST {\n\t\t\t*MESH_FACE 0: A: 0 B: 1 C:2 AB: 1 BC: 1 CA: 1 *MESH_SMOOTHING *MESH_MTLID 0\n\t\t}\n\t}\n\t*MESH_ANIMATION {\n\t\t*MESH {\n\t\t\t*MESH_NUMVERTEX 1\n\t\t}\n\t}\n}\n}\n*GEOMOBJECT {\n\t*MESH {\n\t\t*MESH_NUMVERTEX 3\n\t\t*MESH_NUMFACES 1\n\t\t*MESH_VERTEX_LIST {\n\t\t\t*MESH_VERTEX 0 5 0 0\n\t\t\t*MESH_VERTEX 1 6 0 0\n\t\t\t*MESH_VERTEX 2 5 1 0\n\t\t}\n\t\t*MESH_FACE_LIST {\n\t\t\t*MESH_FACE 0 A: 0 B: 2 C: 1\n\t\t}\n\t}\n}\n";
        let m = read(s.as_bytes(), &Limits::default()).unwrap();
        assert_eq!(m.positions.len(), 6);
        assert_eq!(m.faces, vec![[0, 1, 2], [3, 5, 4]]);
        assert_eq!(m.positions[4], Vec3::new(6.0, 0.0, 0.0));
    }
}
