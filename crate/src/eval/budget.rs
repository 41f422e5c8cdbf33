//! `eval budget`: how well a vertex-budget rule predicts the artist's vertex count from a
//! mesh's surface samples, for a rule fitted on a set of meshes and for the shipped one (on a
//! held-out split, the shipped rule's figures are the held-out ones).

use serde::Serialize;

use crate::Mesh;
use crate::geometry::sample::sample_surface;
use crate::pipeline::budget::{BudgetRule, DEFAULT_RULE, ShapeFeatures, shape_features};
use crate::pipeline::generate::CONDITION_POINTS;

/// A fitted rule beside the shipped one.
#[derive(Serialize)]
pub struct BudgetReport {
    pub source: String,
    pub meshes: usize,
    pub fitted: BudgetRule,
    pub r_squared_log: f64,
    pub shipped: BudgetRule,
    /// R^2 in log space of the shipped rule on these meshes: held out unless they are the
    /// training meshes it was fitted to.
    pub shipped_r_squared_log: f64,
    /// Median of |ln(budget / true vertex count)| for each rule: exp of it is the typical
    /// factor by which a budget misses.
    pub fitted_median_log_error: f64,
    pub shipped_median_log_error: f64,
}

/// Fits [`BudgetRule`] on `meshes` (their surface samples as the conditioning points, seeded
/// by position; meshes that cannot be sampled are left out) and compares it with
/// [`DEFAULT_RULE`], budgets capped at `max_vertices`. `None` when too few meshes remain to
/// fit. `progress` is called after each mesh.
pub fn evaluate_budget_rule(
    meshes: &[(String, Mesh)],
    max_vertices: usize,
    source: String,
    progress: &mut dyn FnMut(usize),
) -> Option<BudgetReport> {
    let examples: Vec<(ShapeFeatures, usize)> = meshes
        .iter()
        .enumerate()
        .filter_map(|(i, (_, m))| {
            progress(i + 1);
            let points = sample_surface(m, CONDITION_POINTS, i as u64).ok()?.points;
            Some((shape_features(&points, i as u64), m.positions.len()))
        })
        .collect();
    let (fitted, r_squared_log) = BudgetRule::fit(&examples)?;
    let median_error = |rule: &BudgetRule| {
        let mut e: Vec<f64> = examples
            .iter()
            .map(|(f, v)| (rule.budget(f, max_vertices) as f64 / *v as f64).ln().abs())
            .collect();
        e.sort_by(f64::total_cmp);
        e[e.len() / 2]
    };
    Some(BudgetReport {
        source,
        meshes: examples.len(),
        fitted,
        r_squared_log,
        shipped: DEFAULT_RULE,
        shipped_r_squared_log: DEFAULT_RULE.r_squared_log(&examples)?,
        fitted_median_log_error: median_error(&fitted),
        shipped_median_log_error: median_error(&DEFAULT_RULE),
    })
}
