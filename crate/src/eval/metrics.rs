//! Evaluation metrics, following docs/design.md section 3 so numbers compare with the paper's tables.
//!
//! - [`chamfer_hausdorff`]: Chamfer distance (sum of the two one-sided mean nearest distances,
//!   unsquared Euclidean) and Hausdorff distance (the larger one-sided maximum) between point sets.
//! - [`compare_meshes`]: the full protocol: normalise both meshes by the ground truth's box to
//!   [-0.5, 0.5], sample 5,000 points by area on each, then CD and HD (x100), normal consistency,
//!   F-scores, the sharp-edge measures ([`SharpEdgeComparison`]: edge Chamfer and edge
//!   F-score) and both topology reports.
//! - [`edge_scores`]: precision / recall / F1 of an undirected edge set (paper Table 3).
//! - [`vertex_distance`] / [`normal_distance`]: mean L2 between corresponding rows (Table 3).
//!
//! Nearest neighbours come from [`PointIndex`] (a k-d tree in `f32`) and each distance is then
//! measured in `f64`: what a brute-force search in `f64` gives, except where two points are
//! nearest within `f32`'s rounding (then either one's distance, the same to about 1e-7).

use std::fmt;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::Mesh;
use crate::geometry::features::{SHARP_ANGLE_DEG, sharp_edges};
use crate::geometry::mesh::MeshError;
use crate::geometry::nearest::PointIndex;
use crate::geometry::normalize::Normalization;
use crate::geometry::sample::{
    MAX_SAMPLES, SampleError, sample_segments, sample_surface, subsample_indices,
};
pub use crate::geometry::topology::TopologyReport;
use crate::rng::Rng;

/// Why a metric cannot be computed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MetricsError {
    #[error("the {which} point set is empty")]
    EmptySet { which: &'static str },
    #[error("the {which} point set has a non-finite coordinate at row {row}")]
    NonFinite { which: &'static str, row: usize },
    #[error("{pred} predicted rows but {gt} ground-truth rows (they must correspond one to one)")]
    LengthMismatch { pred: usize, gt: usize },
    #[error("the {which} mesh has no vertices")]
    EmptyMesh { which: &'static str },
    #[error("the {which} mesh is invalid: {source}")]
    InvalidMesh {
        which: &'static str,
        source: MeshError,
    },
    #[error("sampling the {which} mesh failed: {source}")]
    Sample {
        which: &'static str,
        source: SampleError,
    },
    #[error("the sample count must be positive")]
    ZeroSamples,
}

/// Chamfer and Hausdorff distances between two point sets, in the sets' own units (not x100).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Distances {
    /// `a_to_b_mean + b_to_a_mean`.
    pub chamfer: f64,
    /// `max(a_to_b_max, b_to_a_max)`.
    pub hausdorff: f64,
    /// Mean over A of the distance to the nearest point of B.
    pub a_to_b_mean: f64,
    /// Mean over B of the distance to the nearest point of A.
    pub b_to_a_mean: f64,
    pub a_to_b_max: f64,
    pub b_to_a_max: f64,
}

fn to_f64(p: Vec3) -> [f64; 3] {
    [p.x as f64, p.y as f64, p.z as f64]
}

fn check_set(points: &[Vec3], which: &'static str) -> Result<(), MetricsError> {
    if points.is_empty() {
        return Err(MetricsError::EmptySet { which });
    }
    match points.iter().position(|p| !p.is_finite()) {
        Some(row) => Err(MetricsError::NonFinite { which, row }),
        None => Ok(()),
    }
}

/// For each point of `from`, the row of its nearest point in `to` (non-empty, finite) and the
/// distance to it (in double precision).
fn nearest(from: &[Vec3], to: &[Vec3]) -> Vec<(u32, f64)> {
    let index = PointIndex::new(to);
    from.iter()
        .map(|&p| {
            // `to` is never empty here, so there always is a nearest neighbour.
            index
                .nearest(p)
                .map_or((u32::MAX, f64::INFINITY), |(row, q, _)| {
                    (row, p.as_dvec3().distance(q.as_dvec3()))
                })
        })
        .collect()
}

fn mean_max(nn: &[(u32, f64)]) -> (f64, f64) {
    let sum: f64 = nn.iter().map(|&(_, d)| d).sum();
    let max = nn.iter().map(|&(_, d)| d).fold(0.0, f64::max);
    (sum / nn.len() as f64, max)
}

/// Both directions' nearest neighbours, which [`compare_meshes`] reuses for normals and F-scores.
struct Matching {
    a_to_b: Vec<(u32, f64)>,
    b_to_a: Vec<(u32, f64)>,
}

impl Matching {
    fn new(a: &[Vec3], b: &[Vec3]) -> Result<Self, MetricsError> {
        check_set(a, "first")?;
        check_set(b, "second")?;
        Ok(Matching {
            a_to_b: nearest(a, b),
            b_to_a: nearest(b, a),
        })
    }

    fn distances(&self) -> Distances {
        let (a_to_b_mean, a_to_b_max) = mean_max(&self.a_to_b);
        let (b_to_a_mean, b_to_a_max) = mean_max(&self.b_to_a);
        Distances {
            chamfer: a_to_b_mean + b_to_a_mean,
            hausdorff: a_to_b_max.max(b_to_a_max),
            a_to_b_mean,
            b_to_a_mean,
            a_to_b_max,
            b_to_a_max,
        }
    }
}

/// Chamfer (CD = mean over A of the nearest distance to B + mean over B of the nearest distance
/// to A, unsquared Euclidean) and Hausdorff (HD = the larger one-sided maximum) distances.
///
/// Errors (never panics) when either set is empty or has a non-finite coordinate; "first" is
/// `a`, "second" is `b`.
pub fn chamfer_hausdorff(a: &[Vec3], b: &[Vec3]) -> Result<Distances, MetricsError> {
    Ok(Matching::new(a, b)?.distances())
}

/// Settings of [`compare_meshes`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CompareOptions {
    /// Points sampled on each surface: 5,000 (docs/design.md section 3).
    pub samples: usize,
    /// Master seed. The prediction is sampled with the first output of `Rng::new(seed)`
    /// (`next_u64`) and the ground truth with the second, so the two never share a stream.
    pub seed: u64,
    /// F-score distance thresholds in the metric frame (the ground truth's longest side is 1):
    /// by default 0.01 and 0.02, i.e. 1% and 2% of that side.
    pub f_score_thresholds: Vec<f64>,
    /// Points sampled by length along each mesh's sharp edges: 2,000.
    pub edge_samples: usize,
    /// The edge F-score's distance threshold in the metric frame: 0.01.
    pub edge_f_score_threshold: f64,
}

impl Default for CompareOptions {
    fn default() -> Self {
        CompareOptions {
            samples: 5000,
            seed: 0,
            f_score_thresholds: vec![0.01, 0.02],
            edge_samples: 2000,
            edge_f_score_threshold: 0.01,
        }
    }
}

impl CompareOptions {
    /// The seeds used to sample (prediction, ground truth), derived from [`Self::seed`].
    pub fn sample_seeds(&self) -> (u64, u64) {
        let mut rng = Rng::new(self.seed);
        let pred = rng.next_u64();
        (pred, rng.next_u64())
    }

    /// The seeds of the sharp-edge samples (prediction, ground truth): the master seed's
    /// third and fourth outputs, so adding them left the surface samples as they were.
    pub fn edge_sample_seeds(&self) -> (u64, u64) {
        let mut rng = Rng::new(self.seed);
        rng.next_u64();
        rng.next_u64();
        let pred = rng.next_u64();
        (pred, rng.next_u64())
    }
}

/// The sharp-edge measures of [`compare_meshes`] (docs/design.md section 3): where the
/// creases are, not only where the surface is. Sharp edges are those of
/// [`sharp_edges`] at [`SHARP_ANGLE_DEG`]; each side's are sampled by length, in the ground
/// truth's metric frame.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SharpEdgeComparison {
    pub pred_sharp_edges: usize,
    pub gt_sharp_edges: usize,
    /// Edge Chamfer distance x 100 between the two sides' edge samples. Where exactly one
    /// side has sharp edges, the other side's vertices stand in for its edge samples (a mesh
    /// with no crease is scored as if its creases were wherever its vertices are), so a
    /// missing crease counts against it. `None` when neither side has sharp edges.
    pub edge_chamfer_x100: Option<f64>,
    /// Precision, recall and F-score of the edge samples at
    /// [`CompareOptions::edge_f_score_threshold`]; 1 when neither side has sharp edges, 0
    /// when only one has.
    pub edge_f_score: FScore,
}

/// F-score at one distance threshold: a predicted sample is correct when a ground-truth sample
/// lies within `threshold` (precision), and a ground-truth sample is recovered when a predicted
/// sample does (recall); `f_score = 2 P R / (P + R)`, 0 when both are 0.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FScore {
    pub threshold: f64,
    pub precision: f64,
    pub recall: f64,
    pub f_score: f64,
}

/// The result of [`compare_meshes`]. Distances are in the metric frame (ground truth's longest
/// side = 1); the `_x100` fields are what the paper's tables print.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Comparison {
    /// Chamfer distance x 100 (the paper's "CD").
    pub chamfer_x100: f64,
    /// Hausdorff distance x 100 (the paper's "HD").
    pub hausdorff_x100: f64,
    /// The unscaled distances (not x100); `a` is the prediction, `b` the ground truth.
    pub distances: Distances,
    /// Mean over both directions of |dot| between a sample's normal and its nearest neighbour's
    /// normal, in [0, 1] (1 = every normal parallel; orientation is ignored). `None` when a side
    /// is a point cloud without per-vertex normals.
    pub normal_consistency: Option<f64>,
    pub f_scores: Vec<FScore>,
    /// Sharp edges, edge Chamfer distance and edge F-score.
    #[serde(default)]
    pub sharp: SharpEdgeComparison,
    /// Points per side.
    pub samples: usize,
    pub pred_seed: u64,
    pub gt_seed: u64,
    /// True when the prediction had no faces and its vertices were used as the samples.
    pub pred_is_point_cloud: bool,
    pub gt_is_point_cloud: bool,
    pub pred_topology: TopologyReport,
    pub gt_topology: TopologyReport,
}

/// The comparison as `meshflow compare` prints it under the two file names.
impl fmt::Display for Comparison {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use crate::geometry::topology::{json, write_fields};
        write_fields(
            f,
            &[
                ("chamfer x100", json(&self.chamfer_x100)),
                ("hausdorff x100", json(&self.hausdorff_x100)),
                ("normal consistency", json(&self.normal_consistency)),
                ("f scores", json(&self.f_scores)),
                ("samples", json(&self.samples)),
                ("pred seed", json(&self.pred_seed)),
                ("gt seed", json(&self.gt_seed)),
                ("pred is point cloud", json(&self.pred_is_point_cloud)),
                ("gt is point cloud", json(&self.gt_is_point_cloud)),
            ],
        )?;
        let s = &self.sharp;
        let ecd = s
            .edge_chamfer_x100
            .map_or("none (neither has sharp edges)".to_string(), |d| {
                format!("{d:.3}")
            });
        let (pred, gt) = (s.pred_sharp_edges, s.gt_sharp_edges);
        writeln!(f)?;
        writeln!(
            f,
            "  sharp edges (> 30 deg)      {pred} predicted, {gt} ground truth"
        )?;
        writeln!(f, "  edge chamfer x100           {ecd}")?;
        let e = &s.edge_f_score;
        writeln!(
            f,
            "  edge f-score @0.01          {:.4} (precision {:.4}, recall {:.4})",
            e.f_score, e.precision, e.recall
        )?;
        let (pred, gt) = (self.pred_topology.faces, self.gt_topology.faces);
        let ratio = pred as f64 / gt.max(1) as f64;
        writeln!(
            f,
            "  faces                       {pred} predicted, {gt} ground truth ({ratio:.2}x)"
        )?;
        writeln!(f, "{}", self.pred_topology.titled("prediction topology"))?;
        write!(f, "{}", self.gt_topology.titled("ground-truth topology"))
    }
}

/// Samples of one side: points and (if known) unit normals.
fn side_samples(
    mesh: &Mesh,
    count: usize,
    seed: u64,
    which: &'static str,
) -> Result<(Vec<Vec3>, Option<Vec<Vec3>>), MetricsError> {
    if mesh.is_point_cloud() {
        // A point cloud stands for its surface: subsample its points (all of them, evenly
        // repeated, when it has fewer), carrying per-vertex normals when it has them.
        let picked = subsample_indices(mesh.positions.len(), count, seed);
        let points = picked.iter().map(|&i| mesh.positions[i]).collect();
        let normals = (!mesh.normals.is_empty()).then(|| {
            picked
                .iter()
                .map(|&i| mesh.normals[i].normalize_or_zero())
                .collect()
        });
        Ok((points, normals))
    } else {
        let s = sample_surface(mesh, count, seed)
            .map_err(|source| MetricsError::Sample { which, source })?;
        Ok((s.points, Some(s.normals)))
    }
}

/// The harmonic mean of precision and recall, 0 when both are 0.
fn f1_of(precision: f64, recall: f64) -> f64 {
    if precision + recall > 0.0 {
        2.0 * precision * recall / (precision + recall)
    } else {
        0.0
    }
}

fn f_score(m: &Matching, threshold: f64) -> FScore {
    let within = |nn: &[(u32, f64)]| {
        nn.iter().filter(|&&(_, d)| d <= threshold).count() as f64 / nn.len() as f64
    };
    let precision = within(&m.a_to_b);
    let recall = within(&m.b_to_a);
    let f_score = f1_of(precision, recall);
    FScore {
        threshold,
        precision,
        recall,
        f_score,
    }
}

fn normal_consistency(m: &Matching, na: &[Vec3], nb: &[Vec3]) -> f64 {
    let one_side = |nn: &[(u32, f64)], from: &[Vec3], to: &[Vec3]| {
        nn.iter()
            .zip(from)
            .map(|(&(j, _), n)| (n.dot(to[j as usize]) as f64).abs().min(1.0))
            .sum::<f64>()
            / nn.len() as f64
    };
    0.5 * (one_side(&m.a_to_b, na, nb) + one_side(&m.b_to_a, nb, na))
}

/// [`SharpEdgeComparison`] of two meshes already in the metric frame.
fn sharp_edge_comparison(pred: &Mesh, gt: &Mesh, opts: &CompareOptions) -> SharpEdgeComparison {
    let (pred_seed, gt_seed) = opts.edge_sample_seeds();
    let side = |m: &Mesh, seed: u64| {
        let edges = sharp_edges(&m.positions, &m.faces, SHARP_ANGLE_DEG);
        let samples = sample_segments(&m.positions, &edges, opts.edge_samples, seed);
        (edges.len(), samples)
    };
    let (pred_sharp_edges, pa) = side(pred, pred_seed);
    let (gt_sharp_edges, pb) = side(gt, gt_seed);
    let threshold = opts.edge_f_score_threshold;
    let score = |precision: f64, recall: f64| FScore {
        threshold,
        precision,
        recall,
        f_score: f1_of(precision, recall),
    };
    let (edge_chamfer_x100, edge_f_score) = match (pa.is_empty(), pb.is_empty()) {
        (true, true) => (None, score(1.0, 1.0)),
        (false, false) => match Matching::new(&pa, &pb) {
            Ok(m) => (Some(100.0 * m.distances().chamfer), f_score(&m, threshold)),
            Err(_) => (None, score(0.0, 0.0)),
        },
        // One side has no crease: its vertices stand in for its edge samples.
        (pred_missing, _) => {
            let (a, b) = if pred_missing {
                (&pred.positions[..], &pb[..])
            } else {
                (&pa[..], &gt.positions[..])
            };
            let cd = Matching::new(a, b)
                .ok()
                .map(|m| 100.0 * m.distances().chamfer);
            (cd, score(0.0, 0.0))
        }
    };
    SharpEdgeComparison {
        pred_sharp_edges,
        gt_sharp_edges,
        edge_chamfer_x100,
        edge_f_score,
    }
}

/// Compares a predicted mesh with the ground truth by the protocol of docs/design.md section 3.
///
/// Both meshes are mapped by `Normalization::to_metric_frame(gt.aabb())` (the ground truth's
/// longest side to [-0.5, 0.5], centred; the same transform for the prediction), then
/// `opts.samples` points are sampled uniformly by area on each surface with the seeds of
/// [`CompareOptions::sample_seeds`]. A side without faces (a point cloud) uses its own points,
/// subsampled to `opts.samples` by [`crate::geometry::sample::subsample_indices`]; its normals are its per-vertex normals
/// if it has them, otherwise normal consistency is `None`.
///
/// Noise floor: two independent samples of the same surface are not at distance 0. For `n`
/// points uniform on an area `A` the mean nearest distance is about `sqrt(A / n) / 2`, so a
/// perfect prediction scores CD about `sqrt(A / n)`: 2.5 (x100) for a sphere of diameter 1
/// (A = pi) at 5,000 samples, and about 4.5 (x100) HD. Compare methods on the same protocol only.
///
/// Errors when either mesh is invalid or has no vertices, when a surface has zero area, or when
/// `opts.samples` is 0.
pub fn compare_meshes(
    pred: &Mesh,
    gt: &Mesh,
    opts: &CompareOptions,
) -> Result<Comparison, MetricsError> {
    if opts.samples == 0 {
        return Err(MetricsError::ZeroSamples);
    }
    if opts.samples > MAX_SAMPLES {
        let source = SampleError::TooMany {
            count: opts.samples,
        };
        return Err(MetricsError::Sample {
            which: "predicted",
            source,
        });
    }
    for (mesh, which) in [(pred, "predicted"), (gt, "ground-truth")] {
        mesh.validate()
            .map_err(|source| MetricsError::InvalidMesh { which, source })?;
        if mesh.positions.is_empty() {
            return Err(MetricsError::EmptyMesh { which });
        }
    }
    let frame = gt
        .aabb()
        .map(Normalization::to_metric_frame)
        .ok_or(MetricsError::EmptyMesh {
            which: "ground-truth",
        })?;
    let (pred_seed, gt_seed) = opts.sample_seeds();
    let (pred_m, gt_m) = (frame.apply_mesh(pred), frame.apply_mesh(gt));
    let (pa, na) = side_samples(&pred_m, opts.samples, pred_seed, "predicted")?;
    let (pb, nb) = side_samples(&gt_m, opts.samples, gt_seed, "ground-truth")?;
    let matching = Matching::new(&pa, &pb)?;
    let distances = matching.distances();
    let normal_consistency = match (&na, &nb) {
        (Some(na), Some(nb)) => Some(normal_consistency(&matching, na, nb)),
        _ => None,
    };
    Ok(Comparison {
        chamfer_x100: 100.0 * distances.chamfer,
        hausdorff_x100: 100.0 * distances.hausdorff,
        distances,
        normal_consistency,
        f_scores: opts
            .f_score_thresholds
            .iter()
            .map(|&t| f_score(&matching, t))
            .collect(),
        sharp: sharp_edge_comparison(&pred_m, &gt_m, opts),
        samples: opts.samples,
        pred_seed,
        gt_seed,
        pred_is_point_cloud: pred.is_point_cloud(),
        gt_is_point_cloud: gt.is_point_cloud(),
        pred_topology: TopologyReport::of(pred),
        gt_topology: TopologyReport::of(gt),
    })
}

/// Precision, recall and F1 of a predicted undirected edge set against the actual one.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct EdgeScores {
    pub precision: f64,
    pub recall: f64,
    pub f1: f64,
    /// Distinct edges in both sets.
    pub true_positives: usize,
    /// Distinct predicted edges (after normalising, deduplicating and dropping self-loops).
    pub predicted: usize,
    /// Distinct actual edges (likewise).
    pub actual: usize,
}

/// Scores `predicted` edges against `actual` ones as undirected sets: each pair is normalised to
/// `i < j`, duplicates count once and self-loops `[i, i]` are ignored.
///
/// Zero denominators: precision (nothing predicted) and recall (nothing actual) are 1 when both
/// sets are empty (perfect agreement) and 0 otherwise; F1 is `2 P R / (P + R)`, and 0 when
/// `P + R = 0`. So two empty sets score 1, 1, 1 and one empty set against a non-empty one
/// scores F1 = 0.
pub fn edge_scores(predicted: &[[u32; 2]], actual: &[[u32; 2]]) -> EdgeScores {
    let p = crate::geometry::topology::canonical_edges(predicted);
    let a = crate::geometry::topology::canonical_edges(actual);
    let true_positives = p.iter().filter(|e| a.binary_search(e).is_ok()).count();
    let both_empty = p.is_empty() && a.is_empty();
    let ratio = |num: usize, den: usize| {
        if den > 0 {
            num as f64 / den as f64
        } else if both_empty {
            1.0
        } else {
            0.0
        }
    };
    let precision = ratio(true_positives, p.len());
    let recall = ratio(true_positives, a.len());
    let f1 = f1_of(precision, recall);
    EdgeScores {
        precision,
        recall,
        f1,
        true_positives,
        predicted: p.len(),
        actual: a.len(),
    }
}

fn mean_row_distance(pred: &[Vec3], gt: &[Vec3]) -> Result<f64, MetricsError> {
    if pred.len() != gt.len() {
        return Err(MetricsError::LengthMismatch {
            pred: pred.len(),
            gt: gt.len(),
        });
    }
    check_set(pred, "predicted")?;
    check_set(gt, "ground-truth")?;
    let sum: f64 = pred
        .iter()
        .zip(gt)
        .map(|(&p, &g)| {
            let [x, y, z] = to_f64(p);
            let [u, v, w] = to_f64(g);
            ((x - u).powi(2) + (y - v).powi(2) + (z - w).powi(2)).sqrt()
        })
        .sum();
    Ok(sum / pred.len() as f64)
}

/// Mean Euclidean distance between corresponding vertices (paper Table 3's vertex distance; the
/// caller passes only real, unpadded vertices and multiplies by 100 to report). Errors on
/// different lengths, empty input or non-finite coordinates.
pub fn vertex_distance(pred: &[Vec3], gt: &[Vec3]) -> Result<f64, MetricsError> {
    mean_row_distance(pred, gt)
}

/// Mean Euclidean distance between corresponding normals (paper Table 3's normal distance; the
/// vectors are compared as given, not renormalised). Same rules as [`vertex_distance`].
pub fn normal_distance(pred_normals: &[Vec3], gt_normals: &[Vec3]) -> Result<f64, MetricsError> {
    mean_row_distance(pred_normals, gt_normals)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::primitives::{cube, grid, icosphere, octahedron};

    #[test]
    fn the_text_of_a_comparison_lists_its_figures() {
        let c = compare_meshes(&cube(), &cube(), &CompareOptions::default()).unwrap();
        let text = c.to_string();
        assert!(text.starts_with("  chamfer x100                "), "{text}");
        assert!(
            text.contains("\n  samples                     5000\n"),
            "{text}"
        );
        let faces = "\n  faces                       12 predicted, 12 ground truth (1.00x)\n";
        assert!(text.contains(faces), "{text}");
        assert!(text.contains("\nprediction topology\n  vertices"), "{text}");
    }

    fn brute(a: &[Vec3], b: &[Vec3]) -> Distances {
        let one = |from: &[Vec3], to: &[Vec3]| {
            let d: Vec<f64> = from
                .iter()
                .map(|&p| {
                    to.iter()
                        .map(|&q| {
                            let (p, q) = (to_f64(p), to_f64(q));
                            ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2))
                                .sqrt()
                        })
                        .fold(f64::INFINITY, f64::min)
                })
                .collect();
            (
                d.iter().sum::<f64>() / d.len() as f64,
                d.iter().copied().fold(0.0, f64::max),
            )
        };
        let (am, ax) = one(a, b);
        let (bm, bx) = one(b, a);
        Distances {
            chamfer: am + bm,
            hausdorff: ax.max(bx),
            a_to_b_mean: am,
            b_to_a_mean: bm,
            a_to_b_max: ax,
            b_to_a_max: bx,
        }
    }

    #[test]
    fn chamfer_of_known_sets() {
        let a = [Vec3::ZERO, Vec3::X];
        let b = [Vec3::new(0.0, 2.0, 0.0)];
        let d = chamfer_hausdorff(&a, &b).unwrap();
        let s2 = 5f64.sqrt();
        assert!((d.a_to_b_mean - (2.0 + s2) / 2.0).abs() < 1e-12);
        assert!((d.b_to_a_mean - 2.0).abs() < 1e-12);
        assert!((d.a_to_b_max - s2).abs() < 1e-12);
        assert!((d.hausdorff - s2).abs() < 1e-12);
        assert!((d.chamfer - (d.a_to_b_mean + d.b_to_a_mean)).abs() < 1e-15);
        assert_eq!(d, brute(&a, &b));
        let same = chamfer_hausdorff(&a, &a).unwrap();
        assert_eq!((same.chamfer, same.hausdorff), (0.0, 0.0));
    }

    #[test]
    fn chamfer_errors_instead_of_panicking() {
        assert_eq!(
            chamfer_hausdorff(&[], &[Vec3::ZERO]),
            Err(MetricsError::EmptySet { which: "first" })
        );
        assert_eq!(
            chamfer_hausdorff(&[Vec3::ZERO], &[]),
            Err(MetricsError::EmptySet { which: "second" })
        );
        assert_eq!(
            chamfer_hausdorff(&[Vec3::ZERO], &[Vec3::X, Vec3::NAN]),
            Err(MetricsError::NonFinite {
                which: "second",
                row: 1
            })
        );
    }

    #[test]
    fn same_sphere_is_close_and_cube_is_far() {
        let sphere = icosphere(3);
        let opts = CompareOptions::default();
        let c = compare_meshes(&sphere, &sphere, &opts).unwrap();
        // The protocol's noise floor: two independent 5,000-point samples of a sphere of
        // diameter 1 (area pi) are sqrt(pi / 5000) / 2 = 0.0125 apart on average each way.
        let floor = (std::f64::consts::PI / 5000.0).sqrt();
        assert!((c.distances.chamfer / floor - 1.0).abs() < 0.1, "{c:?}");
        assert!(c.normal_consistency.unwrap() > 0.95, "{c:?}");
        // At 2% most samples have a partner; at 1% (below the mean spacing) fewer than half.
        assert!(c.f_scores[1].f_score > 0.8, "{c:?}");
        assert!(c.f_scores[0].f_score < c.f_scores[1].f_score);
        assert_eq!(c.samples, 5000);
        assert_ne!(c.pred_seed, c.gt_seed);
        assert!(c.pred_topology.is_clean_closed());
        assert_eq!(c.pred_topology, c.gt_topology);

        let far = compare_meshes(&cube(), &sphere, &opts).unwrap();
        assert!(far.chamfer_x100 > 3.0 * c.chamfer_x100, "{far:?}");
        assert!(far.hausdorff_x100 > c.hausdorff_x100);
        assert!(far.normal_consistency.unwrap() < c.normal_consistency.unwrap());
        assert_eq!(far.pred_topology.faces, 12);
    }

    #[test]
    fn normalised_by_the_ground_truth_box() {
        // The same shape at another scale is far in the metric frame of the ground truth.
        let gt = icosphere(2);
        let mut big = gt.clone();
        for p in &mut big.positions {
            *p *= 2.0;
        }
        let opts = CompareOptions {
            samples: 1000,
            ..Default::default()
        };
        let c = compare_meshes(&big, &gt, &opts).unwrap();
        // gt radius 0.5 in the frame, prediction radius 1: every distance is about 0.5.
        assert!((c.distances.a_to_b_mean - 0.5).abs() < 0.02, "{c:?}");
        assert!((c.distances.b_to_a_mean - 0.5).abs() < 0.02, "{c:?}");
    }

    #[test]
    fn point_cloud_prediction_uses_its_points() {
        let gt = icosphere(3);
        let cloud = Mesh::from_points(gt.positions.clone());
        let opts = CompareOptions {
            samples: 2000,
            ..Default::default()
        };
        let c = compare_meshes(&cloud, &gt, &opts).unwrap();
        assert!(c.pred_is_point_cloud && !c.gt_is_point_cloud);
        assert_eq!(c.normal_consistency, None);
        // The 642 vertices lie on the surface: each side is at the sampling noise floor
        // (about 0.5 / sqrt(density) for points uniform on an area of pi).
        assert!(c.distances.a_to_b_mean < 0.025, "{c:?}");
        assert!(c.distances.b_to_a_mean < 0.035, "{c:?}");
        let far = compare_meshes(&cube(), &gt, &opts).unwrap();
        assert!(far.chamfer_x100 > 2.0 * c.chamfer_x100, "{far:?}");
        let mut with_normals = cloud.clone();
        with_normals.normals = gt.positions.clone();
        let n = compare_meshes(&with_normals, &gt, &opts).unwrap();
        assert!(n.normal_consistency.unwrap() > 0.95);
        assert_eq!(n.chamfer_x100, c.chamfer_x100);
    }

    #[test]
    fn compare_errors() {
        let opts = CompareOptions::default();
        let sphere = icosphere(1);
        let flat = Mesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::X * 2.0], vec![[0, 1, 2]]);
        assert!(matches!(
            compare_meshes(&flat, &sphere, &opts),
            Err(MetricsError::Sample {
                which: "predicted",
                source: SampleError::ZeroArea { .. }
            })
        ));
        assert!(matches!(
            compare_meshes(&sphere, &Mesh::default(), &opts),
            Err(MetricsError::EmptyMesh { .. })
        ));
        let broken = Mesh::new(vec![Vec3::ZERO], vec![[0, 0, 5]]);
        assert!(matches!(
            compare_meshes(&broken, &sphere, &opts),
            Err(MetricsError::InvalidMesh { .. })
        ));
        let zero = CompareOptions {
            samples: 0,
            ..Default::default()
        };
        assert_eq!(
            compare_meshes(&sphere, &sphere, &zero),
            Err(MetricsError::ZeroSamples)
        );
    }

    #[test]
    fn sharp_edges_are_compared_where_they_are() {
        let opts = CompareOptions::default();
        // The same box: every crease found, the edge Chamfer at the sampling floor.
        let c = compare_meshes(&cube(), &cube(), &opts).unwrap();
        assert_eq!((c.sharp.pred_sharp_edges, c.sharp.gt_sharp_edges), (12, 12));
        assert!(c.sharp.edge_f_score.f_score > 0.95, "{:?}", c.sharp);
        assert!(c.sharp.edge_chamfer_x100.unwrap() < 1.0, "{:?}", c.sharp);
        // A sphere for a box: no crease where there are twelve, scored as missing.
        let s = compare_meshes(&icosphere(3), &cube(), &opts).unwrap();
        assert_eq!(s.sharp.pred_sharp_edges, 0);
        assert_eq!(s.sharp.edge_f_score.f_score, 0.0);
        assert!(s.sharp.edge_chamfer_x100.unwrap() > 5.0, "{:?}", s.sharp);
        // Two spheres: no creases on either side.
        let n = compare_meshes(&icosphere(2), &icosphere(3), &opts).unwrap();
        assert_eq!(n.sharp.edge_chamfer_x100, None);
        assert_eq!(n.sharp.edge_f_score.f_score, 1.0);
        // A box moved by 5% of its side: its creases are 0.05 off, beyond the 0.01 threshold.
        let mut moved = cube();
        for p in &mut moved.positions {
            *p += Vec3::splat(0.1);
        }
        let m = compare_meshes(&moved, &cube(), &opts).unwrap();
        assert!(m.sharp.edge_f_score.f_score < 0.2, "{:?}", m.sharp);
        let ecd = m.sharp.edge_chamfer_x100.unwrap();
        assert!((4.0..20.0).contains(&ecd), "{ecd}");
    }

    #[test]
    fn comparison_serialises() {
        let c = compare_meshes(
            &octahedron(),
            &grid(2, 2),
            &CompareOptions {
                samples: 100,
                ..Default::default()
            },
        )
        .unwrap();
        let json = serde_json::to_string(&c).unwrap();
        assert!(json.contains("\"chamfer_x100\""));
        assert!(json.contains("\"pred_topology\""));
        let back: Comparison = serde_json::from_str(&json).unwrap();
        assert_eq!(back, c);
    }

    #[test]
    fn edge_scores_known_sets() {
        let actual = [[0, 1], [1, 2], [2, 0], [2, 3]];
        // Reversed pair, duplicate, self-loop and one wrong edge.
        let predicted = [[1, 0], [0, 1], [2, 1], [3, 3], [0, 3]];
        let s = edge_scores(&predicted, &actual);
        assert_eq!((s.true_positives, s.predicted, s.actual), (2, 3, 4));
        assert!((s.precision - 2.0 / 3.0).abs() < 1e-12);
        assert!((s.recall - 0.5).abs() < 1e-12);
        assert!((s.f1 - 4.0 / 7.0).abs() < 1e-12);

        let perfect = edge_scores(&[[3, 2], [1, 2], [0, 2], [1, 0]], &actual);
        assert_eq!(
            (perfect.precision, perfect.recall, perfect.f1),
            (1.0, 1.0, 1.0)
        );

        let empty = edge_scores(&[], &[]);
        assert_eq!((empty.precision, empty.recall, empty.f1), (1.0, 1.0, 1.0));
        let loops_only = edge_scores(&[[4, 4]], &[]);
        assert_eq!(loops_only.f1, 1.0, "self-loops are ignored");
        let nothing_predicted = edge_scores(&[], &actual);
        assert_eq!(
            (
                nothing_predicted.precision,
                nothing_predicted.recall,
                nothing_predicted.f1
            ),
            (0.0, 0.0, 0.0)
        );
        let nothing_actual = edge_scores(&actual, &[]);
        assert_eq!(
            (
                nothing_actual.precision,
                nothing_actual.recall,
                nothing_actual.f1
            ),
            (0.0, 0.0, 0.0)
        );
        let disjoint = edge_scores(&[[5, 6]], &actual);
        assert_eq!((disjoint.precision, disjoint.f1), (0.0, 0.0));
    }

    #[test]
    fn row_distances() {
        let a = [Vec3::ZERO, Vec3::X];
        let b = [Vec3::new(0.0, 3.0, 4.0), Vec3::X];
        assert!((vertex_distance(&a, &b).unwrap() - 2.5).abs() < 1e-12);
        assert_eq!(normal_distance(&a, &a).unwrap(), 0.0);
        assert_eq!(
            vertex_distance(&a, &b[..1]),
            Err(MetricsError::LengthMismatch { pred: 2, gt: 1 })
        );
        assert!(matches!(
            normal_distance(&[], &[]),
            Err(MetricsError::EmptySet { .. })
        ));
    }
}
