//! PMD, the mesh format of 0 A.D. (little-endian binary).
//!
//! Layout: `PSMD`, u32 version, u32 size of the data that follows; u32 vertex count; from
//! version 4 a u32 UV-set count (before that one set); per vertex a position (f32x3), a normal
//! (f32x3), 8 bytes per UV set and 20 bytes of bone weights; then a u32 face count and three
//! u16 vertex indices per face. What follows the faces (bones, prop points) is ignored, as are
//! the UV sets and bone weights.
//!
//! Versions 1 to 4 are accepted with this layout; every file of the 0 A.D. 0.0.26 data is
//! version 4. The declared data size must fit in the file; bytes past it are ignored. The
//! per-vertex normals are kept (see the module rules on normals).
//!
//! 0 A.D. winds its triangles clockwise around the stored normals (199 of 200 files sampled
//! from the 0.0.26 data); each triangle is reversed so that, as everywhere in meshflow, faces
//! wind counter-clockwise seen from the side their normal points to.

use super::{
    Cursor, Format, Limits, ReadError, bad_vertex_index, check_limit, finish, vertex_limit,
};
use crate::geometry::mesh::Mesh;

const F: Format = Format::Pmd;

/// Bytes of a vertex besides its UV sets: position, normal, bone weights.
const VERTEX_FIXED: u64 = 12 + 12 + 20;

pub(super) fn read(bytes: &[u8], limits: &Limits) -> Result<Mesh, ReadError> {
    let mut c = Cursor::new(F, bytes);
    if c.take(4)? != b"PSMD" {
        return Err(super::malformed(
            F,
            super::Location::Byte(0),
            "missing the `PSMD` magic",
        ));
    }
    let version = c.u32()?;
    if !(1..=4).contains(&version) {
        return Err(ReadError::Unsupported {
            format: F,
            what: format!("version {version} (1 to 4 are known)"),
        });
    }
    let data_size = c.u32()? as u64;
    c.need(data_size)?;
    // Read only the declared data.
    let mut c = Cursor::new(F, &bytes[..(12 + data_size) as usize]);
    c.skip(12)?;

    let vertex_count = c.u32()? as u64;
    check_limit(F, "vertex count", vertex_count, vertex_limit(limits))?;
    let uv_sets = if version >= 4 { c.u32()? as u64 } else { 1 };
    let stride = VERTEX_FIXED.saturating_add(uv_sets.saturating_mul(8));
    c.need(vertex_count.saturating_mul(stride))?;

    let n = vertex_count as usize;
    let mut positions = Vec::with_capacity(n);
    let mut normals = Vec::with_capacity(n);
    for _ in 0..n {
        positions.push(c.finite_vec3()?);
        normals.push(c.vec3()?);
        c.skip(stride - 24)?;
    }

    let face_count = c.u32()? as u64;
    check_limit(F, "triangle count", face_count, limits.max_faces as u64)?;
    c.need(face_count * 6)?;
    let mut faces = Vec::with_capacity(face_count as usize);
    for _ in 0..face_count {
        let mut f = [0u32; 3];
        for slot in &mut f {
            let at = c.pos();
            let i = c.u16()? as u32;
            if i as usize >= n {
                return Err(bad_vertex_index(F, at, i, n));
            }
            *slot = i;
        }
        faces.push([f[0], f[2], f[1]]);
    }
    finish(F, positions, normals, faces)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A version-4 PMD with one UV set: a triangle.
    fn tri() -> Vec<u8> {
        let mut b = b"PSMD".to_vec();
        b.extend(4u32.to_le_bytes());
        b.extend(0u32.to_le_bytes()); // size, patched below
        b.extend(3u32.to_le_bytes());
        b.extend(1u32.to_le_bytes());
        for p in [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.]] {
            for x in p.into_iter().chain([0., 0., 1.]).chain([0.5, 0.5]) {
                b.extend(x.to_le_bytes());
            }
            b.extend([0u8; 20]);
        }
        b.extend(1u32.to_le_bytes());
        for i in [0u16, 1, 2] {
            b.extend(i.to_le_bytes());
        }
        let size = (b.len() - 12) as u32;
        b[8..12].copy_from_slice(&size.to_le_bytes());
        b
    }

    #[test]
    fn reads_a_triangle_with_normals() {
        let m = read(&tri(), &Limits::default()).unwrap();
        assert_eq!(m.positions.len(), 3);
        assert_eq!(m.normals.len(), 3);
        assert_eq!(m.faces, vec![[0, 2, 1]]);
    }
}
