//! MD2, the Quake II model format (little-endian binary); only the first frame is read.
//!
//! Header: `IDP2`, then 16 i32: version (8), skin width and height, frame size, and the counts
//! of skins, vertices, texture coordinates, triangles, GL commands and frames, then the offsets
//! of the skins, texture coordinates, triangles, frames, GL commands and the end of the file.
//! A triangle is 6 u16: three vertex indices (kept) and three texture-coordinate indices
//! (ignored). A frame is a scale (f32x3), a translation (f32x3), a 16-byte name, then per vertex
//! three u8 packed coordinates and a normal index; position = byte * scale + translation.
//!
//! Normals are not read: MD2 stores an index into a fixed table of 162 directions that is not
//! part of the file, so the mesh has no normals (recompute them with [`crate::geometry::normals`]).
//! Triangles are stored clockwise seen from outside (838 of the 857 closed-or-not models of
//! ufoai-data 2.5 enclose a negative signed volume); each is reversed so that faces wind
//! counter-clockwise, as everywhere in meshflow.
//! Counts and offsets are checked against the file: negative ones are `Malformed`, counts over
//! the [`Limits`] are `TooLarge`, and a region (or the declared end) past the end of the file is
//! `Truncated`.

use glam::Vec3;

use super::{
    Cursor, Format, Limits, Location, ReadError, bad_vertex_index, check_limit, finish, malformed,
    vertex_limit,
};
use crate::geometry::mesh::Mesh;

const F: Format = Format::Md2;
const HEADER: u64 = 68;

pub(super) fn read(bytes: &[u8], limits: &Limits) -> Result<Mesh, ReadError> {
    let mut c = Cursor::new(F, bytes);
    if c.take(4)? != b"IDP2" {
        return Err(malformed(F, Location::Byte(0), "missing the `IDP2` magic"));
    }
    let mut h = [0i64; 16];
    for v in &mut h {
        *v = c.i32()? as i64;
    }
    let version = h[0];
    if version != 8 {
        return Err(ReadError::Unsupported {
            format: F,
            what: format!("version {version} (8 is known)"),
        });
    }
    // Header field `k` (0 = version) is at byte 4 + 4k.
    let field = |k: usize, what: &str| -> Result<u64, ReadError> {
        u64::try_from(h[k]).map_err(|_| {
            malformed(
                F,
                Location::Byte(4 + 4 * k as u64),
                format!("negative {what} ({})", h[k]),
            )
        })
    };
    let frame_size = field(3, "frame size")?;
    let vertex_count = field(5, "vertex count")?;
    let triangle_count = field(7, "triangle count")?;
    let frame_count = field(9, "frame count")?;
    let triangles_at = field(12, "triangle offset")?;
    let frames_at = field(13, "frame offset")?;
    let end = field(15, "end offset")?;

    check_limit(F, "vertex count", vertex_count, vertex_limit(limits))?;
    check_limit(F, "triangle count", triangle_count, limits.max_faces as u64)?;
    if end > bytes.len() as u64 {
        return Err(ReadError::Truncated {
            format: F,
            offset: bytes.len() as u64,
            expected: end - bytes.len() as u64,
        });
    }
    if vertex_count == 0 {
        return Err(ReadError::Empty { format: F });
    }
    if frame_count == 0 {
        return Err(malformed(F, Location::Byte(40), "the model has no frames"));
    }
    let frame_bytes = 40 + 4 * vertex_count;
    if frame_size < frame_bytes {
        return Err(malformed(
            F,
            Location::Byte(16),
            format!(
                "frame size {frame_size} is less than the {frame_bytes} bytes of {vertex_count} vertices"
            ),
        ));
    }
    // Both regions must lie after the header and inside the file.
    let region = |at: u64, len: u64, at_field: u64| -> Result<Cursor<'_>, ReadError> {
        if at < HEADER {
            return Err(malformed(
                F,
                Location::Byte(at_field),
                format!("offset {at} points into the header"),
            ));
        }
        let mut c = Cursor::new(F, bytes);
        c.skip(at)?;
        c.need(len)?;
        Ok(c)
    };

    let mut fc = region(frames_at, frame_bytes, 56)?;
    let scale = fc.finite_vec3()?;
    let translate = fc.finite_vec3()?;
    fc.skip(16)?;
    let n = vertex_count as usize;
    let mut positions = Vec::with_capacity(n);
    for _ in 0..n {
        let at = fc.pos();
        let q = fc.take(4)?;
        let p = Vec3::new(q[0] as f32, q[1] as f32, q[2] as f32) * scale + translate;
        if !p.is_finite() {
            return Err(ReadError::NonFinite {
                format: F,
                location: Location::Byte(at),
            });
        }
        positions.push(p);
    }

    let mut tc = region(triangles_at, triangle_count * 12, 52)?;
    let mut faces = Vec::with_capacity(triangle_count as usize);
    for _ in 0..triangle_count {
        let mut f = [0u32; 3];
        for slot in &mut f {
            let at = tc.pos();
            let i = tc.u16()? as u32;
            if i as usize >= n {
                return Err(bad_vertex_index(F, at, i, n));
            }
            *slot = i;
        }
        tc.skip(6)?;
        faces.push([f[0], f[2], f[1]]);
    }
    finish(F, positions, Vec::new(), faces)
}
