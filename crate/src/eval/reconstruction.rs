//! `eval vae`: the shipped VAE's round trip over a set of meshes, with the paper's Table 3
//! figures (vertex and normal distance, edge precision / recall / F1), CD/HD x100 by
//! docs/design.md section 3 and the topology of the extracted meshes, per mesh and averaged.

use std::fmt;
use std::path::Path;

use burn::tensor::Device;
use serde::Serialize;

use crate::Mesh;
use crate::eval::edge_errors::{QuadDiagonals, WrongEdgeKinds};
use crate::eval::metrics::{CompareOptions, Comparison};
use crate::eval::sets::EvalSet;
use crate::eval::summary::{SurfaceSummary, bucketed};
use crate::extract::ExtractOptions;
use crate::io::WriteError;
use crate::model::MeshVae;
use crate::pipeline::reconstruct::{Reconstruction, ReconstructionMetrics, reconstruct_batch};
use crate::pipeline::shipped::VaeManifest;

/// Meshes per reconstruction batch.
pub const BATCH: usize = 8;

/// Mean figures over a set of reconstructed meshes.
#[derive(Clone, Debug, Default, Serialize)]
pub struct ReconstructionSummary {
    pub meshes: usize,
    pub vertex_distance_x100: f64,
    pub normal_distance_x100: f64,
    /// Mean of per-mesh precision / recall / F1.
    pub edge_precision: f64,
    pub edge_recall: f64,
    pub edge_f1: f64,
    /// F1 over all edges of all meshes pooled.
    pub edge_f1_pooled: f64,
    /// The false positives of all meshes pooled, by kind.
    pub wrong_edges: WrongEdgeKinds,
    /// The ground truth's quads of all meshes pooled: how their two diagonals score.
    pub quad_diagonals: QuadDiagonals,
    /// Mean per-mesh precision / recall / F1 of the extracted meshes' edges.
    pub mesh_edge_precision: f64,
    pub mesh_edge_recall: f64,
    pub mesh_edge_f1: f64,
    #[serde(flatten)]
    pub surface: SurfaceSummary,
    pub mask_errors: f64,
}

impl ReconstructionSummary {
    /// The means over `ms`.
    pub fn of(ms: &[&ReconstructionMetrics]) -> Self {
        let k = ms.len().max(1) as f64;
        let mean = |f: &dyn Fn(&ReconstructionMetrics) -> f64| {
            ms.iter().map(|m| f(m)).sum::<f64>() / k + 0.0
        };
        let (tp, fp, fn_) = ms.iter().fold((0, 0, 0), |(a, b, c), m| {
            (
                a + m.true_positive_edges,
                b + m.false_positive_edges,
                c + m.false_negative_edges,
            )
        });
        let p = tp as f64 / (tp + fp).max(1) as f64;
        let r = tp as f64 / (tp + fn_).max(1) as f64;
        let comparisons: Vec<Option<&Comparison>> =
            ms.iter().map(|m| m.comparison.as_ref()).collect();
        Self {
            meshes: ms.len(),
            vertex_distance_x100: mean(&|m| m.vertex_distance_x100),
            normal_distance_x100: mean(&|m| m.normal_distance_x100),
            edge_precision: mean(&|m| m.edge_precision),
            edge_recall: mean(&|m| m.edge_recall),
            edge_f1: mean(&|m| m.edge_f1),
            wrong_edges: ms
                .iter()
                .fold(WrongEdgeKinds::default(), |acc, m| acc + m.wrong_edges),
            quad_diagonals: ms
                .iter()
                .fold(QuadDiagonals::default(), |acc, m| acc + m.quad_diagonals),
            mesh_edge_precision: mean(&|m| m.mesh_edge_precision),
            mesh_edge_recall: mean(&|m| m.mesh_edge_recall),
            mesh_edge_f1: mean(&|m| m.mesh_edge_f1),
            edge_f1_pooled: if p + r > 0.0 {
                2.0 * p * r / (p + r)
            } else {
                0.0
            },
            surface: SurfaceSummary::of(&comparisons),
            mask_errors: mean(&|m| m.mask_errors as f64),
        }
    }
}

/// What `eval vae` writes as JSON.
#[derive(Serialize)]
pub struct VaeEvalReport {
    pub weights: String,
    pub weights_sha256: String,
    pub source: String,
    /// N / number of latents.
    pub token_compression: f64,
    /// Floats in (N x encoder input channels) over floats in (latents x latent dim).
    pub float_compression: f64,
    /// Meshes left out, and why: listed first, so a reader sees what the figures leave out.
    pub skipped: Vec<String>,
    pub all: ReconstructionSummary,
    /// Buckets by vertex count ([`crate::eval::summary::VERTEX_BUCKETS`]).
    pub buckets: Vec<(String, ReconstructionSummary)>,
    pub per_mesh: Vec<(String, ReconstructionMetrics)>,
}

/// The summary `meshflow eval vae` prints: skipped meshes first, then the means and buckets.
impl fmt::Display for VaeEvalReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = &self.all;
        for reason in &self.skipped {
            writeln!(f, "skipped: {reason}")?;
        }
        let (vd, nd, f1p) = (
            s.vertex_distance_x100,
            s.normal_distance_x100,
            s.edge_f1_pooled,
        );
        let (p, r, f1) = (s.edge_precision, s.edge_recall, s.edge_f1);
        let (cd, hd) = (s.surface.chamfer_x100, s.surface.hausdorff_x100);
        write!(
            f,
            "{} meshes: vertex x100 {vd:.3}, normal x100 {nd:.3}, ",
            s.meshes
        )?;
        write!(
            f,
            "edge P/R/F1 {p:.3}/{r:.3}/{f1:.3} (pooled F1 {f1p:.3}), "
        )?;
        writeln!(f, "CD x100 {cd:.3}, HD x100 {hd:.3}")?;
        let percent = |a: usize, b: usize| 100.0 * a as f64 / b.max(1) as f64;
        let w = &s.wrong_edges;
        let share = |k: usize| percent(k, w.total());
        let (qd, two) = (share(w.quad_diagonal), share(w.two_hops));
        let (near, far) = (share(w.near_in_space), share(w.far));
        write!(
            f,
            "  wrong edges: {qd:.0}% quad diagonals, {two:.0}% two hops, "
        )?;
        writeln!(
            f,
            "{near:.0}% near in space, {far:.0}% far (of {})",
            w.total()
        )?;
        let q = &s.quad_diagonals;
        let higher = percent(q.taken_scores_higher, q.quads);
        let both = percent(q.both_above_taken_higher, q.both_above_threshold);
        write!(
            f,
            "  quads' diagonals: the artist's scores higher in {higher:.0}% of {}; ",
            q.quads
        )?;
        write!(f, "both pass tau in {}, ", q.both_above_threshold)?;
        writeln!(f, "the artist's higher in {both:.0}% of those")?;
        let (mp, mr, mf) = (s.mesh_edge_precision, s.mesh_edge_recall, s.mesh_edge_f1);
        writeln!(
            f,
            "  the extracted meshes' edges: P/R/F1 {mp:.3}/{mr:.3}/{mf:.3}"
        )?;
        for (name, b) in &self.buckets {
            let (cd, hd) = (b.surface.chamfer_x100, b.surface.hausdorff_x100);
            write!(
                f,
                "  {name:>6} vertices: {:4} meshes, F1 {:.3}, ",
                b.meshes, b.edge_f1
            )?;
            writeln!(f, "CD x100 {cd:.3}, HD x100 {hd:.3}")?;
        }
        let t = &s.surface;
        let (out, gt) = (t.faces_out, t.faces_in);
        write!(
            f,
            "  extracted topology (mean per mesh): {out:.1} faces (gt {gt:.1}), "
        )?;
        write!(
            f,
            "{:.2} non-manifold edges, {:.2} holes, ",
            t.non_manifold_edges, t.holes
        )?;
        write!(
            f,
            "{:.2} components; {} with no faces",
            t.components, t.no_faces
        )
    }
}

/// Reconstructs every mesh of `set` with `vae` in batches of [`BATCH`], extracting with
/// `extract`, and summarises. A batch that fails as a whole (e.g. an extracted mesh with no
/// faces to sample) is retried mesh by mesh, so only the bad mesh is skipped (and listed).
/// With `meshes_dir`, each reconstruction is written as `I.glb` and its ground truth as
/// `I_gt.glb` (model frame), I being the mesh's position in the set. `progress` is called with
/// the meshes done after each batch. `weights` names the weights in the report.
#[allow(clippy::too_many_arguments)]
pub fn evaluate_vae(
    vae: &MeshVae,
    manifest: &VaeManifest,
    weights: &str,
    set: EvalSet,
    extract: &ExtractOptions,
    meshes_dir: Option<&Path>,
    device: &Device,
    progress: &mut dyn FnMut(usize),
) -> Result<VaeEvalReport, WriteError> {
    let cfg = &manifest.model;
    let EvalSet {
        meshes,
        mut skipped,
        source,
    } = set;
    let compare = CompareOptions::default();
    let mut per_mesh = Vec::new();
    let mut keep = |index: usize, name: &str, gt: &Mesh, r: Reconstruction| {
        if let Some(dir) = meshes_dir {
            crate::io::write_path(&r.mesh, &dir.join(format!("{index}.glb")))?;
            crate::io::write_path(gt, &dir.join(format!("{index}_gt.glb")))?;
        }
        per_mesh.push((name.to_owned(), r.metrics));
        Ok::<(), WriteError>(())
    };
    let mut done = 0;
    for (c, chunk) in meshes.chunks(BATCH).enumerate() {
        let batch: Vec<Mesh> = chunk.iter().map(|(_, m)| m.clone()).collect();
        match reconstruct_batch(vae, cfg, &batch, extract, &compare, device) {
            Ok(results) => {
                for (k, ((name, gt), r)) in chunk.iter().zip(results).enumerate() {
                    keep(c * BATCH + k, name, gt, r)?;
                }
            }
            Err(_) => {
                for (k, (name, m)) in chunk.iter().enumerate() {
                    let one = std::slice::from_ref(m);
                    match reconstruct_batch(vae, cfg, one, extract, &compare, device) {
                        Ok(mut r) => keep(c * BATCH + k, name, m, r.remove(0))?,
                        Err(e) => skipped.push(format!("{name}: {e}")),
                    }
                }
            }
        }
        done += chunk.len();
        progress(done);
    }
    let (all, buckets) = bucketed(
        &per_mesh,
        |(_, m)| m.vertices,
        |some| ReconstructionSummary::of(&some.iter().map(|(_, m)| m).collect::<Vec<_>>()),
    );
    Ok(VaeEvalReport {
        weights: weights.into(),
        weights_sha256: manifest.sha256.clone(),
        source,
        token_compression: cfg.merge_ratio() as f64,
        float_compression: (cfg.num_vertices * cfg.in_channels()) as f64
            / (cfg.num_latents * cfg.latent_dim) as f64,
        skipped,
        all,
        buckets,
        per_mesh,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_report_lists_skipped_meshes_first() {
        let report = VaeEvalReport {
            weights: String::new(),
            weights_sha256: String::new(),
            source: String::new(),
            token_compression: 1.0,
            float_compression: 1.0,
            skipped: vec!["a.obj: too big".into()],
            all: ReconstructionSummary::default(),
            buckets: vec![("<=256".into(), ReconstructionSummary::default())],
            per_mesh: Vec::new(),
        };
        let text = report.to_string();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "skipped: a.obj: too big");
        assert!(lines[1].starts_with("0 meshes: vertex x100 0.000, normal x100 0.000, "));
        let bucket = "   <=256 vertices:    0 meshes, F1 0.000, CD x100 0.000, HD x100 0.000";
        assert_eq!(lines[5], bucket);
        assert!(
            lines[6].ends_with("0.00 components; 0 with no faces"),
            "{text}"
        );
    }
}
