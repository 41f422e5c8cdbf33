//! Sharp edges: the creases and corners that make a low-poly mesh read as designed.
//!
//! An edge is sharp when exactly two faces share it and their normals differ by more than an
//! angle (30 degrees for the metrics of docs/design.md section 3). Boundary edges and edges of
//! three or more faces are never sharp. The two normals are compared as the faces would be
//! wound consistently: where both faces walk the edge in the same direction (inconsistent
//! winding, common in imported game assets), one normal is turned round first, so a flat
//! region with a flipped triangle is not a crease. The angle is computed in `f64` and must
//! exceed the limit by a thousandth of a degree, so that an edge at exactly the limit (the
//! sides of a 12-sided prism meet at 30 degrees) is not a crease on one machine and flat on
//! another.

use glam::{DVec3, Vec3};

use crate::geometry::topology::{Edge, EdgeIncidence};

/// The dihedral angle above which the metrics call an edge sharp, in degrees.
pub const SHARP_ANGLE_DEG: f32 = 30.0;

/// The edges of `faces` over `positions` whose two faces' normals differ by more than
/// `angle_deg` degrees (see the module documentation), sorted. Degenerate faces (no normal)
/// make no edge sharp.
pub fn sharp_edges(positions: &[Vec3], faces: &[[u32; 3]], angle_deg: f32) -> Vec<Edge> {
    let cos_limit = (f64::from(angle_deg) + 1e-3).to_radians().cos();
    let normals: Vec<Option<DVec3>> = faces
        .iter()
        .map(|f| {
            let [a, b, c] = f.map(|i| positions[i as usize].as_dvec3());
            (b - a).cross(c - a).try_normalize()
        })
        .collect();
    EdgeIncidence::new(faces)
        .iter()
        .filter_map(|(edge, uses)| {
            let [a, b] = uses else { return None };
            let na = normals[a.face as usize]?;
            let mut nb = normals[b.face as usize]?;
            if a.forward == b.forward {
                nb = -nb;
            }
            (na.dot(nb) < cos_limit).then_some(edge)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::primitives::{cube, grid, icosphere};

    #[test]
    fn a_cube_has_twelve_sharp_edges_and_a_sphere_none() {
        let c = cube();
        assert_eq!(
            sharp_edges(&c.positions, &c.faces, SHARP_ANGLE_DEG).len(),
            12
        );
        let s = icosphere(3);
        assert!(sharp_edges(&s.positions, &s.faces, SHARP_ANGLE_DEG).is_empty());
        // An open flat grid: boundary edges are not sharp, interior edges are flat.
        let g = grid(3, 3);
        assert!(sharp_edges(&g.positions, &g.faces, SHARP_ANGLE_DEG).is_empty());
    }

    #[test]
    fn inconsistent_winding_is_not_a_crease() {
        let mut g = grid(2, 1);
        // Flip one triangle: the flat grid must stay without sharp edges.
        g.faces[1].swap(1, 2);
        assert!(sharp_edges(&g.positions, &g.faces, SHARP_ANGLE_DEG).is_empty());
        // Fold the grid by 90 degrees along x = 0.5: the fold line's interior edge is sharp.
        let mut g = grid(2, 1);
        for p in &mut g.positions {
            if p.x > 0.5 {
                *p = Vec3::new(0.5, p.y, p.x - 0.5);
            }
        }
        assert_eq!(
            sharp_edges(&g.positions, &g.faces, SHARP_ANGLE_DEG),
            vec![[1, 4]]
        );
    }
}
