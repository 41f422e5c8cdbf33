//! STL, binary and ASCII.
//!
//! Binary or ASCII is decided by size: a file whose length is exactly `84 + 50 * count` (the
//! count at byte 80) is binary even when its header starts with `solid`; otherwise a file
//! starting with `solid` is ASCII, and anything else is binary (then cut short if smaller
//! than the count says; bytes after the last triangle are ignored).
//!
//! STL stores each triangle's corners separately; corners with bit-identical coordinates
//! are merged into one vertex so the mesh is indexed (nothing else is welded). Facet
//! normals are not kept: the mesh has no per-vertex normals.

use std::collections::HashMap;

use glam::Vec3;

use super::{Format, Limits, Location, ReadError, check_limit, finish, malformed, vertex_limit};
use crate::geometry::mesh::Mesh;

const F: Format = Format::Stl;

fn declared_count(bytes: &[u8]) -> Option<u64> {
    let c = bytes.get(80..84)?;
    Some(u32::from_le_bytes([c[0], c[1], c[2], c[3]]) as u64)
}

/// True when `bytes` is exactly the size a binary STL with its declared count has.
pub(super) fn binary_size_matches(bytes: &[u8]) -> bool {
    declared_count(bytes).is_some_and(|n| n * 50 + 84 == bytes.len() as u64)
}

pub(super) fn read(bytes: &[u8], limits: &Limits) -> Result<Mesh, ReadError> {
    if binary_size_matches(bytes) {
        return read_binary(bytes, limits);
    }
    let start = bytes
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(bytes.len());
    if bytes[start..].starts_with(b"solid") {
        read_ascii(bytes, limits)
    } else {
        read_binary(bytes, limits)
    }
}

/// Merges bit-identical corners.
struct Welder {
    map: HashMap<[u32; 3], u32>,
    positions: Vec<Vec3>,
    faces: Vec<[u32; 3]>,
    max_vertices: u64,
}

impl Welder {
    fn new(limits: &Limits, triangles_hint: usize) -> Self {
        Welder {
            map: HashMap::with_capacity(triangles_hint.min(1 << 20)),
            positions: Vec::with_capacity(triangles_hint.min(1 << 20)),
            faces: Vec::with_capacity(triangles_hint),
            max_vertices: vertex_limit(limits),
        }
    }

    fn vertex(&mut self, p: Vec3) -> Result<u32, ReadError> {
        let key = p.to_array().map(f32::to_bits);
        if let Some(&i) = self.map.get(&key) {
            return Ok(i);
        }
        let i = self.positions.len() as u64;
        check_limit(F, "vertex count", i + 1, self.max_vertices)?;
        self.positions.push(p);
        self.map.insert(key, i as u32);
        Ok(i as u32)
    }

    fn finish(self) -> Result<Mesh, ReadError> {
        finish(F, self.positions, Vec::new(), self.faces)
    }
}

fn read_binary(bytes: &[u8], limits: &Limits) -> Result<Mesh, ReadError> {
    let Some(count) = declared_count(bytes) else {
        return Err(ReadError::Truncated {
            format: F,
            offset: bytes.len() as u64,
            expected: 84 - bytes.len() as u64,
        });
    };
    let need = count * 50 + 84; // count < 2^32: no overflow in u64
    if need > bytes.len() as u64 {
        return Err(ReadError::Truncated {
            format: F,
            offset: bytes.len() as u64,
            expected: need - bytes.len() as u64,
        });
    }
    check_limit(F, "triangle count", count, limits.max_faces as u64)?;
    if count == 0 {
        return Err(ReadError::Empty { format: F });
    }
    let mut w = Welder::new(limits, count as usize);
    for (t, rec) in bytes[84..need as usize].chunks_exact(50).enumerate() {
        let mut face = [0u32; 3];
        for (k, slot) in face.iter_mut().enumerate() {
            let o = 12 + 12 * k;
            let c = |j: usize| {
                let b = &rec[o + 4 * j..o + 4 * j + 4];
                f32::from_le_bytes([b[0], b[1], b[2], b[3]])
            };
            let p = Vec3::new(c(0), c(1), c(2));
            if !p.is_finite() {
                return Err(ReadError::NonFinite {
                    format: F,
                    location: Location::Byte((84 + 50 * t + o) as u64),
                });
            }
            *slot = w.vertex(p)?;
        }
        w.faces.push(face);
    }
    w.finish()
}

fn read_ascii(bytes: &[u8], limits: &Limits) -> Result<Mesh, ReadError> {
    let text = super::utf8(F, bytes)?;
    let mut w = Welder::new(limits, 0);
    let mut loop_corners: Vec<u32> = Vec::new();
    let mut in_loop = false;
    let mut loop_line = 0;
    for (i, line) in text.lines().enumerate() {
        let line_no = i + 1;
        let loc = || Location::Line(line_no);
        let mut t = line.split_ascii_whitespace();
        match t.next() {
            Some("vertex") => {
                if !in_loop {
                    return Err(malformed(F, loc(), "`vertex` outside `outer loop`"));
                }
                let mut c = [0f32; 3];
                for v in &mut c {
                    let tok = t
                        .next()
                        .ok_or_else(|| malformed(F, loc(), "`vertex` needs 3 coordinates"))?;
                    *v = tok
                        .parse()
                        .map_err(|_| malformed(F, loc(), format!("`{tok}` is not a number")))?;
                }
                let p = Vec3::from_array(c);
                if !p.is_finite() {
                    return Err(ReadError::NonFinite {
                        format: F,
                        location: loc(),
                    });
                }
                let i = w.vertex(p)?;
                loop_corners.push(i);
            }
            Some("outer") => {
                if in_loop {
                    return Err(malformed(F, loc(), "nested `outer loop`"));
                }
                in_loop = true;
                loop_line = line_no;
                loop_corners.clear();
            }
            Some("endloop") => {
                if !in_loop {
                    return Err(malformed(F, loc(), "`endloop` without `outer loop`"));
                }
                in_loop = false;
                if loop_corners.len() < 3 {
                    return Err(malformed(
                        F,
                        Location::Line(loop_line),
                        format!(
                            "a facet needs 3 vertices, this one has {}",
                            loop_corners.len()
                        ),
                    ));
                }
                super::push_fan(F, &loop_corners, &mut w.faces, limits)?;
            }
            Some("solid" | "facet" | "endfacet" | "endsolid") | None => {}
            Some(other) => {
                return Err(malformed(F, loc(), format!("unexpected `{other}`")));
            }
        }
    }
    if in_loop {
        return Err(malformed(
            F,
            Location::Line(loop_line),
            "`outer loop` is never closed",
        ));
    }
    w.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ascii_merges_identical_corners() {
        let s = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
        let m = read(s.as_bytes(), &Limits::default()).unwrap();
        assert_eq!(m.positions.len(), 4);
        assert_eq!(m.faces, vec![[0, 1, 2], [1, 3, 2]]);
    }
}
