//! MD5 (`.md5mesh`), the Doom 3 skeletal mesh text format (version 10), as used by Red
//! Eclipse; the bind pose is read.
//!
//! ```text
//! MD5Version 10
//! commandline ""
//! numJoints 1
//! numMeshes 1
//! joints {
//!     "Bone01" -1 ( 0 0 0 ) ( 0.0005 0.7071 -0.0002 )   // name parent ( pos ) ( orient x y z )
//! }
//! mesh {
//!     shader "01 - Default"
//!     numverts 4
//!     vert 0 ( 0.0 1.0 ) 0 1        // index ( u v ) first weight, weight count
//!     ...
//!     numtris 2
//!     tri 0 0 2 1                   // index, three vertex indices
//!     ...
//!     numweights 4
//!     weight 0 0 1.0 ( 0.0006 -40.0 40.0 )   // index, joint, bias ( position )
//!     ...
//! }
//! ```
//!
//! Tokens are separated by whitespace; `(`, `)`, `{` and `}` are tokens of their own, quoted
//! strings are single tokens and `//` starts a comment. The joints are given in the bind pose,
//! in model space: a joint's orientation is a unit quaternion of which the file holds x, y, z;
//! w is recomputed as `-sqrt(1 - x² - y² - z²)` (0 when that is negative). A vertex's position
//! is the sum over its weights (at most [`MAX_WEIGHTS_PER_VERTEX`]) of
//! `bias * (joint.pos + rotate(joint.orient, weight.pos))`. With this sign of w the weights of
//! every multi-weight vertex of the real Red Eclipse files land on one point, as a bind pose
//! must; with the other they spread up to half a unit apart.
//!
//! Every `numverts`, `numtris` and `numweights` comes before its list, and `numJoints` before
//! `joints`; lists are numbered from 0 in order and must hold the declared counts, as must
//! `joints`. As in the engines that load these files, `numMeshes` is not checked (Red
//! Eclipse's ball declares 2 meshes and holds 1) and the `MD5Version 10` line may be missing
//! (two Red Eclipse weapons start at `commandline`); another version is `Unsupported`. All
//! meshes are merged into one. Coordinates are kept as
//! computed (Doom 3 and Red Eclipse are +Z up). Triangles are stored clockwise seen from outside
//! and are reversed to wind counter-clockwise, as everywhere in meshflow. The mesh has no
//! normals.

use glam::{DQuat, DVec3, Vec3};

use super::tokens::{Token, Tokens};
use super::{Format, Limits, Location, ReadError, check_limit, finish, malformed, vertex_limit};
use crate::geometry::mesh::Mesh;

const F: Format = Format::Md5;

/// Most weights one vertex may have (real files have at most 3; the bound keeps the work
/// linear in the vertex count).
pub const MAX_WEIGHTS_PER_VERTEX: u64 = 64;

struct Joint {
    pos: DVec3,
    orient: DQuat,
}

struct Reader<'a, 'l> {
    t: Tokens<'a>,
    limits: &'l Limits,
    joints: Vec<Joint>,
    positions: Vec<Vec3>,
    faces: Vec<[u32; 3]>,
}

/// The orientation of a joint from the x, y, z the file holds.
fn orientation(x: f64, y: f64, z: f64) -> DQuat {
    let t = 1.0 - x * x - y * y - z * z;
    let w = if t < 0.0 { 0.0 } else { -t.sqrt() };
    DQuat::from_xyzw(x, y, z, w).normalize()
}

impl Reader<'_, '_> {
    /// `( a b c )` as three finite numbers.
    fn vec3(&mut self) -> Result<DVec3, ReadError> {
        self.t.expect("(")?;
        let v = DVec3::new(
            self.t.coordinate()?,
            self.t.coordinate()?,
            self.t.coordinate()?,
        );
        self.t.expect(")")?;
        Ok(v)
    }

    /// A list count (`numverts 12`): its value, checked to be at most `limit`.
    fn count(&mut self, what: &'static str, limit: u64) -> Result<u64, ReadError> {
        let n: u64 = self.t.number(what)?;
        check_limit(F, what, n, limit)?;
        Ok(n)
    }

    /// The number after a list keyword, which must be `k`, the item's position.
    fn item_number(&mut self, key: &Token, k: u64, declared: u64) -> Result<(), ReadError> {
        let i: u64 = self.t.number("item number")?;
        if i != k {
            return Err(malformed(
                F,
                key.loc(),
                format!("`{}` {k} is numbered {i}", key.show()),
            ));
        }
        if k >= declared {
            return Err(malformed(
                F,
                key.loc(),
                format!("more `{}` than the {declared} declared", key.show()),
            ));
        }
        Ok(())
    }

    fn joints(&mut self, declared: u64) -> Result<(), ReadError> {
        // A joint takes at least 20 bytes: `"" 0 ( 0 0 0 ) ( 0 0 0 )`.
        self.joints
            .reserve((declared as usize).min(self.t.remaining() / 20));
        loop {
            let name = self.t.expect_any()?;
            if name.is("}") {
                break;
            }
            let k = self.joints.len() as u64;
            if k >= declared {
                return Err(malformed(
                    F,
                    name.loc(),
                    format!("more joints than the {declared} declared"),
                ));
            }
            let parent_tok = self.t.expect_any()?;
            let parent: i64 = super::tokens::parse(F, &parent_tok, "parent joint")?;
            if parent < -1 || parent >= declared as i64 {
                return Err(ReadError::IndexOutOfRange {
                    format: F,
                    location: parent_tok.loc(),
                    what: "joints",
                    index: parent,
                    count: declared as usize,
                });
            }
            let pos = self.vec3()?;
            let q = self.vec3()?;
            self.joints.push(Joint {
                pos,
                orient: orientation(q.x, q.y, q.z),
            });
        }
        if self.joints.len() as u64 != declared {
            return Err(malformed(
                F,
                self.t.loc_here(),
                format!("{} joints listed, {declared} declared", self.joints.len()),
            ));
        }
        Ok(())
    }

    fn mesh(&mut self) -> Result<(), ReadError> {
        let base = self.positions.len();
        // (first weight, weight count, line) per vertex.
        let mut verts: Vec<(u64, u64, usize)> = Vec::new();
        let mut tris: Vec<([u64; 3], Location)> = Vec::new();
        // (joint, bias, position) per weight.
        let mut weights: Vec<(usize, f64, DVec3)> = Vec::new();
        let (mut nv, mut nt, mut nw) = (None, None, None);
        let max_vertices = vertex_limit(self.limits);
        loop {
            let key = self.t.expect_any()?;
            let kw = key.text;
            match kw {
                b"}" => break,
                b"shader" => {
                    self.t.expect_any()?;
                }
                b"numverts" | b"numtris" | b"numweights" => {
                    let slot = match kw {
                        b"numverts" => &mut nv,
                        b"numtris" => &mut nt,
                        _ => &mut nw,
                    };
                    if slot.is_some() {
                        return Err(malformed(
                            F,
                            key.loc(),
                            format!("a second `{}`", key.show()),
                        ));
                    }
                    // Limits, and allocation bounded by what the rest of the file can hold
                    // (a vertex line takes at least 16 bytes, a triangle 12, a weight 24).
                    let (n, room) = match kw {
                        b"numverts" => (
                            self.count("vertex count", max_vertices.saturating_sub(base as u64))?,
                            16,
                        ),
                        b"numtris" => (
                            self.count(
                                "triangle count",
                                (self.limits.max_faces as u64)
                                    .saturating_sub(self.faces.len() as u64),
                            )?,
                            12,
                        ),
                        _ => (self.t.number("weight count")?, 24),
                    };
                    let cap = (n as usize).min(self.t.remaining() / room);
                    match kw {
                        b"numverts" => verts.reserve(cap),
                        b"numtris" => tris.reserve(cap),
                        _ => weights.reserve(cap),
                    }
                    *slot = Some(n);
                }
                b"vert" => {
                    let declared = nv.unwrap_or(0);
                    self.item_number(&key, verts.len() as u64, declared)?;
                    self.t.expect("(")?;
                    self.t.coordinate()?;
                    self.t.coordinate()?;
                    self.t.expect(")")?;
                    let first: u64 = self.t.number("first weight")?;
                    let count: u64 = self.t.number("weight count")?;
                    verts.push((first, count, key.line));
                }
                b"tri" => {
                    let declared = nt.unwrap_or(0);
                    self.item_number(&key, tris.len() as u64, declared)?;
                    let mut f = [0u64; 3];
                    for v in &mut f {
                        *v = self.t.number("vertex index")?;
                    }
                    tris.push((f, key.loc()));
                }
                b"weight" => {
                    let declared = nw.unwrap_or(0);
                    self.item_number(&key, weights.len() as u64, declared)?;
                    let joint_tok = self.t.expect_any()?;
                    let joint: u64 = super::tokens::parse(F, &joint_tok, "joint index")?;
                    if joint >= self.joints.len() as u64 {
                        return Err(ReadError::IndexOutOfRange {
                            format: F,
                            location: joint_tok.loc(),
                            what: "joints",
                            index: i64::try_from(joint).unwrap_or(i64::MAX),
                            count: self.joints.len(),
                        });
                    }
                    let bias = self.t.coordinate()?;
                    let p = self.vec3()?;
                    weights.push((joint as usize, bias, p));
                }
                _ => {
                    return Err(malformed(
                        F,
                        key.loc(),
                        format!("unexpected `{}` in a mesh", key.show()),
                    ));
                }
            }
        }
        let end = self.t.loc_here();
        for (what, listed, declared) in [
            ("vertices", verts.len(), nv),
            ("triangles", tris.len(), nt),
            ("weights", weights.len(), nw),
        ] {
            if listed as u64 != declared.unwrap_or(0) {
                return Err(malformed(
                    F,
                    end.clone(),
                    format!("{listed} {what} listed, {} declared", declared.unwrap_or(0)),
                ));
            }
        }
        self.positions.reserve(verts.len());
        for &(first, count, line) in &verts {
            if count == 0 {
                return Err(malformed(
                    F,
                    Location::Line(line),
                    "a vertex without weights",
                ));
            }
            check_limit(F, "weights of one vertex", count, MAX_WEIGHTS_PER_VERTEX)?;
            let end = first.saturating_add(count);
            if end > weights.len() as u64 {
                return Err(ReadError::IndexOutOfRange {
                    format: F,
                    location: Location::Line(line),
                    what: "weights",
                    index: i64::try_from(end).unwrap_or(i64::MAX) - 1,
                    count: weights.len(),
                });
            }
            let mut p = DVec3::ZERO;
            for &(joint, bias, wp) in &weights[first as usize..end as usize] {
                let j = &self.joints[joint];
                p += bias * (j.pos + j.orient * wp);
            }
            let p = p.as_vec3();
            if !p.is_finite() {
                return Err(ReadError::NonFinite {
                    format: F,
                    location: Location::Line(line),
                });
            }
            self.positions.push(p);
        }
        self.faces.reserve(tris.len());
        for (f, at) in tris {
            for &i in &f {
                if i >= verts.len() as u64 {
                    return Err(ReadError::IndexOutOfRange {
                        format: F,
                        location: at,
                        what: "vertices",
                        index: i64::try_from(i).unwrap_or(i64::MAX),
                        count: verts.len(),
                    });
                }
            }
            let [a, b, c] = f.map(|i| (base as u64 + i) as u32);
            self.faces.push([a, c, b]);
        }
        Ok(())
    }
}

pub(super) fn read(bytes: &[u8], limits: &Limits) -> Result<Mesh, ReadError> {
    let mut r = Reader {
        t: Tokens::new(F, bytes, b"(){}", true),
        limits,
        joints: Vec::new(),
        positions: Vec::new(),
        faces: Vec::new(),
    };
    let (mut num_joints, mut num_meshes) = (None, None);
    let mut have_version = false;
    let mut have_joints = false;
    let mut first = true;
    while let Some(key) = r.t.next() {
        match key.text {
            b"MD5Version" if first => {
                have_version = true;
                let version: i64 = r.t.number("version")?;
                if version != 10 {
                    return Err(ReadError::Unsupported {
                        format: F,
                        what: format!("version {version} (10 is known)"),
                    });
                }
            }
            b"commandline" => {
                r.t.expect_any()?;
            }
            b"numJoints" if num_joints.is_none() => {
                num_joints = Some(r.t.number::<u64>("joint count")?)
            }
            b"numMeshes" if num_meshes.is_none() => {
                num_meshes = Some(r.t.number::<u64>("mesh count")?)
            }
            b"joints" if !have_joints => {
                let Some(n) = num_joints else {
                    return Err(malformed(F, key.loc(), "`joints` before `numJoints`"));
                };
                r.t.expect("{")?;
                have_joints = true;
                r.joints(n)?;
            }
            b"mesh" => {
                if !have_version && num_joints.is_none() && num_meshes.is_none() {
                    return Err(malformed(F, key.loc(), "a mesh before any MD5 header"));
                }
                r.t.expect("{")?;
                r.mesh()?;
            }
            _ => {
                return Err(malformed(
                    F,
                    key.loc(),
                    format!("unexpected `{}`", key.show()),
                ));
            }
        }
        first = false;
    }
    if num_joints.unwrap_or(0) > 0 && !have_joints {
        return Err(malformed(F, r.t.loc_here(), "no `joints` block"));
    }
    finish(F, r.positions, Vec::new(), r.faces)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_and_joint_rotation() {
        // One joint at (10, 0, 0) turned 90° about z (w = -sqrt(0.5), so the rotation is by
        // -90°... as Doom 3 defines it); two vertices of one weight, one of two.
        let s = "MD5Version 10 // comment\ncommandline \"a b\"\nnumJoints 1\nnumMeshes 1\njoints {\n\t\"root\" -1 ( 10 0 0 ) ( 0 0 0.70710678 )\n}\nmesh {\n\tshader \"s\"\n\tnumverts 3\n\tvert 0 ( 0 0 ) 0 1\n\tvert 1 ( 0 0 ) 1 1\n\tvert 2 ( 0 0 ) 2 2\n\tnumtris 1\n\ttri 0 0 1 2\n\tnumweights 4\n\tweight 0 0 1 ( 0 0 0 )\n\tweight 1 0 1 ( 1 0 0 )\n\tweight 2 0 0.5 ( 0 2 0 )\n\tweight 3 0 0.5 ( 0 0 2 )\n}\n";
        let m = read(s.as_bytes(), &Limits::default()).unwrap();
        assert_eq!(m.faces, vec![[0, 2, 1]]);
        let near = |a: Vec3, b: [f32; 3]| (a - Vec3::from_array(b)).length() < 1e-5;
        assert!(near(m.positions[0], [10.0, 0.0, 0.0]), "{}", m.positions[0]);
        // q = (0, 0, s, -s): a rotation by -90° about z, (1, 0, 0) -> (0, -1, 0).
        assert!(
            near(m.positions[1], [10.0, -1.0, 0.0]),
            "{}",
            m.positions[1]
        );
        // 0.5 (10 + (2, 0, 0)) + 0.5 ((10, 0, 2)) = (11, 0, 1).
        assert!(near(m.positions[2], [11.0, 0.0, 1.0]), "{}", m.positions[2]);
    }
}
