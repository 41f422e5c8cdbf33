//! VAE reconstruction of meshes: tokens -> encode (posterior mean) -> decode -> Algorithm 1,
//! with the paper's Table 3 figures per mesh (vertex and normal distance, edge
//! precision/recall/F1 against the ground-truth adjacency) and CD/HD by docs/design.md section 3.
//!
//! Inputs must already be cleaned and in the model frame (the data build's shards are; use
//! [`prepare`] for an arbitrary mesh file).

use std::fmt;

use burn::tensor::{Device, Tensor};
use glam::Vec3;
use serde::Serialize;

use crate::Mesh;
use crate::eval::edge_errors::{QuadDiagonals, WrongEdgeKinds, quad_diagonals, wrong_edge_kinds};
use crate::eval::metrics::{
    CompareOptions, Comparison, compare_meshes, edge_scores, normal_distance, vertex_distance,
};
use crate::extract::{
    DecodedEdges, DecodedVertices, ExtractOptions, ExtractReport, extract_from_decoded,
};
use crate::geometry::clean::{CleanOptions, clean};
use crate::geometry::normalize::Normalization;
use crate::model::tokens::{TokenError, VertexTokens, build_tokens};
use crate::model::{MeshVae, Trace, VaeConfig};

/// Why a mesh could not be reconstructed.
#[derive(Debug, thiserror::Error)]
pub enum ReconstructError {
    #[error("the mesh has no faces")]
    NoFaces,
    #[error("{vertices} vertices after welding; this VAE takes at most {max}")]
    TooManyVertices { vertices: usize, max: usize },
    #[error(transparent)]
    Tokens(#[from] TokenError),
    #[error(transparent)]
    Extract(#[from] crate::extract::ExtractError),
    #[error(transparent)]
    Metrics(#[from] crate::eval::metrics::MetricsError),
    #[error("reading back from the device failed: {0}")]
    Readback(String),
}

/// Cleans `mesh` (weld, drop degenerate and duplicate faces) and maps it into the model frame,
/// as the data build does. Returns the prepared mesh and the transform back to the input frame.
pub fn prepare(mesh: &Mesh) -> Result<(Mesh, Normalization), ReconstructError> {
    let (cleaned, _) = clean(mesh, &CleanOptions::default());
    if cleaned.faces.is_empty() {
        return Err(ReconstructError::NoFaces);
    }
    let aabb = cleaned.aabb().ok_or(ReconstructError::NoFaces)?;
    let norm = Normalization::to_model_frame(aabb);
    Ok((norm.apply_mesh(&cleaned), norm.inverse()))
}

/// Reconstructs one mesh as read from a file: [`prepare`]d, refused when it has more vertices
/// than the VAE takes, reconstructed as [`reconstruct_batch`] does with the default comparison
/// and mapped back to the input's frame (the figures stay in the metrics' frame).
pub fn reconstruct_mesh(
    vae: &MeshVae,
    cfg: &VaeConfig,
    mesh: &Mesh,
    extract: &ExtractOptions,
    device: &Device,
) -> Result<Reconstruction, ReconstructError> {
    let (model_frame, back) = prepare(mesh)?;
    let vertices = model_frame.positions.len();
    if vertices > cfg.num_vertices {
        let max = cfg.num_vertices;
        return Err(ReconstructError::TooManyVertices { vertices, max });
    }
    let compare = CompareOptions::default();
    let done = reconstruct_batch(vae, cfg, &[model_frame], extract, &compare, device)?;
    let r = done.into_iter().next().expect("one result per mesh");
    Ok(Reconstruction {
        mesh: back.apply_mesh(&r.mesh),
        metrics: r.metrics,
    })
}

/// `points` (in the model frame, like `gt`) in the frame of the metrics, docs/design.md
/// section 3: `gt`'s box mapped to [-0.5, 0.5], as CD and HD are. The model frame is twice
/// that size, so a vertex distance taken there reads double.
fn metric_frame(gt: &Mesh, points: &[Vec3]) -> Vec<Vec3> {
    let norm = gt
        .aabb()
        .map_or(Normalization::IDENTITY, Normalization::to_metric_frame);
    points.iter().map(|&p| norm.apply(p)).collect()
}

/// Per-mesh reconstruction figures. Distances are x100 like the paper's tables, in the
/// metrics' frame (the ground truth's box mapped to [-0.5, 0.5]).
#[derive(Clone, Debug, Serialize)]
pub struct ReconstructionMetrics {
    pub vertices: usize,
    pub faces: usize,
    pub vertex_distance_x100: f64,
    pub normal_distance_x100: f64,
    pub edge_precision: f64,
    pub edge_recall: f64,
    pub edge_f1: f64,
    pub true_positive_edges: usize,
    pub false_positive_edges: usize,
    pub false_negative_edges: usize,
    /// The false positives by how their two vertices relate in the ground truth.
    pub wrong_edges: WrongEdgeKinds,
    /// How the scores of the ground truth's quads' two diagonals compare.
    pub quad_diagonals: QuadDiagonals,
    /// The same scores for the edges of the extracted mesh, which is what a user gets: the
    /// extraction keeps some of the thresholded pairs (at most two faces an edge, consistent
    /// winding) and closes small holes with edges of its own.
    pub mesh_edge_precision: f64,
    pub mesh_edge_recall: f64,
    pub mesh_edge_f1: f64,
    /// Real vertices whose mask logit is <= 0, and padding tokens whose logit is > 0.
    pub mask_errors: usize,
    /// CD/HD and topology against the input; `None` when the extracted mesh has no faces to
    /// sample (counted as a failed reconstruction by the evaluation).
    pub comparison: Option<Comparison>,
    pub extract: ExtractReport,
}

/// The figures as `meshflow reconstruct` prints them: edge scores, counts, CD/HD, topology.
impl fmt::Display for ReconstructionMetrics {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (vd, nd) = (self.vertex_distance_x100, self.normal_distance_x100);
        let (p, r, f1) = (self.edge_precision, self.edge_recall, self.edge_f1);
        let (mp, mr, mf) = (
            self.mesh_edge_precision,
            self.mesh_edge_recall,
            self.mesh_edge_f1,
        );
        write!(
            f,
            "vertex dist x100 {vd:.3}, normal dist x100 {nd:.3}, edge P/R/F1 "
        )?;
        writeln!(
            f,
            "{p:.3}/{r:.3}/{f1:.3}, the extracted mesh's edges {mp:.3}/{mr:.3}/{mf:.3}"
        )?;
        let (v, faces) = (self.vertices, self.faces);
        let Some(c) = &self.comparison else {
            return write!(
                f,
                "{v} vertices / {faces} faces in; the extracted mesh has no faces"
            );
        };
        let t = &c.pred_topology;
        writeln!(
            f,
            "{v} vertices / {faces} faces in; {} vertices / {} faces out",
            t.vertices, t.faces
        )?;
        let (cd, hd) = (c.chamfer_x100, c.hausdorff_x100);
        write!(
            f,
            "CD x100 {cd:.3}, HD x100 {hd:.3}; boundary edges {}, ",
            t.boundary_edges
        )?;
        write!(
            f,
            "non-manifold edges {}, holes {}, ",
            t.non_manifold_edges, t.holes
        )?;
        write!(f, "components {}", t.components)
    }
}

/// One reconstructed mesh and its figures.
pub struct Reconstruction {
    pub mesh: Mesh,
    pub metrics: ReconstructionMetrics,
}

fn read(t: Tensor<3>) -> Result<Vec<f32>, ReconstructError> {
    t.try_into_data()
        .map_err(|e| ReconstructError::Readback(e.to_string()))?
        .convert::<f32>()
        .try_into_vec::<f32>()
        .map_err(|e| ReconstructError::Readback(e.to_string()))
}

fn vec3s(flat: &[f32]) -> Vec<Vec3> {
    flat.chunks_exact(3).map(Vec3::from_slice).collect()
}

/// The edges of `mesh`, extracted from the decoded slots `positions` whose `mask` logit is > 0,
/// in slot numbers. Extraction copies those slots' positions unchanged and only drops
/// unreferenced vertices, so a position names its slot. A position two kept slots share names
/// neither: its vertex gets a number past every slot, so its edges count as wrong.
fn mesh_edges_in_slots(mesh: &Mesh, positions: &[Vec3], mask: &[f32]) -> Vec<[u32; 2]> {
    let key = |p: Vec3| p.to_array().map(f32::to_bits);
    let mut slot_of = std::collections::HashMap::new();
    for (i, &p) in positions.iter().enumerate() {
        if mask[i] > 0.0 {
            slot_of
                .entry(key(p))
                .and_modify(|s| *s = None)
                .or_insert(Some(i as u32));
        }
    }
    let unmatched = positions.len() as u32;
    let slots: Vec<u32> = mesh
        .positions
        .iter()
        .enumerate()
        .map(|(v, &p)| {
            slot_of
                .get(&key(p))
                .copied()
                .flatten()
                .unwrap_or(unmatched + v as u32)
        })
        .collect();
    crate::geometry::topology::edges(&mesh.faces)
        .iter()
        .map(|&[a, b]| [slots[a as usize], slots[b as usize]])
        .collect()
}

/// Reconstructs a batch of model-frame meshes (each with at most N vertices) in one forward
/// pass, extracts each with `extract` at the VAE's tau, and scores it against its input.
pub fn reconstruct_batch(
    vae: &MeshVae,
    cfg: &VaeConfig,
    meshes: &[Mesh],
    extract: &ExtractOptions,
    compare: &CompareOptions,
    device: &Device,
) -> Result<Vec<Reconstruction>, ReconstructError> {
    if meshes.is_empty() {
        return Ok(Vec::new());
    }
    // With length buckets a forward pass holds one length: split the batch by slot count and
    // put the results back in input order.
    let slots: Vec<usize> = meshes
        .iter()
        .map(|m| cfg.slots_for(m.positions.len()))
        .collect();
    if slots.iter().any(|&s| s != slots[0]) {
        let mut results: Vec<Option<Reconstruction>> = (0..meshes.len()).map(|_| None).collect();
        let mut lengths = slots.clone();
        lengths.sort_unstable();
        lengths.dedup();
        for len in lengths {
            let members: Vec<usize> = (0..meshes.len()).filter(|&i| slots[i] == len).collect();
            let group: Vec<Mesh> = members.iter().map(|&i| meshes[i].clone()).collect();
            let done = reconstruct_batch(vae, cfg, &group, extract, compare, device)?;
            for (i, r) in members.into_iter().zip(done) {
                results[i] = Some(r);
            }
        }
        return Ok(results
            .into_iter()
            .map(|r| r.expect("every mesh is in one group"))
            .collect());
    }
    let tokens: Vec<VertexTokens> = meshes
        .iter()
        .map(|m| {
            if m.faces.is_empty() {
                return Err(ReconstructError::NoFaces);
            }
            Ok(build_tokens(m, &cfg.tokens_for(m.positions.len()), 0)?)
        })
        .collect::<Result<_, _>>()?;
    let (b, n, c) = (tokens.len(), slots[0], cfg.in_channels());
    let features: Vec<f32> = tokens
        .iter()
        .flat_map(|t| t.features.iter().copied())
        .collect();
    let x = Tensor::from_data(burn::tensor::TensorData::new(features, [b, n, c]), device);
    let posterior = vae.encode(x, &mut Trace::default());
    let out = vae.decode(posterior.mean, &mut Trace::default());
    let reals: Vec<Vec<u32>> = tokens
        .iter()
        .map(|t| (0..t.num_real as u32).collect())
        .collect();
    let distances = vae
        .edge_distances(out.edge_embeddings.clone(), out.features.clone(), &reals)
        .map_err(ReconstructError::Readback)?;
    let logits = read(out.mask_logits)?;
    // A pair head rescores candidates among the vertices the mask keeps, as in generation;
    // the edge scores above pick them among the ground truth's real vertices.
    let kept_distances = if vae.decoder.pair_head.is_some() {
        let kept = crate::pipeline::generate::kept_slots(&logits, n);
        Some(
            vae.edge_distances(out.edge_embeddings.clone(), out.features.clone(), &kept)
                .map_err(ReconstructError::Readback)?,
        )
    } else {
        None
    };
    let positions = read(out.positions)?;
    let normals = read(out.normals)?;
    let embeddings = read(out.edge_embeddings)?;
    let e = cfg.edge_dim;
    let extract = extract.at_tau_of(cfg);

    let mut results = Vec::with_capacity(b);
    for (k, (t, gt)) in tokens.iter().zip(meshes).enumerate() {
        let rows = k * n..(k + 1) * n;
        let pos = vec3s(&positions[rows.start * 3..rows.end * 3]);
        let nrm = vec3s(&normals[rows.start * 3..rows.end * 3]);
        let real = t.num_real;
        // Edges among the real tokens, for the Table 3 edge scores.
        let plane = &distances[k * n * n..(k + 1) * n * n];
        let mut predicted = Vec::new();
        for i in 0..real {
            for j in i + 1..real {
                if plane[i * n + j] > cfg.tau {
                    predicted.push([i as u32, j as u32]);
                }
            }
        }
        let scores = edge_scores(&predicted, &t.edges);
        let wrong_edges = wrong_edge_kinds(&predicted, &t.edges, &t.positions[..real]);
        let quad_diagonals = quad_diagonals(
            &t.edges,
            real,
            |a, b| plane[a.min(b) as usize * n + a.max(b) as usize],
            cfg.tau,
        );
        let mask = &logits[rows.clone()];
        let mask_errors = mask
            .iter()
            .zip(&t.mask)
            .filter(|(l, m)| (**l > 0.0) != **m)
            .count();
        let decoded = DecodedVertices {
            mask_logits: mask,
            positions: &pos,
            normals: &nrm,
            edges: match &kept_distances {
                Some(values) => DecodedEdges::Distances {
                    values: &values[rows.start * n..rows.end * n],
                },
                None => DecodedEdges::Embeddings {
                    values: &embeddings[rows.start * e..rows.end * e],
                    dim: e,
                },
            },
        };
        let (mesh, report) = extract_from_decoded(&decoded, &extract)?;
        let mesh_scores = edge_scores(&mesh_edges_in_slots(&mesh, &pos, mask), &t.edges);
        let comparison = if mesh.faces.is_empty() {
            None
        } else {
            Some(compare_meshes(&mesh, gt, compare)?)
        };
        results.push(Reconstruction {
            metrics: ReconstructionMetrics {
                vertices: real,
                faces: gt.faces.len(),
                vertex_distance_x100: 100.0
                    * vertex_distance(
                        &metric_frame(gt, &pos[..real]),
                        &metric_frame(gt, &t.positions[..real]),
                    )?,
                normal_distance_x100: 100.0 * normal_distance(&nrm[..real], &t.normals[..real])?,
                edge_precision: scores.precision,
                edge_recall: scores.recall,
                edge_f1: scores.f1,
                true_positive_edges: scores.true_positives,
                false_positive_edges: scores.predicted - scores.true_positives,
                false_negative_edges: scores.actual - scores.true_positives,
                wrong_edges,
                quad_diagonals,
                mesh_edge_precision: mesh_scores.precision,
                mesh_edge_recall: mesh_scores.recall,
                mesh_edge_f1: mesh_scores.f1,
                mask_errors,
                comparison,
                extract: report,
            },
            mesh,
        });
    }
    Ok(results)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn metrics_without_faces_say_so() {
        let m = ReconstructionMetrics {
            vertices: 8,
            faces: 12,
            vertex_distance_x100: 1.0,
            normal_distance_x100: 2.0,
            edge_precision: 0.5,
            edge_recall: 0.25,
            edge_f1: 1.0 / 3.0,
            true_positive_edges: 1,
            false_positive_edges: 1,
            false_negative_edges: 3,
            wrong_edges: WrongEdgeKinds::default(),
            quad_diagonals: QuadDiagonals::default(),
            mesh_edge_precision: 0.0,
            mesh_edge_recall: 0.0,
            mesh_edge_f1: 0.0,
            mask_errors: 0,
            comparison: None,
            extract: ExtractReport::default(),
        };
        assert_eq!(
            m.to_string(),
            "vertex dist x100 1.000, normal dist x100 2.000, edge P/R/F1 0.500/0.250/0.333, the \
             extracted mesh's edges 0.000/0.000/0.000\n8 vertices / 12 faces in; the extracted \
             mesh has no faces"
        );
    }
    use crate::eval::metrics::vertex_distance;
    use crate::geometry::primitives::cube;

    #[test]
    fn the_extracted_meshs_edges_are_named_by_their_slots() {
        // Slot 1 is masked out, so X names slot 2 alone and the mesh's vertices 0, 1, 2 are
        // slots 0, 2, 3; Z, which no slot decoded, and Y, which two kept slots share in the
        // second case, are numbered past the slots.
        let slots = [Vec3::ZERO, Vec3::X, Vec3::X, Vec3::Y];
        let mesh = Mesh::new(
            vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z],
            vec![[0, 1, 2], [1, 3, 2]],
        );
        let mut got = mesh_edges_in_slots(&mesh, &slots, &[1.0, -1.0, 1.0, 1.0]);
        got.sort_unstable();
        assert_eq!(got, vec![[0, 2], [0, 3], [2, 3], [2, 7], [3, 7]]);
        let shared = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Y];
        let mut got = mesh_edges_in_slots(&mesh, &shared, &[1.0; 4]);
        got.sort_unstable();
        assert_eq!(got, vec![[0, 1], [0, 6], [1, 6], [1, 7], [6, 7]]);
    }

    #[test]
    fn a_mesh_is_reconstructed_in_its_own_frame_and_refused_over_the_vaes_size() {
        use crate::geometry::primitives::icosphere;
        let device = Device::flex();
        let cfg = VaeConfig::vae_small();
        let vae = crate::model::seeded_init(MeshVae::new(&cfg, &device), 1);
        let extract = ExtractOptions::default();
        let big = icosphere(2);
        match reconstruct_mesh(&vae, &cfg, &big, &extract, &device) {
            Err(ReconstructError::TooManyVertices { vertices, max }) => {
                assert_eq!((vertices, max), (big.positions.len(), cfg.num_vertices));
            }
            other => panic!("expected a refusal, got {:?}", other.err()),
        }
        // Far from the origin: what comes back lies around the input, not in the model frame.
        let mut far = cube();
        far.positions
            .iter_mut()
            .for_each(|p| *p = *p * 10.0 + Vec3::splat(100.0));
        let r = reconstruct_mesh(&vae, &cfg, &far, &extract, &device).unwrap();
        assert_eq!(r.metrics.vertices, 8);
        let centre = far.aabb().unwrap().center();
        for p in &r.mesh.positions {
            assert!(p.distance(centre) < centre.length() / 2.0, "{p}");
        }
    }

    #[test]
    fn vertex_distance_is_taken_in_the_metrics_frame() {
        // A model-frame cube spans [-1, 1]; the metrics' frame maps its box to [-0.5, 0.5], so
        // a uniform offset of 0.1 model units reads 0.05 there.
        let gt = Normalization::to_model_frame(cube().aabb().unwrap()).apply_mesh(&cube());
        let moved: Vec<Vec3> = gt
            .positions
            .iter()
            .map(|&p| p + Vec3::new(0.1, 0.0, 0.0))
            .collect();
        let d = vertex_distance(
            &metric_frame(&gt, &moved),
            &metric_frame(&gt, &gt.positions),
        );
        assert!((d.unwrap() - 0.05).abs() < 1e-6);
        let box_after = Mesh {
            positions: metric_frame(&gt, &gt.positions),
            ..gt.clone()
        };
        let b = box_after.aabb().unwrap();
        assert!((b.max_extent() - 1.0).abs() < 1e-6 && (b.min.x + 0.5).abs() < 1e-6);
    }
}
