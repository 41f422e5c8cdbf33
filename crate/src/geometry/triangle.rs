//! Distances to a triangle.

use std::borrow::Borrow;

use glam::{DVec3, Vec3};

use crate::Mesh;

/// Distance from `x` to the triangle `[a, b, c]` (its closest point, interior, edge or corner).
pub fn point_triangle_distance(x: DVec3, t: [DVec3; 3]) -> f64 {
    x.distance(closest_point(x, t).0)
}

/// The barycentric weights on `a`, `b` and `c` of the point of the triangle `[a, b, c]`
/// closest to `x`: the same weights on a moved triangle give where that point went.
pub fn closest_point_weights(x: DVec3, t: [DVec3; 3]) -> [f64; 3] {
    closest_point(x, t).1
}

/// Lower bounds of the distance from a point to the triangle `[a, b, c]`: the ball about its
/// centroid through its farthest corner, the slab of its plane, and the three half-spaces that
/// hold it, each bounded by a plane through one of its edges square to the triangle. A search
/// for the nearest of several triangles skips those that one of them already puts farther than
/// the best so far: the ball prunes far triangles, the edge planes a near triangle's coplanar
/// neighbours (which the ball of a large face does not).
#[derive(Clone, Copy, Debug)]
pub struct Bound {
    centre: DVec3,
    radius: f64,
    /// The unit normal, and the lowest and highest of the corners along it.
    normal: DVec3,
    along_normal: [f64; 2],
    /// Each edge's outward unit normal within the plane, and the highest of the corners along
    /// it (the edge's own, up to rounding).
    edges: [(DVec3, f64); 3],
}

impl Bound {
    /// The bounds of `t` (a triangle without area has a ball only).
    pub fn around(t: [DVec3; 3]) -> Self {
        let centre = (t[0] + t[1] + t[2]) / 3.0;
        let radius = t.iter().map(|&c| c.distance(centre)).fold(0.0, f64::max);
        // Each plane's offset is measured on the corners themselves, so that a normal rounded
        // off (a sliver's) still leaves the whole triangle inside its planes.
        let span = |m: DVec3| {
            let along = t.map(|c| m.dot(c));
            [
                along[0].min(along[1]).min(along[2]),
                along[0].max(along[1]).max(along[2]),
            ]
        };
        let normal = (t[1] - t[0]).cross(t[2] - t[0]).normalize_or_zero();
        let edges = [0, 1, 2].map(|i| {
            let m = (t[(i + 1) % 3] - t[i]).cross(normal).normalize_or_zero();
            (m, span(m)[1])
        });
        Bound {
            centre,
            radius,
            normal,
            along_normal: span(normal),
            edges,
        }
    }

    /// A lower bound of the distance from `x` to the triangle, a little below the exact one
    /// (by a relative 1e-9 of the ball's radius and the distance to its centre) so that
    /// rounding never makes it pass a true distance.
    pub fn distance_at_least(&self, x: DVec3) -> f64 {
        let d = x.distance(self.centre);
        let h = self.normal.dot(x);
        let slab = (h - self.along_normal[1]).max(self.along_normal[0] - h);
        let outside = (self.edges.iter())
            .map(|&(m, high)| m.dot(x) - high)
            .fold(slab, f64::max);
        (d - self.radius).max(outside) - 1e-9 * (d + self.radius)
    }
}

/// The nearest of `triangles` (each an id, and its corners with their [`Bound`], owned or
/// borrowed) to `x`: its distance and id, the first of equals (as `Iterator::min_by` picks).
/// `guess`, the index of a triangle likely to be near, is measured first; then a triangle whose
/// [`Bound`] is already farther than the best so far is skipped unmeasured. Neither changes the
/// answer, only its cost. (Borrowed, a search over faces bounded once, as the coverage guard's
/// reassignment makes for each input point, copies 24 bytes a face rather than 250.)
pub fn nearest_triangle<T: Copy, B: Borrow<([DVec3; 3], Bound)>>(
    x: DVec3,
    triangles: &[(T, B)],
    guess: Option<usize>,
) -> Option<(f64, T)> {
    // The best so far: distance and index, compared as (distance, index) so that the order
    // of measuring does not decide between equals.
    let mut best: Option<(f64, usize)> = guess.and_then(|g| {
        triangles
            .get(g)
            .map(|(_, tb)| (point_triangle_distance(x, tb.borrow().0), g))
    });
    for (i, (_, tb)) in triangles.iter().enumerate() {
        if Some(i) == guess {
            continue;
        }
        let &(t, bound) = tb.borrow();
        if let Some((d, _)) = best
            && bound.distance_at_least(x) > d
        {
            continue;
        }
        let d = point_triangle_distance(x, t);
        let better = best.is_none_or(|(b, j)| d.total_cmp(&b).then(i.cmp(&j)).is_lt());
        if better {
            best = Some((d, i));
        }
    }
    best.map(|(d, i)| (d, triangles[i].0))
}

/// Each of `points`' distance to the nearest face of `mesh` (infinite where it has none), by
/// [`nearest_triangle`] over all its faces, each point's search starting from the last point's
/// nearest face (near points in a row, as a k-d tree's order gives them, cost the least).
pub fn distances_to_faces(mesh: &Mesh, points: impl IntoIterator<Item = Vec3>) -> Vec<f64> {
    let faces: Vec<(usize, ([DVec3; 3], Bound))> = (mesh.faces.iter().enumerate())
        .map(|(i, f)| {
            let t = f.map(|v| mesh.positions[v as usize].as_dvec3());
            (i, (t, Bound::around(t)))
        })
        .collect();
    let mut guess = None;
    (points.into_iter())
        .map(|p| {
            let nearest = nearest_triangle(p.as_dvec3(), &faces, guess);
            guess = nearest.map(|(_, f)| f);
            nearest.map_or(f64::INFINITY, |(d, _)| d)
        })
        .collect()
}

/// The point of the triangle `[a, b, c]` closest to `x`, and its barycentric weights (after
/// Ericson, "Real-Time Collision Detection", 5.1.5).
fn closest_point(x: DVec3, [a, b, c]: [DVec3; 3]) -> (DVec3, [f64; 3]) {
    let (ab, ac, ax) = (b - a, c - a, x - a);
    let (d1, d2) = (ab.dot(ax), ac.dot(ax));
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, [1.0, 0.0, 0.0]);
    }
    let bx = x - b;
    let (d3, d4) = (ab.dot(bx), ac.dot(bx));
    if d3 >= 0.0 && d4 <= d3 {
        return (b, [0.0, 1.0, 0.0]);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (a + ab * v, [1.0 - v, v, 0.0]);
    }
    let cx = x - c;
    let (d5, d6) = (ab.dot(cx), ac.dot(cx));
    if d6 >= 0.0 && d5 <= d6 {
        return (c, [0.0, 0.0, 1.0]);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (a + ac * w, [1.0 - w, 0.0, w]);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (b + (c - b) * w, [0.0, 1.0 - w, w]);
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    (a + ab * v + ac * w, [1.0 - v - w, v, w])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    #[test]
    fn distances_to_faces_of_a_square_and_of_no_faces() {
        // The unit square at z = 0 in two triangles.
        let square = Mesh::new(
            vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
            vec![[0, 1, 2], [0, 2, 3]],
        );
        let points = [
            Vec3::new(0.25, 0.75, 0.5),
            Vec3::new(0.75, 0.25, -2.0),
            Vec3::new(2.0, 0.5, 0.0),
            Vec3::new(-3.0, -4.0, 0.0),
        ];
        let d = distances_to_faces(&square, points);
        for (got, want) in d.iter().zip([0.5, 2.0, 1.0, 5.0]) {
            assert!((got - want).abs() < 1e-6, "{d:?}");
        }
        let none = Mesh::new(square.positions.clone(), vec![]);
        assert!(
            distances_to_faces(&none, points)
                .iter()
                .all(|d| d.is_infinite())
        );
    }

    #[test]
    fn point_triangle_distance_regions() {
        let t = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let d = |x: [f64; 3]| point_triangle_distance(DVec3::from(x), t);
        assert!((d([0.2, 0.2, 0.5]) - 0.5).abs() < 1e-12, "interior");
        assert!(
            (d([-1.0, -1.0, 0.0]) - 2f64.sqrt()).abs() < 1e-12,
            "corner a"
        );
        assert!((d([2.0, 0.0, 0.0]) - 1.0).abs() < 1e-12, "corner b");
        assert!((d([0.0, 3.0, 0.0]) - 2.0).abs() < 1e-12, "corner c");
        assert!((d([0.5, -1.0, 0.0]) - 1.0).abs() < 1e-12, "edge ab");
        assert!((d([-2.0, 0.5, 0.0]) - 2.0).abs() < 1e-12, "edge ac");
        assert!(
            (d([1.0, 1.0, 0.0]) - 0.5f64.sqrt()).abs() < 1e-12,
            "edge bc"
        );
    }

    #[test]
    fn a_triangles_bound_never_passes_its_distance() {
        // Deterministic pseudo-random triangles and points, near and far, flat and thin.
        let mut rng = Rng::new(0x2545_f491_4f6c_dd1d);
        let mut next = || rng.next_f64() * 2.0 - 1.0;
        for i in 0..20_000 {
            let scale = if i % 2 == 0 { 1.0 } else { 1e-3 };
            let mut v = || DVec3::new(next(), next(), next()) * scale;
            let t = [v(), v(), v()];
            let x = DVec3::new(next(), next(), next()) * (1.0 + 3.0 * (i % 3) as f64) * scale;
            // Every third one a sliver: its third corner a hair off the line of the other two.
            let t = if i % 3 == 0 {
                [
                    t[0],
                    t[1],
                    t[0].lerp(t[1], next()) + DVec3::splat(1e-12 * scale),
                ]
            } else {
                t
            };
            let bound = Bound::around(t);
            assert!(
                bound.distance_at_least(x) <= point_triangle_distance(x, t),
                "{t:?} {x:?}"
            );
        }
        let t = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let far = DVec3::new(10.0, 0.0, 0.0);
        assert!(
            Bound::around(t).distance_at_least(far) > 8.0,
            "the ball is a useful bound"
        );
        // A point on a face, 0.3 inside its edge with a coplanar neighbour: the neighbour's
        // ball holds it, its edge plane puts it 0.3 away.
        let neighbour = [DVec3::X, DVec3::ZERO, DVec3::new(0.5, -1.0, 0.0)];
        let on = DVec3::new(0.5, 0.3, 0.0);
        assert!(Bound::around(neighbour).distance_at_least(on) > 0.29);
    }

    #[test]
    fn the_nearest_triangle_is_the_first_of_the_nearest_as_measuring_all() {
        let mut rng = Rng::new(0x9e37_79b9_7f4a_7c15);
        let mut next = || rng.next_f64() * 2.0 - 1.0;
        for _ in 0..2_000 {
            let mut tris: Vec<[DVec3; 3]> = (0..8)
                .map(|_| {
                    let c = DVec3::new(next(), next(), next());
                    let mut v = || c + DVec3::new(next(), next(), next()) * 0.2;
                    [v(), v(), v()]
                })
                .collect();
            // Equal distances: the first of them must win, as `min_by` picks.
            tris.push(tris[2]);
            let x = DVec3::new(next(), next(), next()) * 1.5;
            let all = tris
                .iter()
                .enumerate()
                .map(|(i, &t)| (point_triangle_distance(x, t), i))
                .min_by(|p, q| p.0.total_cmp(&q.0));
            let bounded: Vec<(usize, ([DVec3; 3], Bound))> = tris
                .iter()
                .enumerate()
                .map(|(i, &t)| (i, (t, Bound::around(t))))
                .collect();
            let borrowed: Vec<(usize, &([DVec3; 3], Bound))> =
                bounded.iter().map(|(i, tb)| (*i, tb)).collect();
            for guess in [None, Some(0), Some(2), Some(5), Some(8), Some(99)] {
                assert_eq!(nearest_triangle(x, &bounded, guess), all, "guess {guess:?}");
                assert_eq!(
                    nearest_triangle(x, &borrowed, guess),
                    all,
                    "guess {guess:?}"
                );
            }
        }
        assert_eq!(
            nearest_triangle::<u32, ([DVec3; 3], Bound)>(DVec3::ZERO, &[], Some(0)),
            None
        );
    }
}
