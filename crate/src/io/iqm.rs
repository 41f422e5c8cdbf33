//! IQM, the Inter-Quake Model format (little-endian binary, version 2), as used by Red
//! Eclipse; the bind pose is read.
//!
//! Header (124 bytes): the magic `INTERQUAKEMODEL\0`, then 27 u32: version (2), file size,
//! flags, text count and offset, mesh count and offset, vertex-array count, vertex count,
//! vertex-array offset, triangle count and offset, adjacency offset, then the counts and
//! offsets of joints, poses, animations, frames (count, channel count, offset), bounds,
//! comments and extensions. A vertex array (20 bytes) is u32 type, flags, format, size
//! (components per vertex) and offset; type 0 is the position, type 2 the normal; the
//! formats are i8, u8, i16, u16, i32, u32, f16, f32 and f64 (0 to 8). A triangle is three
//! u32 vertex indices into the whole vertex list; a mesh (24 bytes) is u32 name, material,
//! first vertex, vertex count, first triangle and triangle count.
//!
//! The vertex arrays hold the bind pose, so positions are read as stored (Red Eclipse models
//! are +Z up); joints, poses and animations are ignored. All meshes' triangles are merged;
//! they are stored clockwise seen from outside (as the engines that load IQM cull), so each is
//! reversed to wind counter-clockwise, as everywhere in meshflow. Normals are kept when the
//! file has an f32 normal array of 3 components. A file without meshes (an animation-only
//! `.iqm`) is `Empty`.
//!
//! Counts and offsets are checked against the file: an array, the triangles or the meshes
//! past its end (or the header's file size larger than the data) are `Truncated`; a region
//! that overlaps the header, a mesh whose ranges leave the vertex or triangle lists, or an
//! unknown array format are `Malformed`; counts over the [`Limits`] are `TooLarge`.

use glam::Vec3;

use super::{
    Cursor, Format, Limits, Location, ReadError, bad_vertex_index, check_limit, finish, malformed,
    vertex_limit,
};
use crate::geometry::mesh::Mesh;

const F: Format = Format::Iqm;
const MAGIC: &[u8; 16] = b"INTERQUAKEMODEL\0";
const HEADER: u64 = 124;
const POSITION: u32 = 0;
const NORMAL: u32 = 2;
const FLOAT: u32 = 7;

/// `Truncated` unless `n` bytes from `start` lie inside a file of `len` bytes.
fn at_least(len: u64, start: u64, n: u64) -> Result<(), ReadError> {
    let end = start.saturating_add(n);
    if end > len {
        return Err(ReadError::Truncated {
            format: F,
            offset: len,
            expected: end - len,
        });
    }
    Ok(())
}

/// A cursor at `ofs` over `n` bytes that must follow the header and lie inside the file;
/// `field` is the offset of the header field that gave `ofs`.
fn region(bytes: &[u8], ofs: u64, n: u64, field: u64) -> Result<Cursor<'_>, ReadError> {
    if ofs < HEADER {
        return Err(malformed(
            F,
            Location::Byte(field),
            format!("offset {ofs} points into the header"),
        ));
    }
    at_least(bytes.len() as u64, ofs, n)?;
    let mut c = Cursor::new(F, bytes);
    c.skip(ofs)?;
    Ok(c)
}

/// The size in bytes of a component of format `f`.
fn component_size(f: u32) -> Option<u64> {
    Some(match f {
        0 | 1 => 1,
        2 | 3 | 6 => 2,
        4 | 5 | 7 => 4,
        8 => 8,
        _ => return None,
    })
}

/// An IEEE half-precision float.
fn half(h: u16) -> f32 {
    let sign = if h & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exp = ((h >> 10) & 0x1f) as i32;
    let frac = (h & 0x3ff) as f32;
    match exp {
        0 => sign * frac * (2f32).powi(-24),
        31 if frac == 0.0 => sign * f32::INFINITY,
        31 => f32::NAN,
        _ => sign * (1.0 + frac / 1024.0) * (2f32).powi(exp - 15),
    }
}

/// One component of format `f` (known to be valid) as an `f64`.
fn component(c: &mut Cursor, f: u32) -> Result<f64, ReadError> {
    Ok(match f {
        0 => c.u8()? as i8 as f64,
        1 => c.u8()? as f64,
        2 => c.u16()? as i16 as f64,
        3 => c.u16()? as f64,
        4 => c.i32()? as f64,
        5 => c.u32()? as f64,
        6 => half(c.u16()?) as f64,
        7 => c.f32()? as f64,
        _ => f64::from_le_bytes(c.take(8)?.try_into().expect("8 bytes")),
    })
}

pub(super) fn read(bytes: &[u8], limits: &Limits) -> Result<Mesh, ReadError> {
    let len = bytes.len() as u64;
    let mut c = Cursor::new(F, bytes);
    if c.take(16)? != MAGIC {
        return Err(malformed(
            F,
            Location::Byte(0),
            "missing the `INTERQUAKEMODEL` magic",
        ));
    }
    let version = c.u32()?;
    if version != 2 {
        return Err(ReadError::Unsupported {
            format: F,
            what: format!("version {version} (2 is known)"),
        });
    }
    c.need(HEADER - c.pos())?;
    let mut h = [0u64; 27];
    h[0] = version as u64;
    for v in &mut h[1..] {
        *v = c.u32()? as u64;
    }
    // Header field k (0 = version) is at byte 16 + 4k.
    let at = |k: usize| 16 + 4 * k as u64;
    let file_size = h[1];
    at_least(len, 0, file_size)?;
    let (mesh_count, meshes_at) = (h[5], h[6]);
    let (array_count, vertex_count, arrays_at) = (h[7], h[8], h[9]);
    let (triangle_count, triangles_at) = (h[10], h[11]);
    if mesh_count == 0 {
        return Err(ReadError::Empty { format: F });
    }
    check_limit(F, "vertex count", vertex_count, vertex_limit(limits))?;
    let n = vertex_count as usize;

    // The vertex arrays: positions (required) and f32 normals (optional).
    let mut ac = region(bytes, arrays_at, array_count.saturating_mul(20), at(9))?;
    let mut position = None;
    let mut normal = None;
    for _ in 0..array_count {
        let array_at = ac.pos();
        let kind = ac.u32()?;
        let _flags = ac.u32()?;
        let format = ac.u32()?;
        let size = ac.u32()? as u64;
        let offset = ac.u32()? as u64;
        let Some(component) = component_size(format) else {
            return Err(malformed(
                F,
                Location::Byte(array_at + 8),
                format!("unknown vertex array format {format}"),
            ));
        };
        match kind {
            POSITION if position.is_none() => {
                if size < 3 {
                    return Err(malformed(
                        F,
                        Location::Byte(array_at + 12),
                        format!("a position has {size} components"),
                    ));
                }
                position = Some((array_at, format, size, component, offset));
            }
            NORMAL if normal.is_none() && format == FLOAT && size == 3 => {
                normal = Some((array_at, offset));
            }
            _ => {}
        }
    }
    let Some((array_at, format, size, component_bytes, offset)) = position else {
        return Err(malformed(
            F,
            Location::Byte(at(9)),
            "no position vertex array",
        ));
    };
    let stride = size * component_bytes;
    let mut pc = region(
        bytes,
        offset,
        vertex_count.saturating_mul(stride),
        array_at + 16,
    )?;
    let mut positions = Vec::with_capacity(n);
    for _ in 0..n {
        let start = pc.pos();
        let mut p = [0f64; 3];
        for v in &mut p {
            *v = component(&mut pc, format)?;
        }
        pc.skip(stride - 3 * component_bytes)?;
        let p = Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32);
        if !p.is_finite() {
            return Err(ReadError::NonFinite {
                format: F,
                location: Location::Byte(start),
            });
        }
        positions.push(p);
    }
    let mut normals = Vec::new();
    if let Some((array_at, offset)) = normal {
        let mut nc = region(
            bytes,
            offset,
            vertex_count.saturating_mul(12),
            array_at + 16,
        )?;
        normals.reserve(n);
        for _ in 0..n {
            normals.push(nc.vec3()?);
        }
    }

    // The meshes, then their triangles.
    let mut mc = region(bytes, meshes_at, mesh_count.saturating_mul(24), at(6))?;
    let mut ranges = Vec::new();
    let mut total = 0u64;
    for _ in 0..mesh_count {
        let mesh_at = mc.pos();
        mc.skip(8)?; // name, material
        let first_vertex = mc.u32()? as u64;
        let vertices = mc.u32()? as u64;
        let first_triangle = mc.u32()? as u64;
        let triangles = mc.u32()? as u64;
        if first_vertex + vertices > vertex_count {
            return Err(malformed(
                F,
                Location::Byte(mesh_at + 8),
                format!(
                    "mesh vertices {first_vertex}..{} leave the {vertex_count} vertices",
                    first_vertex + vertices
                ),
            ));
        }
        if first_triangle + triangles > triangle_count {
            return Err(malformed(
                F,
                Location::Byte(mesh_at + 16),
                format!(
                    "mesh triangles {first_triangle}..{} leave the {triangle_count} triangles",
                    first_triangle + triangles
                ),
            ));
        }
        total += triangles;
        check_limit(F, "triangle count", total, limits.max_faces as u64)?;
        ranges.push((first_triangle, triangles));
    }
    // The whole triangle list must lie inside the file, after the header.
    region(
        bytes,
        triangles_at,
        triangle_count.saturating_mul(12),
        at(11),
    )?;
    let mut faces = Vec::with_capacity(total as usize);
    for (first, count) in ranges {
        let mut tc = Cursor::new(F, bytes);
        tc.skip(triangles_at + first * 12)?;
        for _ in 0..count {
            let mut f = [0u32; 3];
            for slot in &mut f {
                let at = tc.pos();
                let i = tc.u32()?;
                if i as u64 >= vertex_count {
                    return Err(bad_vertex_index(F, at, i, n));
                }
                *slot = i;
            }
            faces.push([f[0], f[2], f[1]]);
        }
    }
    finish(F, positions, normals, faces)
}

#[cfg(test)]
mod tests {
    use super::half;

    #[test]
    fn half_floats() {
        assert_eq!(half(0x3c00), 1.0);
        assert_eq!(half(0xc000), -2.0);
        assert_eq!(half(0x3555), 0.333_251_95);
        assert_eq!(half(0x0001), 2f32.powi(-24));
        assert!(half(0x7c00).is_infinite() && half(0x7e00).is_nan());
    }
}
