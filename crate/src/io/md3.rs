//! MD3, the Quake III Arena model format (little-endian binary); only the first frame is read.
//!
//! Header (108 bytes): `IDP3`, i32 version (15), a 64-byte name, then i32 flags and the counts
//! of frames, tags, surfaces and skins, then the offsets of the frames, tags, surfaces and the
//! end of the file. The first surface starts at the surface offset and each further one at the
//! end of the one before. A surface header (108 bytes) is `IDP3`, a 64-byte name, i32 flags and
//! the counts of frames, shaders, vertices and triangles, then the offsets (from the start of
//! the surface) of its triangles, shaders, texture coordinates, vertices and its end. A
//! triangle is three i32 vertex indices into its surface; a vertex is three i16 coordinates in
//! 1/64 units and an i16 normal whose high byte is the latitude and low byte the longitude,
//! each in steps of 2π/256: n = (cos lat sin lng, sin lat sin lng, cos lng). Each surface stores
//! all its frames' vertices one frame after the other; frame 0 comes first.
//!
//! All surfaces are merged into one mesh (each surface's indices offset by the vertices
//! before it). Triangles are stored clockwise seen from outside (see the fixtures' signed
//! volumes in `crate/tests/io_game.rs`); each is reversed so that faces wind
//! counter-clockwise, as everywhere in meshflow. Coordinates are integers, so they are always
//! finite; tags, shaders, texture coordinates and later frames are ignored.
//!
//! Counts and offsets are checked against the file: negative ones are `Malformed`, counts over
//! the [`Limits`] are `TooLarge`, and a region (or the declared end) past the end of the file is
//! `Truncated`.

use glam::Vec3;

use super::{
    Cursor, Format, Limits, Location, ReadError, check_limit, finish, malformed, vertex_limit,
};
use crate::geometry::mesh::Mesh;

const F: Format = Format::Md3;
/// The size of the file header and of a surface header.
const HEADER: u64 = 108;
const SURFACE_HEADER: u64 = 108;
/// One vertex of one frame: 3 x i16 position, i16 normal.
const VERTEX_BYTES: u64 = 8;

/// Reads `N` consecutive i32 header fields starting at `at`.
fn fields<const N: usize>(bytes: &[u8], at: u64) -> Result<[i64; N], ReadError> {
    let mut c = Cursor::new(F, bytes);
    c.skip(at)?;
    let mut h = [0i64; N];
    for v in &mut h {
        *v = c.i32()? as i64;
    }
    Ok(h)
}

/// A header field that must not be negative; `at` is its byte offset.
fn non_negative(v: i64, at: u64, what: &str) -> Result<u64, ReadError> {
    u64::try_from(v).map_err(|_| malformed(F, Location::Byte(at), format!("negative {what} ({v})")))
}

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

/// The decoded normal of a packed latitude/longitude pair.
fn normal(packed: u16) -> Vec3 {
    let step = std::f32::consts::TAU / 256.0;
    let lat = (packed >> 8) as f32 * step;
    let lng = (packed & 0xff) as f32 * step;
    Vec3::new(lat.cos() * lng.sin(), lat.sin() * lng.sin(), lng.cos())
}

pub(super) fn read(bytes: &[u8], limits: &Limits) -> Result<Mesh, ReadError> {
    let len = bytes.len() as u64;
    let mut c = Cursor::new(F, bytes);
    if c.take(4)? != b"IDP3" {
        return Err(malformed(F, Location::Byte(0), "missing the `IDP3` magic"));
    }
    let version = c.i32()?;
    if version != 15 {
        return Err(ReadError::Unsupported {
            format: F,
            what: format!("version {version} (15 is known)"),
        });
    }
    c.need(HEADER - c.pos())?;
    // flags, frames, tags, surfaces, skins, ofs frames, ofs tags, ofs surfaces, ofs end
    let h: [i64; 9] = fields(bytes, 72)?;
    let at = |k: usize| 72 + 4 * k as u64;
    let surface_count = non_negative(h[3], at(3), "surface count")?;
    let mut surface_at = non_negative(h[7], at(7), "surface offset")?;
    let end = non_negative(h[8], at(8), "end offset")?;
    at_least(len, end, 0)?;
    if surface_count > 0 && surface_at < HEADER {
        return Err(malformed(
            F,
            Location::Byte(at(7)),
            format!("surface offset {surface_at} points into the header"),
        ));
    }
    // Each surface takes at least its header: a count the file cannot hold is cut short.
    at_least(
        len,
        surface_at,
        surface_count.saturating_mul(SURFACE_HEADER),
    )?;

    let max_vertices = vertex_limit(limits);
    let mut positions: Vec<Vec3> = Vec::new();
    let mut normals: Vec<Vec3> = Vec::new();
    let mut faces: Vec<[u32; 3]> = Vec::new();
    for _ in 0..surface_count {
        let s = surface_at;
        at_least(len, s, SURFACE_HEADER)?;
        let mut hc = Cursor::new(F, bytes);
        hc.skip(s)?;
        if hc.take(4)? != b"IDP3" {
            return Err(malformed(
                F,
                Location::Byte(s),
                "surface is missing the `IDP3` magic",
            ));
        }
        // flags, frames, shaders, verts, triangles, ofs triangles, ofs shaders, ofs st,
        // ofs xyznormal, ofs end
        let sh: [i64; 10] = fields(bytes, s + 68)?;
        let at = |k: usize| s + 68 + 4 * k as u64;
        let frames = non_negative(sh[1], at(1), "surface frame count")?;
        let vertex_count = non_negative(sh[3], at(3), "surface vertex count")?;
        let triangle_count = non_negative(sh[4], at(4), "surface triangle count")?;
        let triangles_at = non_negative(sh[5], at(5), "triangle offset")?;
        let vertices_at = non_negative(sh[8], at(8), "vertex offset")?;
        let surface_end = non_negative(sh[9], at(9), "surface end offset")?;
        if surface_end < SURFACE_HEADER {
            return Err(malformed(
                F,
                Location::Byte(at(9)),
                format!("surface end offset {surface_end} points into the surface header"),
            ));
        }
        let base = positions.len();
        check_limit(
            F,
            "vertex count",
            (base as u64).saturating_add(vertex_count),
            max_vertices,
        )?;
        check_limit(
            F,
            "triangle count",
            (faces.len() as u64).saturating_add(triangle_count),
            limits.max_faces as u64,
        )?;
        if vertex_count > 0 && frames == 0 {
            return Err(malformed(
                F,
                Location::Byte(at(1)),
                "the surface has no frames",
            ));
        }
        // A region of the surface: after its header and inside the file.
        let region = |ofs: u64, n: u64, field: u64| -> Result<Cursor<'_>, ReadError> {
            if ofs < SURFACE_HEADER {
                return Err(malformed(
                    F,
                    Location::Byte(field),
                    format!("offset {ofs} points into the surface header"),
                ));
            }
            let start = s.saturating_add(ofs);
            at_least(len, start, n)?;
            let mut c = Cursor::new(F, bytes);
            c.skip(start)?;
            Ok(c)
        };

        let n = vertex_count as usize;
        if n > 0 {
            let mut vc = region(vertices_at, vertex_count * VERTEX_BYTES, at(8))?;
            positions.reserve(n);
            normals.reserve(n);
            for _ in 0..n {
                let x = vc.u16()? as i16;
                let y = vc.u16()? as i16;
                let z = vc.u16()? as i16;
                positions.push(Vec3::new(x as f32, y as f32, z as f32) / 64.0);
                normals.push(normal(vc.u16()?));
            }
        }
        if triangle_count > 0 {
            let mut tc = region(triangles_at, triangle_count * 12, at(5))?;
            faces.reserve(triangle_count as usize);
            for _ in 0..triangle_count {
                let mut f = [0u32; 3];
                for slot in &mut f {
                    let at = tc.pos();
                    let i = tc.i32()?;
                    if i < 0 || i as usize >= n {
                        return Err(ReadError::IndexOutOfRange {
                            format: F,
                            location: Location::Byte(at),
                            what: "vertices",
                            index: i as i64,
                            count: n,
                        });
                    }
                    *slot = (base + i as usize) as u32;
                }
                faces.push([f[0], f[2], f[1]]);
            }
        }
        surface_at = s.saturating_add(surface_end);
    }
    finish(F, positions, normals, faces)
}
