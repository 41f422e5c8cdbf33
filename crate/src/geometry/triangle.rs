//! Distances to a triangle.

use glam::DVec3;

/// Distance from `x` to the triangle `[a, b, c]` (its closest point, interior, edge or corner).
pub fn point_triangle_distance(x: DVec3, t: [DVec3; 3]) -> f64 {
    x.distance(closest_point(x, t).0)
}

/// The barycentric weights on `a`, `b` and `c` of the point of the triangle `[a, b, c]`
/// closest to `x`: the same weights on a moved triangle give where that point went.
pub fn closest_point_weights(x: DVec3, t: [DVec3; 3]) -> [f64; 3] {
    closest_point(x, t).1
}

/// A ball holding the triangle `[a, b, c]` (centred on its centroid): `x`'s distance to the
/// triangle is at least [`Ball::distance_at_least`], so a search for the nearest of several
/// triangles can skip those whose ball is already farther than the best so far.
#[derive(Clone, Copy, Debug)]
pub struct Ball {
    pub centre: DVec3,
    pub radius: f64,
}

impl Ball {
    /// The ball about the centroid of `t` through its farthest corner.
    pub fn around(t: [DVec3; 3]) -> Self {
        let centre = (t[0] + t[1] + t[2]) / 3.0;
        let radius = t.iter().map(|&c| c.distance(centre)).fold(0.0, f64::max);
        Ball { centre, radius }
    }

    /// A lower bound of the distance from `x` to anything inside the ball, a little below the
    /// exact one (by a relative 1e-9 of the radius and the distance) so that rounding never
    /// makes it pass a true distance.
    pub fn distance_at_least(&self, x: DVec3) -> f64 {
        let d = x.distance(self.centre);
        (d - self.radius) - 1e-9 * (d + self.radius)
    }
}

/// The nearest of `triangles` (each an id, its corners and its [`Ball`]) to `x`: its distance
/// and id, the first of equals (as `Iterator::min_by` picks). `guess`, the index of a triangle
/// likely to be near, is measured first; then a triangle whose ball is already farther than
/// the best so far is skipped unmeasured. Neither changes the answer, only its cost.
pub fn nearest_triangle<T: Copy>(
    x: DVec3,
    triangles: &[(T, [DVec3; 3], Ball)],
    guess: Option<usize>,
) -> Option<(f64, T)> {
    // The best so far: distance and index, compared as (distance, index) so that the order
    // of measuring does not decide between equals.
    let mut best: Option<(f64, usize)> = guess.and_then(|g| {
        triangles
            .get(g)
            .map(|&(_, t, _)| (point_triangle_distance(x, t), g))
    });
    for (i, &(_, t, ball)) in triangles.iter().enumerate() {
        if Some(i) == guess {
            continue;
        }
        if let Some((d, _)) = best
            && ball.distance_at_least(x) > d
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
    fn a_triangles_ball_never_passes_its_distance() {
        // Deterministic pseudo-random triangles and points, near and far, flat and thin.
        let mut rng = Rng::new(0x2545_f491_4f6c_dd1d);
        let mut next = || rng.next_f64() * 2.0 - 1.0;
        for i in 0..20_000 {
            let scale = if i % 2 == 0 { 1.0 } else { 1e-3 };
            let mut v = || DVec3::new(next(), next(), next()) * scale;
            let t = [v(), v(), v()];
            let x = DVec3::new(next(), next(), next()) * (1.0 + 3.0 * (i % 3) as f64) * scale;
            let ball = Ball::around(t);
            assert!(
                ball.distance_at_least(x) <= point_triangle_distance(x, t),
                "{t:?} {x:?}"
            );
        }
        let t = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let far = DVec3::new(10.0, 0.0, 0.0);
        assert!(
            Ball::around(t).distance_at_least(far) > 8.0,
            "the bound is a useful one"
        );
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
            let bounded: Vec<(usize, [DVec3; 3], Ball)> = tris
                .iter()
                .enumerate()
                .map(|(i, &t)| (i, t, Ball::around(t)))
                .collect();
            for guess in [None, Some(0), Some(2), Some(5), Some(8), Some(99)] {
                assert_eq!(nearest_triangle(x, &bounded, guess), all, "guess {guess:?}");
            }
        }
        assert_eq!(nearest_triangle::<u32>(DVec3::ZERO, &[], Some(0)), None);
    }
}
