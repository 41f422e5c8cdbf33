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
}
