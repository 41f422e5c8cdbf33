//! The plane that fits a set of points best: their covariance and its direction of least
//! spread. Fitting, completion, the planar regions, sharpening and the budget rule all read a
//! neighbourhood's plane this way.

use glam::DVec3;

use crate::geometry::quadric::symmetric_eigenvalues;

/// The covariance matrix of `points` (non-empty), normalised by their count.
pub(crate) fn covariance(points: &[DVec3]) -> [[f64; 3]; 3] {
    let n = points.len() as f64;
    let mean = points.iter().copied().sum::<DVec3>() / n;
    let mut c = [[0.0f64; 3]; 3];
    for p in points {
        let d = (*p - mean).to_array();
        for (i, row) in c.iter_mut().enumerate() {
            for (j, x) in row.iter_mut().enumerate() {
                *x += d[i] * d[j] / n;
            }
        }
    }
    c
}

/// The unit eigenvector of the points' covariance with the smallest eigenvalue (the normal of
/// the plane that fits them best), or `None` when they do not span a plane's worth of
/// directions (fewer than 3 points, or all on one line).
pub(crate) fn least_spread_direction(points: &[DVec3]) -> Option<DVec3> {
    if points.len() < 3 {
        return None;
    }
    let c = covariance(points);
    let [smallest, middle, _] = symmetric_eigenvalues(c);
    // A line (or a point): the middle eigenvalue is zero too, and no plane is defined.
    if middle <= 1e-12 * (c[0][0] + c[1][1] + c[2][2]).max(1e-300) {
        return None;
    }
    // The eigenvector is orthogonal to the rows of C - lambda I: the longest cross product of
    // two of them.
    let rows = [0, 1, 2].map(|i| {
        let mut r = DVec3::from_array(c[i]);
        r[i] -= smallest;
        r
    });
    [
        rows[0].cross(rows[1]),
        rows[1].cross(rows[2]),
        rows[2].cross(rows[0]),
    ]
    .into_iter()
    .max_by(|a, b| a.length_squared().total_cmp(&b.length_squared()))
    .and_then(|v| v.try_normalize())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn covariance_is_the_spread_about_the_mean() {
        // Four points at x = 1 +- 1, y = +-2, z = 5: variance 1 in x, 4 in y, none in z, and
        // no correlation; the mean does not count.
        let points =
            [(0.0, -2.0), (2.0, -2.0), (0.0, 2.0), (2.0, 2.0)].map(|(x, y)| DVec3::new(x, y, 5.0));
        let c = covariance(&points);
        let expected = [[1.0, 0.0, 0.0], [0.0, 4.0, 0.0], [0.0, 0.0, 0.0]];
        for (row, want) in c.iter().zip(expected) {
            for (x, w) in row.iter().zip(want) {
                assert!((x - w).abs() < 1e-12, "{c:?}");
            }
        }
        assert_eq!(
            least_spread_direction(&points).map(|n| n.z.abs()),
            Some(1.0)
        );
    }

    #[test]
    fn points_on_a_line_define_no_plane() {
        let line: Vec<DVec3> = (0..10).map(|i| DVec3::new(i as f64, 0.0, 0.0)).collect();
        assert_eq!(least_spread_direction(&line), None);
        let plane: Vec<DVec3> = (0..16)
            .map(|i| DVec3::new((i % 4) as f64, (i / 4) as f64, 0.0))
            .collect();
        let n = least_spread_direction(&plane).unwrap();
        assert!((n.z.abs() - 1.0).abs() < 1e-9);
    }
}
