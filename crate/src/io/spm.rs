//! SPM, the mesh format of SuperTuxKart (little-endian binary), static and skinned.
//!
//! Layout, as found in the SuperTuxKart 1.4 data:
//! - `SP`; a byte whose bits 3 and up hold the version (1) and whose low 3 bits the type
//!   (1 skinned, 2 static; 0 is also read as static); a flags byte (bit 0 normals, bit 1
//!   colours, bit 2 tangents); a 24-byte bounding box (ignored).
//! - u16 texture (material) count, then per material two names, each a u8 length and bytes.
//! - u16 object count; per object a u16 mesh count; per mesh a u32 vertex count, a u32 index
//!   count and a u16 material id, then the vertices and the indices (u16 when the mesh has more
//!   than 255 vertices, else u8; three per triangle).
//! - A vertex is a position (f32x3); a packed normal (4 bytes, signed 10:10:10:2) if flag bit
//!   0; if flag bit 1 a colour: one byte, 128 for "none", else 3 more bytes; 4 bytes of UV if
//!   the material's first texture name is not empty and 4 more if its second one is not; 4
//!   bytes of tangent if flag bit 2 *and* the first texture is present; 16 bytes of joints and
//!   weights if skinned.
//!
//! Two differences from the layout notes in `docs/data.md`, found by reading all 1,222
//! `.spm` files of supertuxkart-data 1.4: tangents are stored only for vertices whose material
//! has a first texture, and static meshes end exactly after the last mesh's indices (no 24
//! trailing bytes). Skinned files continue with armature data, which is ignored, as are any
//! bytes after the last mesh.
//!
//! All meshes of all objects are merged into one [`Mesh`] (indices offset). Normals are kept
//! when the flag says they are present.

use glam::Vec3;

use super::{
    Cursor, Format, Limits, Location, ReadError, bad_vertex_index, check_limit, finish, malformed,
    vertex_limit,
};
use crate::geometry::mesh::Mesh;

const F: Format = Format::Spm;

const FLAG_NORMALS: u8 = 1;
const FLAG_COLOURS: u8 = 2;
const FLAG_TANGENTS: u8 = 4;

/// `SP`, version 1, type 0 to 2.
pub(super) fn magic_matches(bytes: &[u8]) -> bool {
    bytes.len() >= 4 && bytes.starts_with(b"SP") && bytes[2] >> 3 == 1 && bytes[2] & 7 <= 2
}

/// Decodes a signed-normalised 10:10:10:2 normal (x in the low bits).
fn unpack_normal(v: u32) -> Vec3 {
    let c = |shift: u32| {
        let raw = ((v >> shift) & 0x3ff) as i32;
        let signed = if raw >= 512 { raw - 1024 } else { raw };
        (signed as f32 / 511.0).max(-1.0)
    };
    Vec3::new(c(0), c(10), c(20))
}

pub(super) fn read(bytes: &[u8], limits: &Limits) -> Result<Mesh, ReadError> {
    let mut c = Cursor::new(F, bytes);
    if c.take(2)? != b"SP" {
        return Err(malformed(F, Location::Byte(0), "missing the `SP` magic"));
    }
    let kind = c.u8()?;
    if kind >> 3 != 1 {
        return Err(ReadError::Unsupported {
            format: F,
            what: format!("version {} (1 is known)", kind >> 3),
        });
    }
    let skinned = match kind & 7 {
        0 | 2 => false,
        1 => true,
        t => {
            return Err(ReadError::Unsupported {
                format: F,
                what: format!("mesh type {t} (1 skinned and 2 static are known)"),
            });
        }
    };
    let flags = c.u8()?;
    c.skip(24)?;

    // Per material: (has a first texture, has a second texture).
    let material_count = c.u16()?;
    let mut materials = Vec::with_capacity(material_count as usize);
    for _ in 0..material_count {
        let mut present = [false; 2];
        for p in &mut present {
            let len = c.u8()?;
            c.skip(len as u64)?;
            *p = len > 0;
        }
        materials.push(present);
    }

    let mut positions: Vec<Vec3> = Vec::new();
    let mut normals: Vec<Vec3> = Vec::new();
    let mut faces: Vec<[u32; 3]> = Vec::new();
    let object_count = c.u16()?;
    for _ in 0..object_count {
        let mesh_count = c.u16()?;
        for _ in 0..mesh_count {
            let count_at = c.pos();
            let vertex_count = c.u32()? as u64;
            let index_count = c.u32()? as u64;
            let material_at = c.pos();
            let material = c.u16()?;
            let total = positions.len() as u64 + vertex_count;
            check_limit(F, "vertex count", total, vertex_limit(limits))?;
            if !index_count.is_multiple_of(3) {
                return Err(malformed(
                    F,
                    Location::Byte(count_at + 4),
                    format!("index count {index_count} is not a multiple of 3"),
                ));
            }
            let triangles = faces.len() as u64 + index_count / 3;
            check_limit(F, "triangle count", triangles, limits.max_faces as u64)?;
            let Some(&[uv1, uv2]) = materials.get(material as usize) else {
                return Err(ReadError::IndexOutOfRange {
                    format: F,
                    location: Location::Byte(material_at),
                    what: "materials",
                    index: material as i64,
                    count: materials.len(),
                });
            };
            // The least a vertex takes (a colour may take 3 bytes more).
            let mut stride = 12u64;
            if flags & FLAG_NORMALS != 0 {
                stride += 4;
            }
            if flags & FLAG_COLOURS != 0 {
                stride += 1;
            }
            if uv1 {
                stride += 4;
                if flags & FLAG_TANGENTS != 0 {
                    stride += 4;
                }
            }
            if uv2 {
                stride += 4;
            }
            if skinned {
                stride += 16;
            }
            let wide = vertex_count > 255;
            c.need(vertex_count * stride + index_count * if wide { 2 } else { 1 })?;

            // What follows the position, normal and colour: UVs, tangent, joints.
            let tail = stride
                - 12
                - if flags & FLAG_NORMALS != 0 { 4 } else { 0 }
                - if flags & FLAG_COLOURS != 0 { 1 } else { 0 };
            let base = positions.len() as u32;
            positions.reserve(vertex_count as usize);
            for _ in 0..vertex_count {
                positions.push(c.finite_vec3()?);
                if flags & FLAG_NORMALS != 0 {
                    normals.push(unpack_normal(c.u32()?));
                }
                if flags & FLAG_COLOURS != 0 && c.u8()? != 128 {
                    c.skip(3)?;
                }
                c.skip(tail)?;
            }
            let n = vertex_count as usize;
            faces.reserve((index_count / 3) as usize);
            for _ in 0..index_count / 3 {
                let mut f = [0u32; 3];
                for slot in &mut f {
                    let at = c.pos();
                    let i = if wide {
                        c.u16()? as u32
                    } else {
                        c.u8()? as u32
                    };
                    if i as usize >= n {
                        return Err(bad_vertex_index(F, at, i, n));
                    }
                    *slot = base + i;
                }
                faces.push(f);
            }
        }
    }
    // Normals are all present or none (the flag is per file).
    finish(F, positions, normals, faces)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unpacks_normals() {
        assert_eq!(unpack_normal(0x1ff), Vec3::X);
        assert_eq!(unpack_normal(0x1ff << 10), Vec3::Y);
        assert_eq!(unpack_normal(0x201 << 20), Vec3::NEG_Z);
    }
}
