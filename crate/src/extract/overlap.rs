//! Faces lying on top of each other without sharing an edge: the test that keeps a surface
//! one layer thick.
//!
//! The manifold extraction's edge tests (at most two faces an edge, no fold across an edge)
//! see only faces that share an edge. Two faces that share one vertex or none can still cover
//! the same patch of surface, one a little above the other: a second layer, the "shards" a
//! viewer sees, and the reason such a mesh has far more faces than its vertices allow
//! (a single-layer surface has at most about two faces per vertex). [`FaceLayers`] holds the
//! accepted faces in an R-tree of their bounding boxes and refuses a new face that, seen
//! along its own normal, overlaps an accepted one lying within `tolerance` of its plane.
//!
//! The overlap test, for a new face `f` and an accepted face `g` sharing at most one vertex:
//! `g` is near-parallel to `f` (normals within 60 degrees, either orientation: windings are
//! not final while faces are being chosen) and each of `g`'s vertices is within `tolerance`
//! times `f`'s longest edge of `f`'s plane; then both are projected onto that plane and
//! tested by separating axes (the six edge normals), where intervals that overlap by less than
//! a millionth of the face's size count as separate, so faces that only touch at a vertex or
//! along a line do not overlap.

use glam::{Vec2, Vec3};
use rstar::primitives::{GeomWithData, Rectangle};
use rstar::{AABB, RTree};

use crate::extract::manifold::unit_normal;

type Boxed = GeomWithData<Rectangle<[f32; 3]>, [u32; 3]>;

/// Smallest |cosine| between two faces' normals for them to count as lying on each other.
const PARALLEL_COS: f32 = 0.5;

/// The accepted faces, for [`FaceLayers::overlaps`].
pub struct FaceLayers {
    tree: RTree<Boxed>,
    tolerance: f32,
    /// Count only faces wound the same way (normals within 60 degrees, not either
    /// orientation): for faces whose windings are final, where the far side of a thin part
    /// faces away and is no second layer.
    oriented: bool,
}

impl FaceLayers {
    /// No faces yet; `tolerance` is the largest distance from a face's plane, in its longest
    /// edges, at which another face counts as lying on it (0 or less: nothing ever overlaps).
    pub fn new(tolerance: f32) -> Self {
        Self {
            tree: RTree::new(),
            tolerance,
            oriented: false,
        }
    }

    /// [`FaceLayers::new`] for wound faces: a face facing the other way is not on the same
    /// layer (the far side of a thin part).
    pub fn oriented(tolerance: f32) -> Self {
        Self {
            oriented: true,
            ..Self::new(tolerance)
        }
    }

    fn boxed(positions: &[Vec3], face: [u32; 3]) -> Boxed {
        let [a, b, c] = face.map(|v| positions[v as usize]);
        let lo = a.min(b).min(c);
        let hi = a.max(b).max(c);
        GeomWithData::new(Rectangle::from_corners(lo.to_array(), hi.to_array()), face)
    }

    /// Records `face` as accepted.
    pub fn insert(&mut self, positions: &[Vec3], face: [u32; 3]) {
        if self.tolerance > 0.0 {
            self.tree.insert(Self::boxed(positions, face));
        }
    }

    /// Forgets an accepted `face` (its vertices in the order it was inserted with).
    pub fn remove(&mut self, positions: &[Vec3], face: [u32; 3]) {
        if self.tolerance > 0.0 {
            self.tree.remove(&Self::boxed(positions, face));
        }
    }

    /// Whether `face` overlaps an accepted face that shares at most one vertex with it (see
    /// the module documentation).
    pub fn overlaps(&self, positions: &[Vec3], face: [u32; 3]) -> bool {
        if self.tolerance <= 0.0 {
            return false;
        }
        let [a, b, c] = face.map(|v| positions[v as usize]);
        let normal = unit_normal(positions, face);
        if normal == Vec3::ZERO {
            return false;
        }
        let size = a.distance(b).max(b.distance(c)).max(c.distance(a));
        let reach = self.tolerance * size;
        let lo = a.min(b).min(c) - Vec3::splat(reach);
        let hi = a.max(b).max(c) + Vec3::splat(reach);
        let envelope = AABB::from_corners(lo.to_array(), hi.to_array());
        let (u, v) = normal.any_orthonormal_pair();
        let flat = |p: Vec3| Vec2::new((p - a).dot(u), (p - a).dot(v));
        let mine = [a, b, c].map(flat);
        self.tree
            .locate_in_envelope_intersecting(envelope)
            .any(|other| {
                let g = other.data;
                if g.iter().filter(|v| face.contains(v)).count() >= 2 {
                    return false;
                }
                let cos = unit_normal(positions, g).dot(normal);
                if (if self.oriented { cos } else { cos.abs() }) < PARALLEL_COS {
                    return false;
                }
                let corners = g.map(|v| positions[v as usize]);
                if corners.iter().any(|&x| (x - a).dot(normal).abs() > reach) {
                    return false;
                }
                triangles_overlap(mine, corners.map(flat), size * 1e-6)
            })
    }
}

/// Whether two 2-D triangles' interiors overlap by more than `eps` along every separating
/// axis candidate (their six edge normals).
fn triangles_overlap(s: [Vec2; 3], t: [Vec2; 3], eps: f32) -> bool {
    let axes = [s, t].into_iter().flat_map(|tri| {
        (0..3).map(move |k| {
            let e = tri[(k + 1) % 3] - tri[k];
            Vec2::new(-e.y, e.x)
        })
    });
    for axis in axes {
        let len = axis.length();
        if len <= 0.0 {
            continue;
        }
        let axis = axis / len;
        let span = |tri: [Vec2; 3]| {
            let d = tri.map(|p| p.dot(axis));
            (d[0].min(d[1]).min(d[2]), d[0].max(d[1]).max(d[2]))
        };
        let (s0, s1) = span(s);
        let (t0, t1) = span(t);
        if s1.min(t1) - s0.max(t0) <= eps {
            return false;
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    fn positions() -> Vec<Vec3> {
        vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            // A copy of the first triangle shifted a little up and sideways.
            Vec3::new(0.2, 0.2, 0.05),
            Vec3::new(1.2, 0.2, 0.05),
            Vec3::new(0.2, 1.2, 0.05),
            // The neighbour across the edge 1-2, and one that touches at vertex 1 only.
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(2.0, -1.0, 0.0),
            // The first triangle far above: a real second surface (a thick part's far side).
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(1.0, 0.0, 1.0),
            Vec3::new(0.0, 1.0, 1.0),
        ]
    }

    #[test]
    fn a_second_layer_overlaps_but_neighbours_and_far_sides_do_not() {
        let p = positions();
        let mut layers = FaceLayers::new(0.2);
        layers.insert(&p, [0, 1, 2]);
        assert!(layers.overlaps(&p, [3, 4, 5]));
        assert!(layers.overlaps(&p, [3, 5, 4]), "either winding");
        assert!(!layers.overlaps(&p, [1, 6, 2]), "shares an edge");
        assert!(!layers.overlaps(&p, [1, 7, 8]), "touches at a vertex");
        assert!(
            !layers.overlaps(&p, [9, 10, 11]),
            "a surface a whole edge away"
        );
        layers.remove(&p, [0, 1, 2]);
        assert!(!layers.overlaps(&p, [3, 4, 5]));
        assert!(!FaceLayers::new(0.0).overlaps(&p, [3, 4, 5]));
    }

    #[test]
    fn separating_axes() {
        let tri = [Vec2::ZERO, Vec2::X, Vec2::Y];
        let inside = [Vec2::splat(0.1), Vec2::new(0.3, 0.1), Vec2::new(0.1, 0.3)];
        let beside = [Vec2::X, Vec2::new(2.0, 0.0), Vec2::new(1.0, 1.0)];
        assert!(triangles_overlap(tri, inside, 1e-6));
        assert!(!triangles_overlap(tri, beside, 1e-6));
    }
}
