//! Area-weighted vertex normals and unit face normals.
//!
//! Conventions (docs/design.md section 2, the same the reference's meshes use): every face adds its
//! *unnormalised* cross product `(b - a) x (c - a)` (twice its area times its unit normal) to its
//! three corners; the sum is then normalised. A vertex whose sum has length `<= 1e-8`, or that no
//! face uses, gets `+Z`, the fallback mesh extraction uses for its winding test too.
//!
//! The sums are accumulated in `f64` so the result does not depend on face order beyond the
//! final rounding to `f32` (the golden normals match to about 1e-7).

use glam::{DVec3, Vec3};

/// Length at or below which a normal is considered undefined and replaced by `+Z`.
pub const NORMAL_EPS: f64 = 1e-8;

fn unit_or_z(v: DVec3) -> Vec3 {
    let len = v.length();
    if len.is_finite() && len > NORMAL_EPS {
        (v / len).as_vec3()
    } else {
        Vec3::Z
    }
}

/// Area-weighted unit normal of every vertex (see the module doc for the rule and fallback).
///
/// # Panics
/// When a face names a vertex `>= positions.len()` (see [`crate::Mesh::validate`]).
pub fn vertex_normals(positions: &[Vec3], faces: &[[u32; 3]]) -> Vec<Vec3> {
    let mut sums = vec![DVec3::ZERO; positions.len()];
    for f in faces {
        let [a, b, c] = f.map(|i| positions[i as usize].as_dvec3());
        let n = (b - a).cross(c - a);
        for &i in f {
            sums[i as usize] += n;
        }
    }
    sums.into_iter().map(unit_or_z).collect()
}

/// Unit normal of a triangle (counter-clockwise front), `+Z` when its cross product has length
/// `<= 1e-8` (degenerate or tiny triangles).
pub fn face_normal(tri: [Vec3; 3]) -> Vec3 {
    let [a, b, c] = tri.map(|p| p.as_dvec3());
    unit_or_z((b - a).cross(c - a))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::primitives::{cube, grid, icosphere, octahedron};

    #[test]
    fn sphere_normals_point_outward() {
        let m = icosphere(2);
        let n = vertex_normals(&m.positions, &m.faces);
        for (p, n) in m.positions.iter().zip(&n) {
            assert!((n.length() - 1.0).abs() < 1e-6);
            assert!(p.normalize().dot(*n) > 0.99, "{p} {n}");
        }
        let o = octahedron();
        for (p, n) in o
            .positions
            .iter()
            .zip(vertex_normals(&o.positions, &o.faces))
        {
            assert!((p.normalize() - n).length() < 1e-6);
        }
    }

    #[test]
    fn cube_corners_are_diagonal() {
        let m = cube();
        let c = m.aabb().unwrap().center();
        for (p, n) in m
            .positions
            .iter()
            .zip(vertex_normals(&m.positions, &m.faces))
        {
            let d = (*p - c).normalize();
            // Area weighting on a triangulated cube is not symmetric per corner, but it stays
            // in the corner's octant.
            assert!(d.dot(n) > 0.5, "{d} {n}");
        }
    }

    #[test]
    fn flat_grid_and_fallbacks() {
        let g = grid(3, 3);
        let n = vertex_normals(&g.positions, &g.faces);
        let up = face_normal(g.triangle(0));
        assert!(up.z.abs() > 0.999);
        assert!(n.iter().all(|v| (*v - up).length() < 1e-6));
        // Unused vertex and degenerate face both fall back to +Z.
        let pos = vec![Vec3::ZERO, Vec3::X, Vec3::X * 2.0, Vec3::ONE];
        let n = vertex_normals(&pos, &[[0, 1, 2]]);
        assert!(n.iter().all(|&v| v == Vec3::Z));
        assert_eq!(face_normal([Vec3::ZERO, Vec3::X, Vec3::X]), Vec3::Z);
        assert_eq!(face_normal([Vec3::ZERO, Vec3::X, Vec3::Y]), Vec3::Z);
        assert_eq!(face_normal([Vec3::ZERO, Vec3::Y, Vec3::X]), -Vec3::Z);
    }

    #[test]
    fn opposite_faces_cancel_to_fallback() {
        let pos = vec![Vec3::ZERO, Vec3::X, Vec3::Y];
        let n = vertex_normals(&pos, &[[0, 1, 2], [0, 2, 1]]);
        assert!(n.iter().all(|&v| v == Vec3::Z));
    }
}
