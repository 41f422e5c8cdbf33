//! The default vertex budget of a generation, from the input point cloud alone.
//!
//! Artists spend vertices on size and on curvature: a large flat wall needs few, a small
//! detailed prop many per unit area. Two features of the model-frame point cloud capture that:
//! - **occupancy** `A`: occupied cells of the 32^3 conditioning grid (a surface-area proxy that
//!   a point cloud without faces still has);
//! - **surface variation** `C`: the mean over sampled points of `l0 / (l0 + l1 + l2)`, the
//!   smallest eigenvalue share of the covariance of the point's 16 nearest neighbours (0 on a
//!   plane, up to 1/3 where the surface bends in every direction). At that scale smooth
//!   curvature barely registers; creases and corners do, and they are where artists put
//!   vertices.
//!
//! The rule is `V = exp(a + b ln A + c C)`, clamped to `[MIN_BUDGET, max]`, with `a, b, c` a
//! least-squares fit of `ln V` over the training meshes that fit the shipped VAE
//! (`meshflow eval budget --split train`, figures in BENCHMARKS.md).

use glam::{DVec3, Vec3};
use rstar::RTree;
use rstar::primitives::GeomWithData;
use serde::{Deserialize, Serialize};

use crate::geometry::voxel::voxel_index;
use crate::rng::Rng;

/// Neighbours per local covariance.
const NEIGHBOURS: usize = 16;
/// Points whose neighbourhoods are averaged into the surface variation.
const VARIATION_SAMPLES: usize = 512;
/// The smallest default budget: below it the VAE's mask makes too few vertices for a shape.
pub const MIN_BUDGET: usize = 16;

/// What the default budget is computed from.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShapeFeatures {
    /// Occupied cells of the 32^3 grid over [-1, 1]^3.
    pub occupied_voxels: usize,
    /// Mean smallest-eigenvalue share of local covariances, in [0, 1/3].
    pub surface_variation: f64,
}

/// Coefficients of `ln V = a + b ln A + c C`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct BudgetRule {
    pub intercept: f64,
    pub occupancy_exponent: f64,
    pub variation_weight: f64,
}

/// The shipped rule: fitted by `meshflow eval budget --split train --data <pipeline-3 build>`
/// on the 3,806 training meshes of at most 512 vertices. The fit is weak (R^2 0.10 in log
/// space; the median budget misses the artist's count by a factor of 2): artists' vertex
/// counts depend on more than size and curvature, so `--vertices` is there to override it.
pub const DEFAULT_RULE: BudgetRule = BudgetRule {
    intercept: 3.9559,
    occupancy_exponent: 0.0619,
    variation_weight: 8.4494,
};

/// Measures [`ShapeFeatures`] of model-frame points (any count; seeded subsampling for the
/// neighbourhoods). An empty input gives zero features.
pub fn shape_features(points: &[Vec3], seed: u64) -> ShapeFeatures {
    let mut cells: Vec<[u32; 3]> = points.iter().map(|&p| voxel_index(p)).collect();
    cells.sort_unstable();
    cells.dedup();
    if points.len() < NEIGHBOURS {
        return ShapeFeatures {
            occupied_voxels: cells.len(),
            surface_variation: 0.0,
        };
    }
    let tree = RTree::bulk_load(
        points
            .iter()
            .map(|p| GeomWithData::new(p.to_array(), ()))
            .collect(),
    );
    let mut rng = Rng::new(seed);
    let queries = VARIATION_SAMPLES.min(points.len());
    let mut total = 0.0;
    for _ in 0..queries {
        let q = points[rng.below(points.len())];
        let near: Vec<DVec3> = tree
            .nearest_neighbor_iter(q.to_array())
            .take(NEIGHBOURS)
            .map(|g| Vec3::from_array(*g.geom()).as_dvec3())
            .collect();
        total += smallest_eigenvalue_share(&near);
    }
    ShapeFeatures {
        occupied_voxels: cells.len(),
        surface_variation: total / queries as f64,
    }
}

/// `l0 / (l0 + l1 + l2)` of the points' covariance (0 for coincident points).
fn smallest_eigenvalue_share(points: &[DVec3]) -> f64 {
    let c = covariance(points);
    let trace = c[0][0] + c[1][1] + c[2][2];
    if trace <= 1e-18 {
        return 0.0;
    }
    (symmetric_eigenvalues(c)[0] / trace).clamp(0.0, 1.0 / 3.0)
}

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

/// Eigenvalues, ascending, of a symmetric 3x3 matrix (closed form, trigonometric).
pub(crate) fn symmetric_eigenvalues(a: [[f64; 3]; 3]) -> [f64; 3] {
    let p1 = a[0][1].powi(2) + a[0][2].powi(2) + a[1][2].powi(2);
    let q = (a[0][0] + a[1][1] + a[2][2]) / 3.0;
    if p1 <= 1e-30 {
        let mut d = [a[0][0], a[1][1], a[2][2]];
        d.sort_by(f64::total_cmp);
        return d;
    }
    let p2 = (a[0][0] - q).powi(2) + (a[1][1] - q).powi(2) + (a[2][2] - q).powi(2) + 2.0 * p1;
    let p = (p2 / 6.0).sqrt();
    let b = |i: usize, j: usize| (a[i][j] - if i == j { q } else { 0.0 }) / p;
    let det = b(0, 0) * (b(1, 1) * b(2, 2) - b(1, 2) * b(2, 1))
        - b(0, 1) * (b(1, 0) * b(2, 2) - b(1, 2) * b(2, 0))
        + b(0, 2) * (b(1, 0) * b(2, 1) - b(1, 1) * b(2, 0));
    let phi = (det / 2.0).clamp(-1.0, 1.0).acos() / 3.0;
    let largest = q + 2.0 * p * phi.cos();
    let smallest = q + 2.0 * p * (phi + 2.0 * std::f64::consts::PI / 3.0).cos();
    [smallest, 3.0 * q - largest - smallest, largest]
}

impl BudgetRule {
    /// The budget for `features`, clamped to `[MIN_BUDGET, max]` (`max` is the VAE's N).
    pub fn budget(&self, features: &ShapeFeatures, max: usize) -> usize {
        let a = (features.occupied_voxels.max(1) as f64).ln();
        let v = (self.intercept
            + self.occupancy_exponent * a
            + self.variation_weight * features.surface_variation)
            .exp();
        (v.round() as usize).clamp(MIN_BUDGET.min(max), max)
    }

    /// Least-squares fit of `ln V` over `(features, vertex count)` pairs, with R^2 of the fit in
    /// log space. `None` with fewer than 3 examples or a singular system.
    pub fn fit(examples: &[(ShapeFeatures, usize)]) -> Option<(BudgetRule, f64)> {
        if examples.len() < 3 {
            return None;
        }
        let rows: Vec<([f64; 3], f64)> = examples
            .iter()
            .map(|(f, v)| {
                (
                    [
                        1.0,
                        (f.occupied_voxels.max(1) as f64).ln(),
                        f.surface_variation,
                    ],
                    (*v.max(&1) as f64).ln(),
                )
            })
            .collect();
        let mut ata = [[0.0; 3]; 3];
        let mut atb = [0.0; 3];
        for (x, y) in &rows {
            for i in 0..3 {
                atb[i] += x[i] * y;
                for j in 0..3 {
                    ata[i][j] += x[i] * x[j];
                }
            }
        }
        let coef = solve3(ata, atb)?;
        let mean = rows.iter().map(|r| r.1).sum::<f64>() / rows.len() as f64;
        let (mut ss_res, mut ss_tot) = (0.0, 0.0);
        for (x, y) in &rows {
            let pred = coef[0] * x[0] + coef[1] * x[1] + coef[2] * x[2];
            ss_res += (y - pred).powi(2);
            ss_tot += (y - mean).powi(2);
        }
        let rule = BudgetRule {
            intercept: coef[0],
            occupancy_exponent: coef[1],
            variation_weight: coef[2],
        };
        Some((rule, 1.0 - ss_res / ss_tot.max(1e-30)))
    }
}

/// Solves a 3x3 system by Gaussian elimination with partial pivoting.
fn solve3(mut a: [[f64; 3]; 3], mut b: [f64; 3]) -> Option<[f64; 3]> {
    for col in 0..3 {
        let pivot = (col..3).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        if a[pivot][col].abs() < 1e-12 {
            return None;
        }
        a.swap(col, pivot);
        b.swap(col, pivot);
        for row in col + 1..3 {
            let f = a[row][col] / a[col][col];
            let pivot_row = a[col];
            for (x, p) in a[row].iter_mut().zip(pivot_row).skip(col) {
                *x -= f * p;
            }
            b[row] -= f * b[col];
        }
    }
    let mut x = [0.0; 3];
    for row in (0..3).rev() {
        let s: f64 = (row + 1..3).map(|k| a[row][k] * x[k]).sum();
        x[row] = (b[row] - s) / a[row][row];
    }
    Some(x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::primitives::{cube, grid};
    use crate::geometry::sample::sample_surface;

    #[test]
    fn eigenvalues_of_a_known_matrix() {
        let e = symmetric_eigenvalues([[2.0, 1.0, 0.0], [1.0, 2.0, 0.0], [0.0, 0.0, 5.0]]);
        for (got, want) in e.iter().zip([1.0, 3.0, 5.0]) {
            assert!((got - want).abs() < 1e-9, "{e:?}");
        }
    }

    #[test]
    fn a_plane_is_flat_and_a_small_cube_creased() {
        let plane = sample_surface(&grid(8, 8), 4096, 1).unwrap().points;
        let cube: Vec<Vec3> = sample_surface(&cube(), 4096, 1)
            .unwrap()
            .points
            .iter()
            .map(|&p| p * 0.1)
            .collect();
        let flat = shape_features(&plane, 0);
        let creased = shape_features(&cube, 0);
        assert!(flat.surface_variation < 1e-6, "{flat:?}");
        // Neighbourhoods that straddle the cube's edges are far from planar.
        assert!(creased.surface_variation > 0.005, "{creased:?}");
        assert!(flat.occupied_voxels > creased.occupied_voxels);
    }

    #[test]
    fn fit_recovers_a_noise_free_rule() {
        let truth = BudgetRule {
            intercept: 1.5,
            occupancy_exponent: 0.6,
            variation_weight: 4.0,
        };
        let examples: Vec<(ShapeFeatures, usize)> = (0..50)
            .map(|i| {
                let f = ShapeFeatures {
                    occupied_voxels: 20 + 37 * i,
                    surface_variation: (i % 7) as f64 * 0.04,
                };
                let ln_v = truth.intercept
                    + truth.occupancy_exponent * (f.occupied_voxels as f64).ln()
                    + truth.variation_weight * f.surface_variation;
                (f, ln_v.exp().round() as usize)
            })
            .collect();
        let (rule, r2) = BudgetRule::fit(&examples).unwrap();
        assert!((rule.occupancy_exponent - 0.6).abs() < 0.02, "{rule:?}");
        assert!((rule.variation_weight - 4.0).abs() < 0.2, "{rule:?}");
        assert!(r2 > 0.99);
        assert!(BudgetRule::fit(&examples[..2]).is_none());
    }

    #[test]
    fn budgets_are_clamped() {
        let f = ShapeFeatures {
            occupied_voxels: 10_000,
            surface_variation: 0.3,
        };
        let big = BudgetRule {
            intercept: 10.0,
            occupancy_exponent: 1.0,
            variation_weight: 1.0,
        };
        assert_eq!(big.budget(&f, 512), 512);
        let tiny = BudgetRule {
            intercept: -10.0,
            ..big
        };
        assert_eq!(tiny.budget(&f, 512), MIN_BUDGET);
        assert_eq!(tiny.budget(&f, 8), 8);
    }
}
