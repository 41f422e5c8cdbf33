//! Wavefront OBJ.
//!
//! Read: `v` (x y z; a `w` or vertex colours after xyz are ignored), `vn`, `f` with the
//! corner syntaxes `v`, `v/vt`, `v//vn`, `v/vt/vn`, 1-based or negative (relative) indices,
//! polygons fan-triangulated; an `f` with only one or two corners (a point or line some
//! exporters write as a face) is skipped after its indices are checked. `vt o g s usemtl mtllib
//! l p`, comments and any other statement are ignored. Indices must refer to elements defined earlier in the file.
//!
//! Normals rule: positions keep their own index. If every face corner names a normal, vertex
//! `i` takes the normal of the first corner that uses it; a vertex no face uses takes `vn`
//! number `i` when there are exactly as many `vn` as `v`, else the file gets no normals. If
//! some corner has no normal, the file gets no normals. A file without faces whose `vn`
//! count equals its `v` count pairs them in order (a point cloud with normals). A `vn`
//! with a NaN or infinite component is read (it is not an error, unlike such a `v`); if it
//! becomes the normal of a vertex, the file gets no normals, as in every reader.

use std::fmt::Write as _;

use glam::Vec3;

use super::{Format, Limits, Location, ReadError, check_limit, finish, malformed, push_fan, utf8};
use crate::geometry::mesh::Mesh;

const F: Format = Format::Obj;

pub(super) fn read(bytes: &[u8], limits: &Limits) -> Result<Mesh, ReadError> {
    let text = utf8(F, bytes)?;
    let vmax = super::vertex_limit(limits);
    let mut positions: Vec<Vec3> = Vec::new();
    let mut vn: Vec<Vec3> = Vec::new();
    let mut vt_count: usize = 0;
    let mut faces: Vec<[u32; 3]> = Vec::new();
    // Per face corner normal index, parallel to the triangulated faces.
    let mut corner_normals: Vec<[u32; 3]> = Vec::new();
    let mut all_corners_have_normals = true;
    let mut corners: Vec<u32> = Vec::new();
    let mut corner_vn: Vec<Option<u32>> = Vec::new();

    for (i, raw) in text.split('\n').enumerate() {
        let line_no = i + 1;
        let loc = || Location::Line(line_no);
        let line = raw.strip_suffix('\r').unwrap_or(raw);
        let line = line.split('#').next().unwrap_or("");
        let mut tokens = line.split_ascii_whitespace();
        let Some(keyword) = tokens.next() else {
            continue;
        };
        match keyword {
            "v" => {
                let p = parse_vec3(&mut tokens, line_no, true)?;
                check_limit(F, "vertex count", positions.len() as u64 + 1, vmax)?;
                positions.push(p);
            }
            "vn" => {
                // Not required finite: the shared normals rule drops them all instead.
                let n = parse_vec3(&mut tokens, line_no, false)?;
                check_limit(F, "normal count", vn.len() as u64 + 1, vmax)?;
                vn.push(n);
            }
            "vt" => vt_count = vt_count.saturating_add(1),
            "f" => {
                corners.clear();
                corner_vn.clear();
                for tok in tokens {
                    let mut parts = tok.split('/');
                    let v = parts.next().unwrap_or("");
                    let t = parts.next();
                    let n = parts.next();
                    if parts.next().is_some() {
                        return Err(malformed(F, loc(), format!("bad face corner `{tok}`")));
                    }
                    corners.push(resolve(v, positions.len(), line_no, "vertices")?);
                    if let Some(t) = t.filter(|t| !t.is_empty()) {
                        resolve(t, vt_count, line_no, "texture coordinates")?;
                    }
                    corner_vn.push(match n.filter(|n| !n.is_empty()) {
                        Some(n) => Some(resolve(n, vn.len(), line_no, "normals")?),
                        None => None,
                    });
                }
                if corners.is_empty() {
                    return Err(malformed(F, loc(), "a face with no corners".to_string()));
                }
                if corners.len() < 3 {
                    // A one- or two-corner `f` is a point or a line written as a face (some
                    // exporters do this); like `p` and `l` it has no surface and is skipped.
                    continue;
                }
                push_fan(F, &corners, &mut faces, limits)?;
                if all_corners_have_normals && corner_vn.iter().all(Option::is_some) {
                    let c: Vec<u32> = corner_vn.iter().map(|c| c.unwrap_or(0)).collect();
                    for k in 1..c.len() - 1 {
                        corner_normals.push([c[0], c[k], c[k + 1]]);
                    }
                } else {
                    all_corners_have_normals = false;
                    corner_normals = Vec::new();
                }
            }
            _ => {} // o g s usemtl mtllib l p vp cstype ... : not geometry we keep.
        }
    }

    let normals = if faces.is_empty() {
        if vn.len() == positions.len() {
            vn
        } else {
            Vec::new()
        }
    } else if all_corners_have_normals {
        deindex_normals(&positions, &vn, &faces, &corner_normals)
    } else {
        Vec::new()
    };
    finish(F, positions, normals, faces)
}

fn deindex_normals(
    positions: &[Vec3],
    vn: &[Vec3],
    faces: &[[u32; 3]],
    corner_normals: &[[u32; 3]],
) -> Vec<Vec3> {
    let mut out: Vec<Option<Vec3>> = vec![None; positions.len()];
    for (f, c) in faces.iter().zip(corner_normals) {
        for k in 0..3 {
            let slot = &mut out[f[k] as usize];
            if slot.is_none() {
                *slot = vn.get(c[k] as usize).copied();
            }
        }
    }
    let same_count = vn.len() == positions.len();
    let mut normals = Vec::with_capacity(out.len());
    for (i, n) in out.into_iter().enumerate() {
        match n {
            Some(n) => normals.push(n),
            None if same_count => normals.push(vn[i]),
            None => return Vec::new(),
        }
    }
    normals
}

/// Three numbers; with `finite`, NaN and infinities are [`ReadError::NonFinite`].
fn parse_vec3<'a>(
    tokens: &mut impl Iterator<Item = &'a str>,
    line: usize,
    finite: bool,
) -> Result<Vec3, ReadError> {
    let mut v = [0f32; 3];
    for c in &mut v {
        let tok = tokens
            .next()
            .ok_or_else(|| malformed(F, Location::Line(line), "expected 3 coordinates"))?;
        *c = tok
            .parse::<f32>()
            .map_err(|_| malformed(F, Location::Line(line), format!("`{tok}` is not a number")))?;
        if finite && !c.is_finite() {
            return Err(ReadError::NonFinite {
                format: F,
                location: Location::Line(line),
            });
        }
    }
    Ok(Vec3::from_array(v))
}

/// Resolves a 1-based or negative OBJ index against the `count` elements defined so far.
fn resolve(tok: &str, count: usize, line: usize, what: &'static str) -> Result<u32, ReadError> {
    let i: i64 = tok.parse().map_err(|_| {
        malformed(
            F,
            Location::Line(line),
            format!("`{tok}` is not a valid index"),
        )
    })?;
    let idx = if i > 0 {
        i - 1
    } else if i < 0 {
        (count as i64).saturating_add(i)
    } else {
        -1
    };
    if idx < 0 || idx as u64 >= count as u64 {
        return Err(ReadError::IndexOutOfRange {
            format: F,
            what,
            location: Location::Line(line),
            index: i,
            count,
        });
    }
    Ok(idx as u32)
}

/// True when the text looks like OBJ: every statement starts with an OBJ keyword and there
/// is at least one `v`.
pub(super) fn looks_like_obj(text: &str) -> bool {
    let mut has_v = false;
    let mut lines = text.lines().peekable();
    while let Some(line) = lines.next() {
        // The last line may be cut by the sniffing window.
        let is_last = lines.peek().is_none();
        let Some(kw) = line.split_ascii_whitespace().next() else {
            continue;
        };
        if kw.starts_with('#') {
            continue;
        }
        match kw {
            "v" => has_v = true,
            "vn" | "vt" | "vp" | "f" | "l" | "p" | "o" | "g" | "s" | "usemtl" | "mtllib" => {}
            _ if is_last => {}
            _ => return false,
        }
    }
    has_v
}

/// Writes `v`, `vn` (when the mesh has normals) and `f` lines. Coordinates use Rust's
/// shortest round-trip formatting, so reading the file back gives bit-identical values.
pub fn write_obj(mesh: &Mesh) -> String {
    let has_n = !mesh.normals.is_empty() && mesh.normals.len() == mesh.positions.len();
    let mut s = String::with_capacity(mesh.positions.len() * 40 + mesh.faces.len() * 30);
    s.push_str("# written by meshflow\n");
    for p in &mesh.positions {
        let _ = writeln!(s, "v {} {} {}", p.x, p.y, p.z);
    }
    if has_n {
        for n in &mesh.normals {
            let _ = writeln!(s, "vn {} {} {}", n.x, n.y, n.z);
        }
    }
    for f in &mesh.faces {
        let [a, b, c] = f.map(|i| i as u64 + 1);
        if has_n {
            let _ = writeln!(s, "f {a}//{a} {b}//{b} {c}//{c}");
        } else {
            let _ = writeln!(s, "f {a} {b} {c}");
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read_str(s: &str) -> Result<Mesh, ReadError> {
        read(s.as_bytes(), &Limits::default())
    }

    #[test]
    fn all_face_syntaxes_and_negative_indices() {
        let m = read_str(
            "# c\nmtllib a.mtl\no x\nv 0 0 0\nv 1 0 0 1\nv 1 1 0 0.5 0.5 0.5\nv 0 1 0\nvt 0 0\nvt 1 0\nvn 0 0 1\ng g\ns 1\nusemtl m\nf 1 2 3\nf 1/1 2/2 3/1\nf 1//1 2//1 3//1\nf 1/1/1 2/2/1 3/1/1\nf -4 -3 -2 -1\nl 1 2\np 1\n",
        )
        .unwrap();
        assert_eq!(m.positions.len(), 4);
        assert_eq!(m.faces.len(), 6);
        assert_eq!(m.faces[4], [0, 1, 2]);
        assert_eq!(m.faces[5], [0, 2, 3]);
        assert!(m.normals.is_empty(), "some corners lack normals");
    }

    #[test]
    fn normals_deindexed_from_first_reference() {
        let m =
            read_str("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn 1 0 0\nf 1//1 2//2 3//1\n").unwrap();
        assert_eq!(m.normals, vec![Vec3::Z, Vec3::X, Vec3::Z]);
    }

    #[test]
    fn zero_index_is_out_of_range() {
        assert!(matches!(
            read_str("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"),
            Err(ReadError::IndexOutOfRange {
                index: 0,
                location: Location::Line(4),
                ..
            })
        ));
    }

    #[test]
    fn sniffing() {
        assert!(looks_like_obj("# hi\nv 1 2 3\nf 1 1 1\n"));
        assert!(!looks_like_obj("1 2 3\n"));
    }
}
