//! Means over a set of meshes' comparisons with their ground truth: what `eval vae` and
//! `eval generate` report per method and per size bucket.

use serde::Serialize;

use crate::eval::metrics::Comparison;

/// The size buckets evaluations report beside the whole set: meshes with at least the first
/// and at most the second count of ground-truth vertices. The last holds the meshes above the
/// 512 vertices every model stopped at until 2026-12 (issue 53's targets are on it).
pub const VERTEX_BUCKETS: [(usize, usize); 5] =
    [(0, 256), (0, 512), (0, 1024), (0, 2048), (513, 2048)];

/// Mean surface and topology figures over meshes' comparisons with their ground truth;
/// meshes without a comparison (no faces extracted) are counted, not averaged.
#[derive(Clone, Debug, Default, Serialize)]
pub struct SurfaceSummary {
    /// Meshes whose extraction gave no faces; the figures below are over the others.
    pub no_faces: usize,
    pub chamfer_x100: f64,
    pub hausdorff_x100: f64,
    /// Normal consistency (area samples both ways, absolute cosine), over the meshes that
    /// have it.
    pub normal_consistency: f64,
    /// Edge Chamfer distance x100 over the meshes where either side has sharp edges
    /// ([`crate::eval::metrics::SharpEdgeComparison`]), and how many those are.
    pub edge_chamfer_x100: f64,
    pub edge_chamfer_meshes: usize,
    /// Edge F-score at 0.01 over all meshes (1 where neither side has sharp edges).
    pub edge_f_score: f64,
    /// Sharp edges per mesh, and the ground truths' own.
    pub sharp_edges: f64,
    pub gt_sharp_edges: f64,
    /// Mean of each mesh's faces over its ground truth's.
    pub faces_ratio: f64,
    pub faces_out: f64,
    pub faces_in: f64,
    pub non_manifold_edges: f64,
    pub boundary_edges: f64,
    pub holes: f64,
    pub inconsistent_winding_edges: f64,
    pub degenerate_faces: f64,
    /// Folded edges (two faces doubled back onto each other,
    /// [`crate::geometry::topology::TopologyReport::folded_edges`]) per mesh, and the meshes
    /// with any.
    pub folded_edges: f64,
    pub folded_meshes: usize,
    pub components: f64,
    /// The ground truths' own holes and components (artist meshes are often open and in
    /// pieces), the yardstick for the two above.
    pub gt_holes: f64,
    pub gt_components: f64,
    /// Meshes whose ground truth is closed (no boundary edge), and the holes of these
    /// meshes' predictions: holes where there should be none.
    pub gt_closed: usize,
    pub holes_where_gt_closed: f64,
}

impl SurfaceSummary {
    /// The means over `comparisons` (`None`: a mesh with no faces).
    pub fn of(comparisons: &[Option<&Comparison>]) -> Self {
        let surfaces: Vec<&Comparison> = comparisons.iter().flatten().copied().collect();
        let k = surfaces.len().max(1) as f64;
        // `+ 0.0` turns the -0.0 of an empty sum into 0.0 in the JSON.
        let mean =
            |f: &dyn Fn(&Comparison) -> f64| surfaces.iter().map(|c| f(c)).sum::<f64>() / k + 0.0;
        let closed: Vec<&&Comparison> = surfaces
            .iter()
            .filter(|c| c.gt_topology.boundary_edges == 0)
            .collect();
        let mean_of = |values: Vec<f64>| values.iter().sum::<f64>() / values.len().max(1) as f64;
        let ecd: Vec<f64> = surfaces
            .iter()
            .filter_map(|c| c.sharp.edge_chamfer_x100)
            .collect();
        SurfaceSummary {
            no_faces: comparisons.len() - surfaces.len(),
            chamfer_x100: mean(&|c| c.chamfer_x100),
            hausdorff_x100: mean(&|c| c.hausdorff_x100),
            normal_consistency: mean_of(
                surfaces
                    .iter()
                    .filter_map(|c| c.normal_consistency)
                    .collect(),
            ),
            edge_chamfer_meshes: ecd.len(),
            edge_chamfer_x100: mean_of(ecd),
            edge_f_score: mean(&|c| c.sharp.edge_f_score.f_score),
            sharp_edges: mean(&|c| c.sharp.pred_sharp_edges as f64),
            gt_sharp_edges: mean(&|c| c.sharp.gt_sharp_edges as f64),
            faces_ratio: mean(&|c| {
                c.pred_topology.faces as f64 / c.gt_topology.faces.max(1) as f64
            }),
            faces_out: mean(&|c| c.pred_topology.faces as f64),
            faces_in: mean(&|c| c.gt_topology.faces as f64),
            non_manifold_edges: mean(&|c| c.pred_topology.non_manifold_edges as f64),
            boundary_edges: mean(&|c| c.pred_topology.boundary_edges as f64),
            holes: mean(&|c| c.pred_topology.holes as f64),
            inconsistent_winding_edges: mean(&|c| {
                c.pred_topology.inconsistent_winding_edges as f64
            }),
            degenerate_faces: mean(&|c| c.pred_topology.degenerate_faces as f64),
            folded_edges: mean(&|c| c.pred_topology.folded_edges as f64),
            folded_meshes: surfaces
                .iter()
                .filter(|c| c.pred_topology.folded_edges > 0)
                .count(),
            components: mean(&|c| c.pred_topology.components as f64),
            gt_holes: mean(&|c| c.gt_topology.holes as f64),
            gt_components: mean(&|c| c.gt_topology.components as f64),
            gt_closed: closed.len(),
            holes_where_gt_closed: closed
                .iter()
                .map(|c| c.pred_topology.holes as f64)
                .sum::<f64>()
                / closed.len().max(1) as f64,
        }
    }
}

/// `summarise` over the whole set and over each of [`VERTEX_BUCKETS`] (named `<= N`, or
/// `M-N` where it has a lower bound), with
/// `vertices` giving an item's ground-truth vertex count.
pub fn bucketed<T, S>(
    items: &[T],
    vertices: impl Fn(&T) -> usize,
    summarise: impl Fn(&[&T]) -> S,
) -> (S, Vec<(String, S)>) {
    let all: Vec<&T> = items.iter().collect();
    let buckets = VERTEX_BUCKETS
        .iter()
        .map(|&(low, high)| {
            let some: Vec<&T> = all
                .iter()
                .copied()
                .filter(|t| (low..=high).contains(&vertices(t)))
                .collect();
            let name = if low == 0 {
                format!("<= {high}")
            } else {
                format!("{low}-{high}")
            };
            (name, summarise(&some))
        })
        .collect();
    (summarise(&all), buckets)
}
