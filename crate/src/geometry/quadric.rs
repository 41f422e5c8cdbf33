//! Quadric error of a point against a set of planes, and its rank-truncated minimiser.
//!
//! A plane through `p` with unit normal `n` gives the squared distance `(n . (x - p))^2`; a sum
//! of such terms is the quadric `x^T A x - 2 b^T x + c` with `A = sum n n^T` and
//! `b = sum n (n . p)`. Garland and Heckbert's quadric decimation ("Surface Simplification Using
//! Quadric Error Metrics", SIGGRAPH 1997) sums the planes of a vertex's faces; dual contouring
//! (Ju et al., SIGGRAPH 2002) solves the same system for the planes of nearby samples, with the
//! small eigenvalues of `A` truncated: on a flat region only the normal direction is
//! constrained, so the point moves across the plane and nowhere else; on a crease two directions
//! are, and the point snaps onto the crease line; at a corner all three, and it snaps onto the
//! corner. Hand-written: no maintained crate offers this 3x3 system with truncation.

use glam::{DMat3, DVec3};

/// `x^T A x - 2 b^T x + c`, the summed squared distance to weighted planes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quadric {
    pub a: DMat3,
    pub b: DVec3,
    pub c: f64,
    /// Sum of the planes' weights (for a mean squared distance).
    pub weight: f64,
}

impl Default for Quadric {
    /// No plane (all zero; glam's own default matrix is the identity, not zero).
    fn default() -> Self {
        Quadric {
            a: DMat3::ZERO,
            b: DVec3::ZERO,
            c: 0.0,
            weight: 0.0,
        }
    }
}

impl std::ops::Add for Quadric {
    type Output = Quadric;

    fn add(self, o: Quadric) -> Quadric {
        Quadric {
            a: self.a + o.a,
            b: self.b + o.b,
            c: self.c + o.c,
            weight: self.weight + o.weight,
        }
    }
}

impl std::ops::AddAssign for Quadric {
    fn add_assign(&mut self, o: Quadric) {
        *self = *self + o;
    }
}

impl Quadric {
    /// The squared distance to the plane through `point` with unit `normal`, times `weight`.
    pub fn plane(normal: DVec3, point: DVec3, weight: f64) -> Self {
        let d = normal.dot(point);
        Quadric {
            a: DMat3::from_cols(normal * normal.x, normal * normal.y, normal * normal.z) * weight,
            b: normal * (d * weight),
            c: d * d * weight,
            weight,
        }
    }

    /// The quadric's value at `x` (never below 0 up to rounding).
    pub fn error(&self, x: DVec3) -> f64 {
        (x.dot(self.a * x) - 2.0 * self.b.dot(x) + self.c).max(0.0)
    }

    /// The point nearest `origin` among the minimisers of the quadric, where the eigenvalues of
    /// `A` below `relative_cutoff` times the largest count as zero (those directions are left
    /// where `origin` puts them). With no plane at all, `origin`.
    pub fn minimiser_near(&self, origin: DVec3, relative_cutoff: f64) -> DVec3 {
        let (values, vectors) = symmetric_eigen(self.a);
        let largest = values.iter().copied().fold(0.0, f64::max);
        if largest <= 0.0 {
            return origin;
        }
        // Solve A (origin + d) = b for d in the kept eigendirections.
        let residual = self.b - self.a * origin;
        let mut x = origin;
        for (k, &value) in values.iter().enumerate() {
            if value > relative_cutoff * largest {
                let v = vectors.col(k);
                x += v * (v.dot(residual) / value);
            }
        }
        x
    }

    /// The minimiser of the quadric plus `damping` times the largest diagonal entry of `A`
    /// times the squared distance to `origin`: one 3x3 solve, no eigenvectors, for the many
    /// candidates of a decimation. Directions the planes leave free stay near `origin`, as
    /// with [`Self::minimiser_near`]; `origin` where there is no plane or no solution.
    pub fn damped_minimiser(&self, origin: DVec3, damping: f64) -> DVec3 {
        let scale = self.a.x_axis.x.max(self.a.y_axis.y).max(self.a.z_axis.z);
        if scale.is_nan() || scale <= 0.0 {
            return origin;
        }
        let eps = damping * scale;
        let m = self.a + DMat3::from_diagonal(DVec3::splat(eps));
        let det = m.determinant();
        if det.is_nan() || det.abs() <= 1e-300 {
            return origin;
        }
        let x = m.inverse() * (self.b + origin * eps);
        if x.is_finite() { x } else { origin }
    }

    /// How many eigenvalues of `A` exceed `relative_cutoff` times the largest: 1 on a flat
    /// region, 2 on a crease, 3 at a corner, 0 without planes.
    pub fn rank(&self, relative_cutoff: f64) -> usize {
        let (values, _) = symmetric_eigen(self.a);
        let largest = values.iter().copied().fold(0.0, f64::max);
        if largest <= 0.0 {
            return 0;
        }
        values
            .iter()
            .filter(|&&v| v > relative_cutoff * largest)
            .count()
    }
}

/// Eigenvalues, ascending, of a symmetric 3x3 matrix ([`symmetric_eigen`]'s rotations: no
/// trigonometry, so the same bits natively and inside WebAssembly, where the platforms' `acos`
/// and `cos` may differ in the last place).
pub fn symmetric_eigenvalues(a: [[f64; 3]; 3]) -> [f64; 3] {
    let (mut values, _) = symmetric_eigen(DMat3::from_cols_array_2d(&a));
    values.sort_by(f64::total_cmp);
    values
}

/// Eigenvalues and unit eigenvectors (the matrix's columns, in the same order) of a symmetric
/// 3x3 matrix, by cyclic Jacobi rotations (converges to machine precision in a few sweeps).
pub fn symmetric_eigen(m: DMat3) -> ([f64; 3], DMat3) {
    let mut a = m.to_cols_array_2d();
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _sweep in 0..32 {
        let off = a[0][1].powi(2) + a[0][2].powi(2) + a[1][2].powi(2);
        let diag = a[0][0].powi(2) + a[1][1].powi(2) + a[2][2].powi(2);
        if off <= 1e-30 * diag.max(1e-300) {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q].abs() < 1e-300 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            // A <- J^T A J with J the rotation in the (p, q) plane.
            for row in a.iter_mut() {
                let (x, y) = (row[p], row[q]);
                row[p] = c * x - s * y;
                row[q] = s * x + c * y;
            }
            let (rp, rq) = (a[p], a[q]);
            a[p] = std::array::from_fn(|k| c * rp[k] - s * rq[k]);
            a[q] = std::array::from_fn(|k| s * rp[k] + c * rq[k]);
            for row in v.iter_mut() {
                let (x, y) = (row[p], row[q]);
                row[p] = c * x - s * y;
                row[q] = s * x + c * y;
            }
        }
    }
    // `v` is built row by row as V (columns are eigenvectors); DMat3 wants columns.
    let vectors = DMat3::from_cols(
        DVec3::new(v[0][0], v[1][0], v[2][0]),
        DVec3::new(v[0][1], v[1][1], v[2][1]),
        DVec3::new(v[0][2], v[1][2], v[2][2]),
    );
    ([a[0][0], a[1][1], a[2][2]], vectors)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eigenvalues_of_a_known_matrix_ascending() {
        let e = symmetric_eigenvalues([[5.0, 0.0, 0.0], [0.0, 2.0, 1.0], [0.0, 1.0, 2.0]]);
        for (got, want) in e.iter().zip([1.0, 3.0, 5.0]) {
            assert!((got - want).abs() < 1e-9, "{e:?}");
        }
    }

    #[test]
    fn eigen_decomposition_reconstructs_the_matrix() {
        let m = DMat3::from_cols_array_2d(&[[4.0, 1.0, -2.0], [1.0, 3.0, 0.5], [-2.0, 0.5, 1.0]]);
        let (values, vectors) = symmetric_eigen(m);
        for (k, &value) in values.iter().enumerate() {
            let v = vectors.col(k);
            assert!((v.length() - 1.0).abs() < 1e-12);
            assert!((m * v - v * value).length() < 1e-10, "{k}");
        }
    }

    #[test]
    fn truncation_keeps_a_flat_point_in_place_and_snaps_to_creases_and_corners() {
        let plane = |n: DVec3, p: DVec3| Quadric::plane(n.normalize(), p, 1.0);
        let origin = DVec3::new(0.3, 0.2, 0.1);
        // One plane z = 0: only z changes.
        let flat = plane(DVec3::Z, DVec3::ZERO) + plane(DVec3::Z, DVec3::X);
        assert_eq!(flat.rank(0.05), 1);
        let x = flat.minimiser_near(origin, 0.05);
        assert!((x - DVec3::new(0.3, 0.2, 0.0)).length() < 1e-12, "{x}");
        // Two planes z = 0 and y = 0: onto the x axis, x kept.
        let crease = flat + plane(DVec3::Y, DVec3::ZERO);
        assert_eq!(crease.rank(0.05), 2);
        let x = crease.minimiser_near(origin, 0.05);
        assert!((x - DVec3::new(0.3, 0.0, 0.0)).length() < 1e-12, "{x}");
        // Three: the corner.
        let corner = crease + plane(DVec3::X, DVec3::ZERO);
        let x = corner.minimiser_near(origin, 0.05);
        assert!(x.length() < 1e-12, "{x}");
        assert!(corner.error(x) < 1e-20 && corner.error(origin) > 0.0);
        // A slightly tilted second plane is noise below the cutoff: the point stays flat.
        let noisy = flat + plane(DVec3::new(0.0, 0.01, 1.0), DVec3::ZERO);
        assert_eq!(noisy.rank(0.05), 1);
        assert_eq!(Quadric::default().minimiser_near(origin, 0.05), origin);
        // Damped: the crease point up to the damping's pull towards the origin.
        let x = crease.damped_minimiser(origin, 1e-6);
        assert!((x - DVec3::new(0.3, 0.0, 0.0)).length() < 1e-5, "{x}");
        assert_eq!(Quadric::default().damped_minimiser(origin, 1e-3), origin);
    }
}
