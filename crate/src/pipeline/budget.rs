//! The default vertex budget of a generation, from the input point cloud alone.
//!
//! Artists spend vertices on size and on curvature: a large flat wall needs few, a small
//! detailed prop many per unit area. Three features of the model-frame point cloud capture that
//! (the last two from the same 16-neighbour neighbourhoods of 512 sampled points):
//! - **occupancy** `A`: occupied cells of the 32^3 conditioning grid (a surface-area proxy that
//!   a point cloud without faces still has);
//! - **surface variation** `C`: the mean over sampled points of `l0 / (l0 + l1 + l2)`, the
//!   smallest eigenvalue share of the covariance of the point's 16 nearest neighbours (0 on a
//!   plane, up to 1/3 where the surface bends in every direction). At that scale smooth
//!   curvature barely registers; creases and corners do, and they are where artists put
//!   vertices.
//! - **planar share** `P`: the share of those neighbourhoods that lie on one plane (smallest
//!   eigenvalue share below [`PLANAR_SHARE`]). Points sampled from a low-poly surface lie on
//!   its faces, and an artist who spent few vertices left large ones, so many neighbourhoods
//!   fall inside one face; a dense or curved surface has few such. It is the feature that
//!   moves the fit (held-out R^2 0.10 -> 0.42 on validation,
//!   docs/experiments/2026-11-29-budget-planar-share.md). Noise
//!   erases it as it raises `C`: a noisy scan reads as a curved surface and gets more
//!   vertices, by about as much as with `A` and `C` alone.
//!
//! The rule is `V = exp(a + b ln A + c C + d P)`, clamped to `[MIN_BUDGET, max]`, with
//! `a, b, c, d` a least-squares fit of `ln V` over the training meshes that fit the shipped
//! VAE (`meshflow eval budget --split train`, figures in
//! docs/experiments/2026-11-29-budget-planar-share.md).

use glam::{DVec3, Vec3};
use serde::{Deserialize, Serialize};

use crate::geometry::nearest::PointIndex;
use crate::geometry::plane_fit::covariance;
use crate::geometry::quadric::symmetric_eigenvalues;
use crate::geometry::voxel::voxel_index;
use crate::rng::Rng;

/// Neighbours per local covariance.
const NEIGHBOURS: usize = 16;
/// Points whose neighbourhoods are averaged into the surface variation and the planar share.
const VARIATION_SAMPLES: usize = 512;
/// The smallest-eigenvalue share below which a neighbourhood counts as planar: an RMS
/// distance from the plane of about 0.3% of the neighbourhood's extent. Points sampled from
/// one face lie far below it (float rounding), and the fit on the training meshes was best at
/// the smallest of the thresholds tried (1e-5 to 3e-4,
/// docs/experiments/2026-11-29-budget-planar-share.md).
pub const PLANAR_SHARE: f64 = 1e-5;
/// The smallest default budget: below it the VAE's mask makes too few vertices for a shape.
pub const MIN_BUDGET: usize = 16;

/// What the default budget is computed from.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShapeFeatures {
    /// Occupied cells of the 32^3 grid over [-1, 1]^3.
    pub occupied_voxels: usize,
    /// Mean smallest-eigenvalue share of local covariances, in [0, 1/3].
    pub surface_variation: f64,
    /// Share of those neighbourhoods that are planar ([`PLANAR_SHARE`]), in [0, 1].
    pub planar_share: f64,
}

/// Coefficients of `ln V = a + b ln A + c C + d P`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct BudgetRule {
    pub intercept: f64,
    pub occupancy_exponent: f64,
    pub variation_weight: f64,
    pub planar_weight: f64,
}

/// The shipped rule: fitted by `meshflow eval budget --split train --data <pipeline-3 build>`
/// on the 3,806 training meshes of at most 512 vertices. Held out, R^2 in log space is 0.42
/// on validation and 0.32 on test (the rule without the planar share: 0.10 and 0.00), and
/// the median budget misses the artist's count by a factor of 1.6-1.8: artists' vertex
/// counts depend on more than the input shows, so `--vertices` and `--faces` are there to
/// override it.
pub const DEFAULT_RULE: BudgetRule = BudgetRule {
    intercept: 4.7914,
    occupancy_exponent: 0.0758,
    variation_weight: 0.2489,
    planar_weight: -2.4209,
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
            planar_share: 0.0,
        };
    }
    let index = PointIndex::new(points);
    let mut rng = Rng::new(seed);
    let queries = VARIATION_SAMPLES.min(points.len());
    let (mut total, mut planar) = (0.0, 0usize);
    for _ in 0..queries {
        let q = points[rng.below(points.len())];
        let near: Vec<DVec3> = index
            .k_nearest(q, NEIGHBOURS)
            .map(|(_, p)| p.as_dvec3())
            .collect();
        let share = smallest_eigenvalue_share(&near);
        total += share;
        planar += usize::from(share < PLANAR_SHARE);
    }
    ShapeFeatures {
        occupied_voxels: cells.len(),
        surface_variation: total / queries as f64,
        planar_share: planar as f64 / queries as f64,
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

/// The rule's inputs for `features`, in the order of [`BudgetRule::coefficients`]: `1, ln A,
/// C, P`.
fn regressors(features: &ShapeFeatures) -> [f64; 4] {
    [
        1.0,
        (features.occupied_voxels.max(1) as f64).ln(),
        features.surface_variation,
        features.planar_share,
    ]
}

impl BudgetRule {
    /// `[a, b, c, d]`, the weights of [`regressors`].
    fn coefficients(&self) -> [f64; 4] {
        [
            self.intercept,
            self.occupancy_exponent,
            self.variation_weight,
            self.planar_weight,
        ]
    }

    /// `ln V` before rounding and clamping.
    fn ln_vertices(&self, features: &ShapeFeatures) -> f64 {
        let x = regressors(features);
        self.coefficients().iter().zip(x).map(|(w, x)| w * x).sum()
    }

    /// The budget for `features`, clamped to `[MIN_BUDGET, max]` (`max` is the VAE's N).
    pub fn budget(&self, features: &ShapeFeatures, max: usize) -> usize {
        (self.ln_vertices(features).exp().round() as usize).clamp(MIN_BUDGET.min(max), max)
    }

    /// R^2 of the rule's `ln V` (unclamped) against the `(features, vertex count)` pairs, in
    /// log space: 1 for a perfect rule, 0 for one no better than their mean, below 0 for a
    /// worse one (a rule fitted elsewhere, scored on held-out meshes). `None` without examples.
    pub fn r_squared_log(&self, examples: &[(ShapeFeatures, usize)]) -> Option<f64> {
        if examples.is_empty() {
            return None;
        }
        let ln_v = |v: usize| (v.max(1) as f64).ln();
        let mean = examples.iter().map(|e| ln_v(e.1)).sum::<f64>() / examples.len() as f64;
        let (mut ss_res, mut ss_tot) = (0.0, 0.0);
        for (f, v) in examples {
            ss_res += (ln_v(*v) - self.ln_vertices(f)).powi(2);
            ss_tot += (ln_v(*v) - mean).powi(2);
        }
        Some(1.0 - ss_res / ss_tot.max(1e-30))
    }

    /// Least-squares fit of `ln V` over `(features, vertex count)` pairs, with R^2 of the fit in
    /// log space. `None` with fewer examples than coefficients or a singular system.
    pub fn fit(examples: &[(ShapeFeatures, usize)]) -> Option<(BudgetRule, f64)> {
        if examples.len() < 4 {
            return None;
        }
        // Normal equations: (X^T X) w = X^T y.
        let mut xtx = [[0.0; 4]; 4];
        let mut xty = [0.0; 4];
        for (f, v) in examples {
            let (x, y) = (regressors(f), (*v.max(&1) as f64).ln());
            for i in 0..4 {
                xty[i] += x[i] * y;
                for j in 0..4 {
                    xtx[i][j] += x[i] * x[j];
                }
            }
        }
        let [a, b, c, d] = solve(xtx, xty)?;
        let rule = BudgetRule {
            intercept: a,
            occupancy_exponent: b,
            variation_weight: c,
            planar_weight: d,
        };
        Some((rule, rule.r_squared_log(examples)?))
    }
}

/// Solves an N x N system by Gaussian elimination with partial pivoting; `None` when it is
/// singular.
fn solve<const N: usize>(mut a: [[f64; N]; N], mut b: [f64; N]) -> Option<[f64; N]> {
    for col in 0..N {
        let pivot = (col..N).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        if a[pivot][col].abs() < 1e-12 {
            return None;
        }
        a.swap(col, pivot);
        b.swap(col, pivot);
        for row in col + 1..N {
            let f = a[row][col] / a[col][col];
            let pivot_row = a[col];
            for (x, p) in a[row].iter_mut().zip(pivot_row).skip(col) {
                *x -= f * p;
            }
            b[row] -= f * b[col];
        }
    }
    let mut x = [0.0; N];
    for row in (0..N).rev() {
        let s: f64 = (row + 1..N).map(|k| a[row][k] * x[k]).sum();
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
        assert_eq!(flat.planar_share, 1.0);
        // Neighbourhoods that straddle the cube's edges are far from planar; those inside a
        // face are planar.
        assert!(creased.surface_variation > 0.005, "{creased:?}");
        assert!((0.3..0.95).contains(&creased.planar_share), "{creased:?}");
        assert!(flat.occupied_voxels > creased.occupied_voxels);
    }

    #[test]
    fn a_round_surface_has_no_planar_neighbourhoods() {
        // Points on the unit sphere itself, not on a tessellation of it.
        let mut rng = Rng::new(3);
        let sphere: Vec<Vec3> = (0..4096)
            .map(|_| {
                let (z, t) = (
                    rng.next_f32() * 2.0 - 1.0,
                    rng.next_f32() * std::f32::consts::TAU,
                );
                let r = (1.0 - z * z).max(0.0).sqrt();
                Vec3::new(r * t.cos(), r * t.sin(), z)
            })
            .collect();
        let round = shape_features(&sphere, 0);
        assert_eq!(round.planar_share, 0.0, "{round:?}");
        assert!(round.surface_variation > 0.0, "{round:?}");
    }

    #[test]
    fn fit_recovers_a_noise_free_rule() {
        let truth = BudgetRule {
            intercept: 1.5,
            occupancy_exponent: 0.6,
            variation_weight: 4.0,
            planar_weight: -2.0,
        };
        let examples: Vec<(ShapeFeatures, usize)> = (0..50)
            .map(|i| {
                let f = ShapeFeatures {
                    occupied_voxels: 20 + 37 * i,
                    surface_variation: (i % 7) as f64 * 0.04,
                    planar_share: (i % 5) as f64 * 0.2,
                };
                let ln_v = truth.intercept
                    + truth.occupancy_exponent * (f.occupied_voxels as f64).ln()
                    + truth.variation_weight * f.surface_variation
                    + truth.planar_weight * f.planar_share;
                (f, ln_v.exp().round() as usize)
            })
            .collect();
        let (rule, r2) = BudgetRule::fit(&examples).unwrap();
        assert!((rule.occupancy_exponent - 0.6).abs() < 0.02, "{rule:?}");
        assert!((rule.variation_weight - 4.0).abs() < 0.2, "{rule:?}");
        assert!((rule.planar_weight + 2.0).abs() < 0.05, "{rule:?}");
        assert!(r2 > 0.99);
        assert_eq!(rule.r_squared_log(&examples), Some(r2));
        assert!(BudgetRule::fit(&examples[..3]).is_none());
        // Scored on meshes it was not fitted to, a rule can be worse than their mean.
        let constant = BudgetRule {
            intercept: 10.0,
            occupancy_exponent: 0.0,
            variation_weight: 0.0,
            planar_weight: 0.0,
        };
        assert!(constant.r_squared_log(&examples).unwrap() < 0.0);
        assert_eq!(constant.r_squared_log(&[]), None);
    }

    #[test]
    fn budgets_are_clamped() {
        let f = ShapeFeatures {
            occupied_voxels: 10_000,
            surface_variation: 0.3,
            planar_share: 0.5,
        };
        let big = BudgetRule {
            intercept: 10.0,
            occupancy_exponent: 1.0,
            variation_weight: 1.0,
            planar_weight: 1.0,
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
