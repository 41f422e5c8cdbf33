//! Mesh extraction: decoded vertices -> edges -> faces -> mesh.
//!
//! Two methods share steps 1, 2 and 7 below. The default, [`ExtractMethod::Manifold`], takes
//! the 3-cliques of step 3 as candidates and accepts them best-first by the model's edge
//! margins into a manifold, consistently wound mesh, then fills small holes and drops tiny
//! pieces ([`crate::extract::manifold`]). On edge embeddings its candidates come from the pairs above
//! `tau - candidate_slack` (default 0.3): those with an edge below tau rank after all the
//! others and only close gaps where the decoder missed an edge. [`ExtractMethod::Paper`] is the paper's Algorithm 1 exactly
//! (steps 1-7), for comparing with the paper and the reference:
//!
//! 1. Keep the vertices whose mask logit is > 0 and clamp their normals to [-1, 1].
//! 2. Edges: vertices i < j are joined iff their spacetime distance exceeds `tau` (0.6):
//!    `d(h_i, h_j) = |s_i - s_j|^2 - |t_i - t_j|^2`, where `s` is the first half of the edge
//!    embedding ("space") and `t` the second half ("time"). Note the direction: edge iff d > tau.
//! 3. Faces: every 3-clique of the edge graph.
//! 4. Winding: with the triple sorted (a < b < c), the face is emitted as (a, c, b) when the unit
//!    geometric normal (b - a) x (c - a) points against the normalised mean of the three vertex
//!    normals (negative dot product); either normal falls back to +z when its length is <= 1e-8.
//! 5. Optional hole repair: the edges used by exactly one face form loops
//!    ([`crate::geometry::topology::boundary_loops`]); a loop of at most `max_hole_edges` vertices is
//!    fan-triangulated from its first vertex, and the new faces get the same winding rule. The
//!    paper fills quads only (k < 5, our default 4); the reference allows 10 or 20, which
//!    over-fills open borders.
//! 6. Optional (not in the paper): drop faces that would put a third face on an edge, keeping
//!    the best-supported ones (see [`FaceSupport`]).
//! 7. Compact: drop vertices no face uses.
//!
//! The edge list is the seam between the threshold and the rest: [`spacetime_edges`] is the CPU
//! threshold; a GPU kernel can produce the same list and call [`extract_mesh`] directly.

pub mod manifold;
pub mod overlap;
/// A mesh round-tripped through its ground-truth edges, and what extraction lost.
pub mod round_trip;
#[cfg(feature = "wgpu")]
pub mod threshold_gpu;

use std::collections::HashMap;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::Mesh;
use crate::extract::manifold::{ManifoldOptions, manifold_faces};
use crate::geometry::topology::{
    self, Edge, EdgeIncidence, boundary_loops, face_edges, sorted_face,
};

/// The paper's edge threshold on the spacetime distance.
pub const TAU: f32 = 0.6;

/// How edges become faces.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ExtractMethod {
    /// Candidate 3-cliques accepted best-first into a manifold, consistently wound mesh
    /// ([`crate::extract::manifold`]); the default.
    #[default]
    Manifold,
    /// The paper's Algorithm 1: every 3-clique is a face.
    Paper,
}

/// Options of [`extract_mesh`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ExtractOptions {
    /// Manifold (default) or the paper's Algorithm 1.
    pub method: ExtractMethod,
    /// Spacetime-distance threshold: an edge iff d > tau. Reconstruction and generation take
    /// their VAE's `tau` instead ([`Self::at_tau_of`]): it belongs to the decoder, whose
    /// training sets where edge and non-edge scores cross.
    pub tau: f32,
    /// Fan-fill boundary loops of at most `max_hole_edges` vertices.
    pub fill_holes: bool,
    /// Largest boundary loop (in vertices, = edges) that hole repair fills. Default 4 (quads).
    pub max_hole_edges: usize,
    /// Algorithm 1 only: drop faces that would make an edge non-manifold (a third face),
    /// keeping the best-supported ones. Off by default (the paper does not do it); the manifold
    /// method never makes such an edge.
    pub drop_non_manifold: bool,
    /// Manifold method only: remove connected pieces of fewer faces than this (0 or 1 keeps
    /// every piece).
    pub min_component_faces: usize,
    /// Manifold method on edge embeddings only: candidates are the 3-cliques of the pairs with
    /// `d > tau - candidate_slack`. Faces with an edge below `tau` have a negative score and
    /// come after every face Algorithm 1 would keep, so they only close gaps that the surer
    /// faces leave (where the decoder missed an edge). Must be >= 0.
    pub candidate_slack: f32,
    /// Manifold method only: refuse a face lying on an accepted face it shares at most one
    /// vertex with, within this many of its longest edges of its plane (a second layer;
    /// [`crate::extract::overlap`]). 0 (the default) turns the test off: on the decoder's own faces it
    /// refuses true ones too (validation CD x100 5.57 -> 6.53 at 0.5); surface completion
    /// ([`crate::surface::complete`]) applies its own. Must be >= 0.
    pub overlap_tolerance: f32,
    /// Remove vertices that no face uses and renumber the rest (keeping their order).
    pub compact: bool,
}

impl Default for ExtractOptions {
    fn default() -> Self {
        Self {
            method: ExtractMethod::Manifold,
            tau: TAU,
            fill_holes: true,
            max_hole_edges: 4,
            drop_non_manifold: false,
            min_component_faces: 2,
            candidate_slack: 0.3,
            overlap_tolerance: 0.0,
            compact: true,
        }
    }
}

impl ExtractOptions {
    /// These options at the threshold of the VAE that decoded the edges
    /// ([`crate::model::VaeConfig::tau`]): reconstruction and generation extract with it.
    pub fn at_tau_of(&self, vae: &crate::model::VaeConfig) -> Self {
        Self {
            tau: vae.tau,
            ..self.clone()
        }
    }

    /// The paper's Algorithm 1 with its defaults (quads filled, no filter).
    pub fn paper() -> Self {
        Self {
            method: ExtractMethod::Paper,
            ..Self::default()
        }
    }

    /// The manifold method's settings: hole filling and small pieces.
    pub fn manifold_options(&self) -> ManifoldOptions {
        ManifoldOptions {
            max_hole_edges: if self.fill_holes {
                self.max_hole_edges
            } else {
                0
            },
            min_component_faces: self.min_component_faces,
            overlap_tolerance: self.overlap_tolerance,
        }
    }

    /// Refuses combinations that would otherwise be silently ignored or meaningless.
    pub fn check(&self) -> Result<(), ExtractError> {
        if self.drop_non_manifold && self.method == ExtractMethod::Manifold {
            return Err(ExtractError::BadOptions(
                "drop_non_manifold applies to the paper's Algorithm 1 only (the manifold method never leaves a non-manifold edge)",
            ));
        }
        if !(self.candidate_slack >= 0.0 && self.candidate_slack.is_finite()) {
            return Err(ExtractError::BadOptions(
                "candidate_slack must be a finite number >= 0",
            ));
        }
        if !(self.overlap_tolerance >= 0.0 && self.overlap_tolerance.is_finite()) {
            return Err(ExtractError::BadOptions(
                "overlap_tolerance must be a finite number >= 0",
            ));
        }
        if !self.tau.is_finite() {
            return Err(ExtractError::BadOptions("tau must be finite"));
        }
        Ok(())
    }

    /// Whether extraction ranks faces by the edge embeddings' margins, so the embeddings (not
    /// only an edge list) must reach the host.
    pub fn uses_margins(&self) -> bool {
        self.method == ExtractMethod::Manifold || self.drop_non_manifold
    }
}

/// What extraction did, for the CLI and the web page to show.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct ExtractReport {
    pub input_vertices: usize,
    /// Vertices whose mask logit is > 0 (all of them when no mask is given).
    pub kept_vertices: usize,
    /// Distinct edges after dropping self-loops and duplicates.
    pub edges: usize,
    /// Faces found as 3-cliques (the manifold method's candidates).
    pub clique_faces: usize,
    /// Manifold method: candidates refused because no winding agreed with their neighbours,
    /// because they folded back onto a neighbour, or because they had no area.
    pub winding_faces_dropped: usize,
    pub folded_faces_dropped: usize,
    pub degenerate_faces_dropped: usize,
    /// Manifold method: pieces removed for having fewer than `min_component_faces` faces,
    /// and their faces.
    pub pieces_dropped: usize,
    pub piece_faces_dropped: usize,
    /// Boundary loops filled, and the faces that added.
    pub holes_filled: usize,
    pub hole_faces: usize,
    /// Boundary loops left open (longer than `max_hole_edges`, or repair off).
    pub holes_left: usize,
    /// Faces dropped (Algorithm 1's optional filter) or candidates refused (manifold method)
    /// because an edge already had two faces.
    pub non_manifold_faces_dropped: usize,
    /// Vertices removed by compaction.
    pub unreferenced_vertices_removed: usize,
    /// Faces in the output.
    pub faces: usize,
}

/// Bad input to extraction: always a caller's bug or a corrupt decoder output, never a panic.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ExtractError {
    #[error("{what} has {got} entries, expected {expected}")]
    LengthMismatch {
        what: &'static str,
        got: usize,
        expected: usize,
    },
    #[error("edge ({a}, {b}) names a vertex outside 0..{vertices}")]
    EdgeOutOfRange { a: u32, b: u32, vertices: usize },
    #[error("the edge embedding dimension must be even and non-zero, got {0}")]
    BadEmbeddingDim(usize),
    #[error("{what} contains a non-finite value at row {row}")]
    NonFinite { what: &'static str, row: usize },
    #[error("edge bit ({a}, {b}) joins a vertex the mask dropped")]
    MaskedEdge { a: u32, b: u32 },
    #[error("extraction options: {0}")]
    BadOptions(&'static str),
}

/// How the non-manifold filter ranks faces that compete for an edge.
#[derive(Clone, Copy, Debug)]
pub enum FaceSupport<'a> {
    /// By how well the face's geometric normal agrees with its vertex normals,
    /// `|dot(face normal, mean vertex normal)|`.
    Geometric,
    /// By the smallest margin `d - tau` over the face's three edges (the model's confidence),
    /// with the embeddings of the (kept) vertices, `dim` values per vertex.
    EdgeMargin { embeddings: &'a [f32], dim: usize },
    /// The same margin from given pair scores (a pair head's refined distances): `distances`
    /// is `n x n` row-major over the (kept) vertices, its upper triangle read.
    DistanceMargin { distances: &'a [f32] },
}

/// The spacetime distance between two edge embeddings of equal, even length.
pub fn spacetime_distance(a: &[f32], b: &[f32]) -> f32 {
    let half = a.len() / 2;
    let sq = |range: std::ops::Range<usize>| -> f32 {
        range.map(|k| (a[k] - b[k]) * (a[k] - b[k])).sum()
    };
    sq(0..half) - sq(half..a.len())
}

/// All pairs i < j of the `n = embeddings.len() / dim` vertices whose spacetime distance
/// exceeds `tau`, sorted lexicographically. This is the O(n^2 dim) hot spot of extraction.
///
/// It uses the expansion `d_ij = q_i + q_j - 2 <h_i, g_j>` with `q = |s|^2 - |t|^2` and
/// `g = [s, -t]`, so the inner loop is a blocked matrix product that vectorises (AVX2 where the
/// CPU has it, chosen at run time). Values agree with the direct formula to
/// ~1e-6 relative to |h|^2. Every code path does the same f32 operations in the same order, so
/// the edge list does not depend on the machine.
pub fn spacetime_edges(
    embeddings: &[f32],
    dim: usize,
    tau: f32,
) -> Result<Vec<Edge>, ExtractError> {
    if dim == 0 || !dim.is_multiple_of(2) {
        return Err(ExtractError::BadEmbeddingDim(dim));
    }
    if !embeddings.len().is_multiple_of(dim) {
        return Err(ExtractError::LengthMismatch {
            what: "embeddings",
            got: embeddings.len(),
            expected: embeddings.len() / dim * dim,
        });
    }
    if let Some(i) = embeddings.iter().position(|x| !x.is_finite()) {
        return Err(ExtractError::NonFinite {
            what: "embeddings",
            row: i / dim,
        });
    }
    Ok(run_threshold(
        embeddings,
        dim,
        tau,
        |block, edges| match dim {
            32 => threshold_dispatch::<32>(block, edges),
            _ => threshold_rows_any(block, edges),
        },
    ))
}

/// Lays out g^T and q for `kernel`, runs it, and sorts the edges it found.
fn run_threshold(
    embeddings: &[f32],
    dim: usize,
    tau: f32,
    kernel: impl Fn(&ThresholdBlock, &mut Vec<Edge>),
) -> Vec<Edge> {
    let n = embeddings.len() / dim;
    let half = dim / 2;
    // g^T laid out dimension-major and padded to a whole number of column blocks.
    let cols = n.div_ceil(MAX_COL_BLOCK) * MAX_COL_BLOCK;
    let mut g_t = vec![0.0f32; dim * cols];
    // Padding columns get q = -inf, so they never pass the threshold.
    let mut q = vec![f32::NEG_INFINITY; cols];
    for j in 0..n {
        let h = &embeddings[j * dim..(j + 1) * dim];
        for k in 0..dim {
            g_t[k * cols + j] = if k < half { h[k] } else { -h[k] };
        }
        q[j] = h[..half].iter().map(|x| x * x).sum::<f32>()
            - h[half..].iter().map(|x| x * x).sum::<f32>();
    }
    let block = ThresholdBlock {
        embeddings,
        dim,
        n,
        cols,
        g_t: &g_t,
        q: &q,
        tau,
    };
    let mut edges = Vec::new();
    kernel(&block, &mut edges);
    // Rows were visited in blocks; restore the lexicographic order callers rely on.
    edges.sort_unstable();
    edges
}

/// Columns are padded to a multiple of the widest column block any kernel build uses.
const MAX_COL_BLOCK: usize = 16;

struct ThresholdBlock<'a> {
    embeddings: &'a [f32],
    dim: usize,
    n: usize,
    cols: usize,
    g_t: &'a [f32],
    q: &'a [f32],
    tau: f32,
}

/// Picks the AVX2 build of the kernel when the CPU has it (6 x 16 accumulators fill its
/// sixteen 8-lane registers). Both builds run the same scalar operations in the same order (no
/// FMA contraction), so they give identical results. (An AVX-512 build measured several times
/// slower here: the vectoriser handles this kernel badly with 16 lanes.)
fn threshold_dispatch<const DIM: usize>(b: &ThresholdBlock, edges: &mut Vec<Edge>) {
    #[cfg(target_arch = "x86_64")]
    {
        if std::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2, checked just above.
            unsafe { threshold_rows_avx2::<DIM>(b, edges) };
            return;
        }
    }
    threshold_rows::<DIM, 4, 16>(b, edges)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn threshold_rows_avx2<const DIM: usize>(b: &ThresholdBlock, edges: &mut Vec<Edge>) {
    threshold_rows::<DIM, 6, 16>(b, edges)
}

/// The register-blocked kernel for embeddings of `DIM` values: `ROW_BLOCK` rows of h against
/// `COL_BLOCK` columns of g at a time, only for column blocks that reach past the diagonal.
/// Fixed sizes let the compiler keep the accumulators in vector registers.
// Index loops over fixed-size arrays are what the vectoriser turns into register blocks.
#[allow(clippy::needless_range_loop)]
#[inline(always)]
fn threshold_rows<const DIM: usize, const ROW_BLOCK: usize, const COL_BLOCK: usize>(
    b: &ThresholdBlock,
    edges: &mut Vec<Edge>,
) {
    let (n, cols) = (b.n, b.cols);
    let mut i0 = 0;
    while i0 < n {
        let rows = ROW_BLOCK.min(n - i0);
        let mut h = [[0.0f32; DIM]; ROW_BLOCK];
        for (r, row) in h.iter_mut().enumerate().take(rows) {
            row.copy_from_slice(&b.embeddings[(i0 + r) * DIM..(i0 + r + 1) * DIM]);
        }
        let mut j0 = (i0 + 1) / COL_BLOCK * COL_BLOCK;
        while j0 < cols {
            let mut acc = [[0.0f32; COL_BLOCK]; ROW_BLOCK];
            for k in 0..DIM {
                let g: &[f32; COL_BLOCK] = b.g_t[k * cols + j0..k * cols + j0 + COL_BLOCK]
                    .try_into()
                    .expect("block");
                for r in 0..ROW_BLOCK {
                    let hv = h[r][k];
                    for c in 0..COL_BLOCK {
                        acc[r][c] += hv * g[c];
                    }
                }
            }
            let qj: &[f32; COL_BLOCK] = b.q[j0..j0 + COL_BLOCK].try_into().expect("block");
            for (r, acc_row) in acc.iter().enumerate().take(rows) {
                let i = i0 + r;
                let qi = b.q[i];
                // Edges are rare (a few per vertex): test the whole row of the block with
                // vector compares and only walk it when something passed.
                let mut any = false;
                for c in 0..COL_BLOCK {
                    any |= qi + qj[c] - 2.0 * acc_row[c] > b.tau;
                }
                if any {
                    for (c, &dot) in acc_row.iter().enumerate() {
                        let j = j0 + c;
                        if j > i && qi + qj[c] - 2.0 * dot > b.tau {
                            edges.push([i as u32, j as u32]);
                        }
                    }
                }
            }
            j0 += COL_BLOCK;
        }
        i0 += ROW_BLOCK;
    }
}

/// The same computation for any embedding size (no model uses one other than 32; kept simple).
fn threshold_rows_any(b: &ThresholdBlock, edges: &mut Vec<Edge>) {
    let (dim, n, cols) = (b.dim, b.n, b.cols);
    for i in 0..n {
        let h = &b.embeddings[i * dim..(i + 1) * dim];
        for j in i + 1..n {
            let mut dot = 0.0f32;
            for (k, &hv) in h.iter().enumerate() {
                dot += hv * b.g_t[k * cols + j];
            }
            if b.q[i] + b.q[j] - 2.0 * dot > b.tau {
                edges.push([i as u32, j as u32]);
            }
        }
    }
}

/// Normalises a messy edge list ([`crate::geometry::topology::canonical_edges`]) after checking that
/// every edge names one of `num_vertices` vertices.
pub fn canonical_edges(edges: &[Edge], num_vertices: usize) -> Result<Vec<Edge>, ExtractError> {
    if let Some(&[a, b]) = edges
        .iter()
        .find(|e| e.iter().any(|&v| v as usize >= num_vertices))
    {
        return Err(ExtractError::EdgeOutOfRange {
            a,
            b,
            vertices: num_vertices,
        });
    }
    Ok(topology::canonical_edges(edges))
}

/// Every 3-clique (a < b < c) of a canonical edge list, sorted lexicographically.
///
/// Each edge is oriented from its lower- to its higher-ranked end, rank = (degree, index), and
/// for every vertex v the triangles are found by marking v's out-neighbours and scanning theirs.
/// Out-degrees are then at most sqrt(2m), so the work is O(m^1.5) even around a vertex joined to
/// everything (the pole of a cone), where a plain sorted-list intersection is quadratic.
pub fn triangles_of_edges(num_vertices: usize, edges: &[Edge]) -> Vec<[u32; 3]> {
    let mut degree = vec![0u32; num_vertices];
    for &[a, b] in edges {
        degree[a as usize] += 1;
        degree[b as usize] += 1;
    }
    let ranks_below = |a: u32, b: u32| (degree[a as usize], a) < (degree[b as usize], b);
    let mut offsets = vec![0u32; num_vertices + 1];
    for &[a, b] in edges {
        let from = if ranks_below(a, b) { a } else { b };
        offsets[from as usize + 1] += 1;
    }
    for v in 0..num_vertices {
        offsets[v + 1] += offsets[v];
    }
    let mut out = vec![0u32; edges.len()];
    let mut fill = offsets.clone();
    for &[a, b] in edges {
        let (from, to) = if ranks_below(a, b) { (a, b) } else { (b, a) };
        out[fill[from as usize] as usize] = to;
        fill[from as usize] += 1;
    }
    let out_of = |v: u32| &out[offsets[v as usize] as usize..offsets[v as usize + 1] as usize];
    let mut mark = vec![u32::MAX; num_vertices];
    let mut faces = Vec::new();
    for v in 0..num_vertices as u32 {
        for &u in out_of(v) {
            mark[u as usize] = v;
        }
        for &u in out_of(v) {
            for &w in out_of(u) {
                if mark[w as usize] == v {
                    faces.push(sorted_face([v, u, w]));
                }
            }
        }
    }
    faces.sort_unstable();
    faces
}

/// f32 on purpose (unlike [`crate::geometry::normals`]): the winding decision mirrors the reference's f32
/// arithmetic so near-degenerate faces turn out the same way.
fn unit_or_z(v: Vec3) -> Vec3 {
    let len = v.length();
    if len <= 1e-8 { Vec3::Z } else { v / len }
}

/// The unit geometric normal of (a, b, c) and the normalised mean of the vertex normals, each
/// +z when too short to normalise. Their dot product decides the winding.
fn orientation_dot(tri: [u32; 3], positions: &[Vec3], normals: &[Vec3]) -> f32 {
    let [a, b, c] = tri.map(|i| positions[i as usize]);
    let geometric = unit_or_z((b - a).cross(c - a));
    let [na, nb, nc] = tri.map(|i| normals[i as usize]);
    let mean = unit_or_z((na + nb + nc) / 3.0);
    geometric.dot(mean)
}

/// Winds the triangle `{a, b, c}` by the rule in the module doc: sorted, then flipped to
/// (a, c, b) when its geometric normal points against its vertex normals.
pub fn orient_face(tri: [u32; 3], positions: &[Vec3], normals: &[Vec3]) -> [u32; 3] {
    let t = sorted_face(tri);
    if orientation_dot(t, positions, normals) < 0.0 {
        [t[0], t[2], t[1]]
    } else {
        t
    }
}

/// Faces from an edge list by `opts.method`: the manifold method over the 3-cliques, or
/// Algorithm 1 (faces from 3-cliques, winding, optional non-manifold filter and hole repair);
/// then compaction. `normals` are clamped to [-1, 1] as the paper does.
pub fn extract_mesh(
    positions: &[Vec3],
    normals: &[Vec3],
    edges: &[Edge],
    support: FaceSupport,
    opts: &ExtractOptions,
) -> Result<(Mesh, ExtractReport), ExtractError> {
    opts.check()?;
    let n = positions.len();
    if normals.len() != n {
        return Err(ExtractError::LengthMismatch {
            what: "normals",
            got: normals.len(),
            expected: n,
        });
    }
    for (what, rows) in [("positions", positions), ("normals", normals)] {
        if let Some(row) = rows.iter().position(|p| !p.is_finite()) {
            return Err(ExtractError::NonFinite { what, row });
        }
    }
    if let FaceSupport::EdgeMargin { embeddings, dim } = support
        && embeddings.len() != n * dim
    {
        return Err(ExtractError::LengthMismatch {
            what: "embeddings",
            got: embeddings.len(),
            expected: n * dim,
        });
    }
    if let FaceSupport::DistanceMargin { distances } = support
        && distances.len() != n * n
    {
        return Err(ExtractError::LengthMismatch {
            what: "pair distances",
            got: distances.len(),
            expected: n * n,
        });
    }
    let normals: Vec<Vec3> = normals
        .iter()
        .map(|v| v.clamp(Vec3::splat(-1.0), Vec3::ONE))
        .collect();
    let edges = canonical_edges(edges, n)?;
    let mut report = ExtractReport {
        input_vertices: n,
        kept_vertices: n,
        edges: edges.len(),
        ..Default::default()
    };

    let cliques = triangles_of_edges(n, &edges);
    report.clique_faces = cliques.len();
    let mut faces: Vec<[u32; 3]> = cliques
        .iter()
        .map(|&t| orient_face(t, positions, &normals))
        .collect();

    if opts.method == ExtractMethod::Manifold {
        let scores = face_scores(&faces, positions, &normals, support, opts.tau);
        let (faces, r) = manifold_faces(positions, &faces, &scores, &opts.manifold_options());
        report.non_manifold_faces_dropped = r.rejected_non_manifold;
        report.winding_faces_dropped = r.rejected_winding;
        report.folded_faces_dropped = r.rejected_fold;
        report.degenerate_faces_dropped = r.rejected_degenerate;
        report.holes_filled = r.holes_filled;
        report.hole_faces = r.hole_faces;
        report.holes_left = r.holes_left;
        report.pieces_dropped = r.pieces_dropped;
        report.piece_faces_dropped = r.piece_faces_dropped;
        return Ok(finish(positions, normals, faces, opts, report));
    }

    if opts.drop_non_manifold {
        let before = faces.len();
        faces = drop_non_manifold_faces(faces, positions, &normals, support, opts.tau);
        report.non_manifold_faces_dropped = before - faces.len();
    }

    // A loop whose fan would repeat an existing face is left open: the boundary of a lone
    // triangle is a 3-loop (filling it makes a double-sided copy), and a partial fan would put
    // a third face on an edge.
    let mut existing: Vec<[u32; 3]> = faces.iter().map(|&f| sorted_face(f)).collect();
    existing.sort_unstable();
    // Under the non-manifold filter a fan must not undo it either: a diagonal that is already
    // an edge of the mesh (or of an earlier fan) would get a third face.
    let mut faces_on_edge: HashMap<Edge, u32> = HashMap::new();
    if opts.drop_non_manifold {
        for f in &faces {
            for e in face_edges(*f) {
                *faces_on_edge.entry(e).or_default() += 1;
            }
        }
    }
    for lp in boundary_loops(&faces) {
        let fan: Vec<[u32; 3]> = (1..lp.len() - 1)
            .map(|k| [lp[0], lp[k], lp[k + 1]])
            .collect();
        let repeats_a_face = fan
            .iter()
            .any(|&t| existing.binary_search(&sorted_face(t)).is_ok());
        let mut added: HashMap<Edge, u32> = HashMap::new();
        if opts.drop_non_manifold {
            for e in fan.iter().flat_map(|&t| face_edges(t)) {
                *added.entry(e).or_default() += 1;
            }
        }
        let breaks_manifold = added
            .iter()
            .any(|(e, n)| faces_on_edge.get(e).copied().unwrap_or(0) + n > 2);
        if opts.fill_holes && lp.len() <= opts.max_hole_edges && !repeats_a_face && !breaks_manifold
        {
            report.holes_filled += 1;
            report.hole_faces += fan.len();
            for (e, n) in added {
                *faces_on_edge.entry(e).or_default() += n;
            }
            faces.extend(fan.into_iter().map(|t| orient_face(t, positions, &normals)));
        } else {
            report.holes_left += 1;
        }
    }

    Ok(finish(positions, normals, faces, opts, report))
}

/// Step 7 and the face count: the mesh of `faces`, compacted when asked.
fn finish(
    positions: &[Vec3],
    normals: Vec<Vec3>,
    faces: Vec<[u32; 3]>,
    opts: &ExtractOptions,
    mut report: ExtractReport,
) -> (Mesh, ExtractReport) {
    let mut mesh = Mesh {
        positions: positions.to_vec(),
        normals,
        faces,
    };
    if opts.compact {
        report.unreferenced_vertices_removed = mesh.remove_unreferenced_vertices();
    }
    report.faces = mesh.faces.len();
    (mesh, report)
}

/// How well the model (or, from plain edges, the geometry) supports each face, higher is
/// better: the smallest margin `d - tau` over its three edges, or `|dot(face normal, mean
/// vertex normal)|`.
fn face_scores(
    faces: &[[u32; 3]],
    positions: &[Vec3],
    normals: &[Vec3],
    support: FaceSupport,
    tau: f32,
) -> Vec<f32> {
    let score = |f: &[u32; 3]| -> f32 {
        match support {
            FaceSupport::Geometric => orientation_dot(*f, positions, normals).abs(),
            FaceSupport::EdgeMargin { embeddings, dim } => {
                let h = |v: u32| &embeddings[v as usize * dim..(v as usize + 1) * dim];
                [(f[0], f[1]), (f[1], f[2]), (f[2], f[0])]
                    .iter()
                    .map(|&(a, b)| spacetime_distance(h(a), h(b)) - tau)
                    .fold(f32::INFINITY, f32::min)
            }
            FaceSupport::DistanceMargin { distances } => {
                let n = positions.len();
                let d = |a: u32, b: u32| distances[a.min(b) as usize * n + a.max(b) as usize];
                [(f[0], f[1]), (f[1], f[2]), (f[2], f[0])]
                    .iter()
                    .map(|&(a, b)| d(a, b) - tau)
                    .fold(f32::INFINITY, f32::min)
            }
        }
    };
    faces.iter().map(score).collect()
}

/// Greedy non-manifold filter: faces in order of decreasing support (ties by position in the
/// list) are accepted while each of their three edges has fewer than two accepted faces.
/// The result keeps the original relative order of the accepted faces.
fn drop_non_manifold_faces(
    faces: Vec<[u32; 3]>,
    positions: &[Vec3],
    normals: &[Vec3],
    support: FaceSupport,
    tau: f32,
) -> Vec<[u32; 3]> {
    let inc = EdgeIncidence::new(&faces);
    if inc.iter().all(|(_, uses)| uses.len() <= 2) {
        return faces;
    }
    let scores = face_scores(&faces, positions, normals, support, tau);
    let mut order: Vec<usize> = (0..faces.len()).collect();
    order.sort_by(|&x, &y| scores[y].total_cmp(&scores[x]).then(x.cmp(&y)));
    let edge_id = |a: u32, b: u32| {
        inc.edges
            .binary_search(&[a.min(b), a.max(b)])
            .expect("edge of a face")
    };
    let mut count = vec![0u8; inc.edges.len()];
    let mut keep = vec![false; faces.len()];
    for f in order {
        let [a, b, c] = faces[f];
        let ids = [edge_id(a, b), edge_id(b, c), edge_id(c, a)];
        if ids.iter().all(|&e| count[e] < 2) {
            for e in ids {
                count[e] += 1;
            }
            keep[f] = true;
        }
    }
    faces
        .into_iter()
        .zip(keep)
        .filter_map(|(f, k)| k.then_some(f))
        .collect()
}

/// The decoder's per-vertex outputs, row-major, for one mesh.
#[derive(Clone, Copy, Debug)]
pub struct DecodedVertices<'a> {
    /// One logit per vertex; a vertex is real when its logit is > 0.
    pub mask_logits: &'a [f32],
    pub positions: &'a [Vec3],
    pub normals: &'a [Vec3],
    pub edges: DecodedEdges<'a>,
}

/// Where a decoded mesh's edges come from.
#[derive(Clone, Copy, Debug)]
pub enum DecodedEdges<'a> {
    /// The edge embeddings, `dim` values per vertex, thresholded on the CPU after masking.
    Embeddings { values: &'a [f32], dim: usize },
    /// Pair scores compared with tau as spacetime distances are (a pair head's refined
    /// distances, [`crate::model::MeshVae::edge_distances`]): `n x n` row-major over all `n`
    /// decoded vertices, the upper triangle read; masked after reading.
    Distances { values: &'a [f32] },
    /// The bit matrix of the GPU threshold (`threshold_gpu`, feature `wgpu`), which has
    /// applied the mask and tau already; see [`edges_from_bits`].
    Bits {
        words: &'a [u32],
        words_per_row: usize,
    },
}

/// The edges `[i, j]`, i < j < n, of a bit matrix with `words_per_row` u32 words per vertex:
/// bit `j % 32` of word `i * words_per_row + j / 32` marks (i, j). Sorted lexicographically.
/// Bits at or below the diagonal are not edges and are ignored; a bit past the last vertex, or
/// a matrix of the wrong size, is an error.
pub fn edges_from_bits(
    words: &[u32],
    words_per_row: usize,
    n: usize,
) -> Result<Vec<Edge>, ExtractError> {
    if words_per_row < n.div_ceil(32) || words.len() != n * words_per_row {
        return Err(ExtractError::LengthMismatch {
            what: "edge bits",
            got: words.len(),
            expected: n * n.div_ceil(32),
        });
    }
    let mut edges = Vec::new();
    for (i, row) in words.chunks_exact(words_per_row.max(1)).enumerate() {
        for (w, &word) in row.iter().enumerate() {
            let mut rest = word;
            while rest != 0 {
                let j = w * 32 + rest.trailing_zeros() as usize;
                rest &= rest - 1;
                if j >= n {
                    return Err(ExtractError::EdgeOutOfRange {
                        a: i as u32,
                        b: j as u32,
                        vertices: n,
                    });
                }
                if j > i {
                    edges.push([i as u32, j as u32]);
                }
            }
        }
    }
    Ok(edges)
}

/// Checks that `values` holds `rows` rows of `width` finite values each (a decoder output read
/// back), naming `what` and the first bad row in the decoder's numbering.
fn check_rows(
    what: &'static str,
    values: &[f32],
    rows: usize,
    width: usize,
) -> Result<(), ExtractError> {
    if values.len() != rows * width {
        return Err(ExtractError::LengthMismatch {
            what,
            got: values.len(),
            expected: rows * width,
        });
    }
    match values.iter().position(|x| !x.is_finite()) {
        Some(i) => Err(ExtractError::NonFinite {
            what,
            row: i / width.max(1),
        }),
        None => Ok(()),
    }
}

/// The vertices the mask keeps: those whose logit is > 0, ascending. Extraction keeps these,
/// and a pair head picks its candidates among them.
pub fn kept_vertices(mask_logits: &[f32]) -> Vec<u32> {
    (0..mask_logits.len() as u32)
        .filter(|&i| mask_logits[i as usize] > 0.0)
        .collect()
}

/// Extraction on decoder outputs: mask, spacetime threshold (on the CPU, or already done on
/// the GPU), then [`extract_mesh`]. The manifold method and Algorithm 1's optional filter rank
/// faces by edge margin when the embeddings are at hand, and geometrically from edge bits.
pub fn extract_from_decoded(
    decoded: &DecodedVertices,
    opts: &ExtractOptions,
) -> Result<(Mesh, ExtractReport), ExtractError> {
    opts.check()?;
    let n = decoded.mask_logits.len();
    for (what, got, expected) in [
        ("positions", decoded.positions.len(), n),
        ("normals", decoded.normals.len(), n),
    ] {
        if got != expected {
            return Err(ExtractError::LengthMismatch {
                what,
                got,
                expected,
            });
        }
    }
    // Checked here, before masking, so a bad row is reported in the decoder's numbering.
    for (what, rows) in [
        ("positions", decoded.positions),
        ("normals", decoded.normals),
    ] {
        if let Some(row) = rows.iter().position(|p| !p.is_finite()) {
            return Err(ExtractError::NonFinite { what, row });
        }
    }
    let kept: Vec<usize> = kept_vertices(decoded.mask_logits)
        .into_iter()
        .map(|i| i as usize)
        .collect();
    let positions: Vec<Vec3> = kept.iter().map(|&i| decoded.positions[i]).collect();
    let normals: Vec<Vec3> = kept.iter().map(|&i| decoded.normals[i]).collect();
    // The manifold method takes candidate edges a little below tau (its faces are ranked
    // by their margins); Algorithm 1 thresholds at tau.
    let edge_tau = match opts.method {
        ExtractMethod::Manifold => opts.tau - opts.candidate_slack,
        ExtractMethod::Paper => opts.tau,
    };
    let (mesh, mut report) = match decoded.edges {
        DecodedEdges::Embeddings { values, dim } => {
            check_rows("embeddings", values, n, dim)?;
            let embeddings: Vec<f32> = kept
                .iter()
                .flat_map(|&i| values[i * dim..(i + 1) * dim].iter().copied())
                .collect();
            let edges = spacetime_edges(&embeddings, dim, edge_tau)?;
            let support = FaceSupport::EdgeMargin {
                embeddings: &embeddings,
                dim,
            };
            extract_mesh(&positions, &normals, &edges, support, opts)?
        }
        DecodedEdges::Distances { values } => {
            check_rows("pair distances", values, n, n)?;
            // The kept vertices' pairs, renumbered; `kept` is ascending, so a < b reads the
            // upper triangle.
            let k = kept.len();
            let mut distances = vec![0f32; k * k];
            for (a, &i) in kept.iter().enumerate() {
                for (b, &j) in kept.iter().enumerate().skip(a + 1) {
                    distances[a * k + b] = values[i * n + j];
                }
            }
            let edges: Vec<Edge> = (0..k)
                .flat_map(|a| (a + 1..k).map(move |b| (a, b)))
                .filter(|&(a, b)| distances[a * k + b] > edge_tau)
                .map(|(a, b)| [a as u32, b as u32])
                .collect();
            let support = FaceSupport::DistanceMargin {
                distances: &distances,
            };
            extract_mesh(&positions, &normals, &edges, support, opts)?
        }
        DecodedEdges::Bits {
            words,
            words_per_row,
        } => {
            // The kernel only marks kept pairs; renumber them as the kept vertices.
            let mut new_index = vec![u32::MAX; n];
            for (k, &i) in kept.iter().enumerate() {
                new_index[i] = k as u32;
            }
            let mut edges = Vec::new();
            for [i, j] in edges_from_bits(words, words_per_row, n)? {
                let (a, b) = (new_index[i as usize], new_index[j as usize]);
                if a == u32::MAX || b == u32::MAX {
                    return Err(ExtractError::MaskedEdge { a: i, b: j });
                }
                edges.push([a, b]);
            }
            extract_mesh(&positions, &normals, &edges, FaceSupport::Geometric, opts)?
        }
    };
    report.input_vertices = n;
    report.kept_vertices = kept.len();
    Ok((mesh, report))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::primitives::{grid, icosphere, octahedron};
    use crate::geometry::topology::{TopologyReport, edges, rotate_min_first};

    /// The web API passes options as JSON: a partial object takes the defaults for the rest,
    /// and a misspelt field is an error rather than silently ignored.
    #[test]
    fn options_from_partial_json() {
        let opts: ExtractOptions = serde_json::from_str(r#"{"drop_non_manifold": true}"#).unwrap();
        assert_eq!(
            opts,
            ExtractOptions {
                drop_non_manifold: true,
                ..Default::default()
            }
        );
        let err = serde_json::from_str::<ExtractOptions>(r#"{"drop_nonmanifold": true}"#);
        assert!(err.unwrap_err().to_string().contains("unknown field"));
    }

    fn area_weighted_normals(m: &Mesh) -> Vec<Vec3> {
        crate::geometry::normals::vertex_normals(&m.positions, &m.faces)
    }

    fn roundtrip(m: &Mesh, opts: &ExtractOptions) -> (Mesh, ExtractReport) {
        let normals = area_weighted_normals(m);
        extract_mesh(
            &m.positions,
            &normals,
            &edges(&m.faces),
            FaceSupport::Geometric,
            opts,
        )
        .unwrap()
    }

    fn canonical(faces: &[[u32; 3]]) -> Vec<[u32; 3]> {
        let mut out: Vec<[u32; 3]> = faces.iter().map(|&f| rotate_min_first(f)).collect();
        out.sort_unstable();
        out
    }

    #[test]
    fn ground_truth_edges_give_back_the_faces() {
        for m in [octahedron(), icosphere(2), grid(3, 3)] {
            let (out, report) = roundtrip(&m, &ExtractOptions::paper());
            assert_eq!(canonical(&out.faces), canonical(&m.faces));
            assert_eq!(report.holes_left, usize::from(m.faces.len() == 18));
            assert_eq!(report.unreferenced_vertices_removed, 0);
        }
    }

    #[test]
    fn cliques_around_a_high_degree_vertex_are_complete() {
        // A bipyramid: two poles joined to every vertex of a long rim. A quadratic clique search
        // would take many minutes at this size (no timing assertion: the suite's run time shows
        // it); the degree-ordered one takes milliseconds.
        let rim = 200_000u32;
        let (north, south) = (rim, rim + 1);
        let mut e: Vec<Edge> = Vec::new();
        for i in 0..rim {
            let j = (i + 1) % rim;
            e.extend([[i.min(j), i.max(j)], [i, north], [i, south]]);
        }
        e.sort_unstable();
        let t = triangles_of_edges(rim as usize + 2, &e);
        assert_eq!(t.len(), 2 * rim as usize);
        assert!(t.windows(2).all(|w| w[0] < w[1]));
    }

    #[test]
    fn every_kernel_build_finds_the_same_edges() {
        // CI's CPUs take the AVX2 path; the portable build and the any-size loop must agree
        // with it exactly (same operations in the same order), tails of every block size included.
        let mut rng = crate::rng::Rng::new(9);
        for n in [0usize, 1, 2, 5, 6, 7, 15, 16, 17, 37, 100, 203] {
            let emb: Vec<f32> = (0..n * 32).map(|_| rng.normal() as f32 * 0.3).collect();
            let portable = run_threshold(&emb, 32, TAU, threshold_rows::<32, 4, 16>);
            let wide = run_threshold(&emb, 32, TAU, threshold_rows::<32, 6, 16>);
            let any = run_threshold(&emb, 32, TAU, threshold_rows_any);
            let public = spacetime_edges(&emb, 32, TAU).unwrap();
            assert_eq!(portable, wide, "n={n}");
            assert_eq!(portable, any, "n={n}");
            assert_eq!(portable, public, "n={n}");
            assert!(n < 37 || !portable.is_empty());
        }
    }

    #[test]
    fn threshold_matches_direct_formula() {
        let mut rng = crate::rng::Rng::new(3);
        for &(n, dim) in &[(1, 32), (5, 32), (37, 32), (70, 8), (33, 80)] {
            let emb: Vec<f32> = (0..n * dim).map(|_| rng.normal() as f32 * 0.4).collect();
            let fast = spacetime_edges(&emb, dim, TAU).unwrap();
            let mut slow = Vec::new();
            for i in 0..n {
                for j in i + 1..n {
                    let d = spacetime_distance(
                        &emb[i * dim..(i + 1) * dim],
                        &emb[j * dim..(j + 1) * dim],
                    );
                    if d > TAU {
                        slow.push([i as u32, j as u32]);
                    }
                }
            }
            // Pairs within rounding of tau may differ between the two formulas.
            let near = |e: &Edge| {
                let (i, j) = (e[0] as usize, e[1] as usize);
                (spacetime_distance(&emb[i * dim..(i + 1) * dim], &emb[j * dim..(j + 1) * dim])
                    - TAU)
                    .abs()
                    < 1e-4
            };
            let differ: Vec<&Edge> = fast
                .iter()
                .filter(|e| !slow.contains(e))
                .chain(slow.iter().filter(|e| !fast.contains(e)))
                .collect();
            assert!(
                differ.iter().all(|e| near(e)),
                "n={n} dim={dim}: {differ:?}"
            );
            assert!(!slow.is_empty() || n < 2);
        }
    }

    #[test]
    fn bad_inputs_are_typed_errors() {
        assert_eq!(
            spacetime_edges(&[0.0; 6], 3, TAU),
            Err(ExtractError::BadEmbeddingDim(3))
        );
        assert_eq!(
            spacetime_edges(&[0.0; 6], 0, TAU),
            Err(ExtractError::BadEmbeddingDim(0))
        );
        assert!(matches!(
            spacetime_edges(&[0.0; 5], 4, TAU),
            Err(ExtractError::LengthMismatch { .. })
        ));
        assert!(matches!(
            spacetime_edges(&[0.0, f32::NAN, 0.0, 0.0], 2, TAU),
            Err(ExtractError::NonFinite { row: 0, .. })
        ));
        let m = octahedron();
        let normals = area_weighted_normals(&m);
        let e = extract_mesh(
            &m.positions,
            &normals,
            &[[0, 9]],
            FaceSupport::Geometric,
            &ExtractOptions::paper(),
        );
        assert_eq!(
            e.unwrap_err(),
            ExtractError::EdgeOutOfRange {
                a: 0,
                b: 9,
                vertices: 6
            }
        );
        let e = extract_mesh(
            &m.positions,
            &normals[..3],
            &[],
            FaceSupport::Geometric,
            &ExtractOptions::paper(),
        );
        assert!(matches!(
            e,
            Err(ExtractError::LengthMismatch {
                what: "normals",
                ..
            })
        ));
        let mut bad = m.positions.clone();
        bad[2].y = f32::INFINITY;
        let e = extract_mesh(
            &bad,
            &normals,
            &[],
            FaceSupport::Geometric,
            &ExtractOptions::paper(),
        );
        assert!(matches!(
            e,
            Err(ExtractError::NonFinite {
                what: "positions",
                row: 2
            })
        ));
    }

    #[test]
    fn hole_repair_respects_the_loop_size() {
        // Removing one edge of the octahedron opens a quad hole; default k = 4 fills it.
        let m = octahedron();
        let normals = area_weighted_normals(&m);
        let mut e = edges(&m.faces);
        e.retain(|&x| x != [0, 2]);
        let run = |opts: &ExtractOptions| {
            extract_mesh(&m.positions, &normals, &e, FaceSupport::Geometric, opts).unwrap()
        };
        let (filled, r) = run(&ExtractOptions::paper());
        assert_eq!(
            (filled.faces.len(), r.holes_filled, r.hole_faces),
            (8, 1, 2)
        );
        assert!(TopologyReport::of(&filled).is_clean_closed());
        let (open, r) = run(&ExtractOptions {
            max_hole_edges: 3,
            ..ExtractOptions::paper()
        });
        assert_eq!((open.faces.len(), r.holes_left), (6, 1));
        let (open, _) = run(&ExtractOptions {
            fill_holes: false,
            ..ExtractOptions::paper()
        });
        assert_eq!(open.faces.len(), 6);
    }

    #[test]
    fn non_manifold_filter_keeps_two_faces_per_edge() {
        // A closed octahedron plus an extra vertex near face (0,2,4) joined to 0, 2 and 4:
        // the edges (0,2), (2,4), (0,4) get three or four faces.
        let mut m = octahedron();
        m.positions.push(Vec3::new(0.6, 0.6, 0.6));
        let normals = {
            let mut n = area_weighted_normals(&m);
            n[6] = Vec3::new(1.0, 1.0, 1.0).normalize();
            n
        };
        let mut e = edges(&m.faces);
        e.extend([[0, 6], [2, 6], [4, 6]]);
        let opts = ExtractOptions {
            drop_non_manifold: true,
            fill_holes: false,
            ..ExtractOptions::paper()
        };
        let (kept, r) =
            extract_mesh(&m.positions, &normals, &e, FaceSupport::Geometric, &opts).unwrap();
        let t = TopologyReport::of(&kept);
        assert_eq!(t.non_manifold_edges, 0);
        assert!(r.non_manifold_faces_dropped >= 1);
        let (all, _) = extract_mesh(
            &m.positions,
            &normals,
            &e,
            FaceSupport::Geometric,
            &ExtractOptions {
                fill_holes: false,
                ..ExtractOptions::paper()
            },
        )
        .unwrap();
        assert!(TopologyReport::of(&all).non_manifold_edges > 0);
        assert_eq!(
            all.faces.len(),
            kept.faces.len() + r.non_manifold_faces_dropped
        );
    }

    #[test]
    fn candidate_slack_offers_faces_with_an_edge_just_below_tau() {
        // d(0,1) = 1 and d(1,2) = 1.5 are edges; d(0,2) = 0.5 is just below tau = 0.6.
        let emb = [
            0.0,
            0.0,
            0.0,
            0.0,
            1.0,
            0.0,
            0.0,
            0.0,
            0.0,
            1.0,
            0.5f32.sqrt(),
            0.0,
        ];
        let positions = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let normals = [Vec3::Z; 3];
        let decoded = DecodedVertices {
            mask_logits: &[1.0; 3],
            positions: &positions,
            normals: &normals,
            edges: DecodedEdges::Embeddings {
                values: &emb,
                dim: 4,
            },
        };
        let faces = |opts: ExtractOptions| extract_from_decoded(&decoded, &opts).unwrap().0.faces;
        let manifold = ExtractOptions {
            min_component_faces: 0,
            ..Default::default()
        };
        assert!((manifold.candidate_slack - 0.3).abs() < 1e-6);
        assert_eq!(faces(manifold.clone()), vec![[0, 1, 2]]);
        let strict = ExtractOptions {
            candidate_slack: 0.0,
            ..manifold
        };
        assert!(faces(strict).is_empty());
        assert!(faces(ExtractOptions::paper()).is_empty());
        // Options that would be ignored or meaningless are refused, not silently dropped.
        for bad in [
            ExtractOptions {
                drop_non_manifold: true,
                ..Default::default()
            },
            ExtractOptions {
                candidate_slack: -0.1,
                ..Default::default()
            },
            ExtractOptions {
                candidate_slack: f32::NAN,
                ..Default::default()
            },
        ] {
            assert!(matches!(
                extract_from_decoded(&decoded, &bad),
                Err(ExtractError::BadOptions(_))
            ));
        }
    }

    #[test]
    fn bit_rows_become_sorted_edges_above_the_diagonal() {
        // n = 40: two words per row; row 0 marks 1 and 33, row 1 marks itself (ignored) and 39.
        let mut words = vec![0u32; 80];
        words[0] = 1 << 1;
        words[1] = 1 << 1;
        words[2] = 1 << 1;
        words[3] = 1 << 7;
        assert_eq!(
            edges_from_bits(&words, 2, 40).unwrap(),
            vec![[0, 1], [0, 33], [1, 39]]
        );
        // A bit past the last vertex, and a matrix of the wrong size.
        words[5] = 1 << 8;
        assert!(matches!(
            edges_from_bits(&words, 2, 40),
            Err(ExtractError::EdgeOutOfRange { a: 2, b: 40, .. })
        ));
        assert!(edges_from_bits(&words[..78], 2, 40).is_err());
        assert!(edges_from_bits(&words[..40], 1, 40).is_err());
    }

    #[test]
    fn decoded_outputs_are_masked_then_thresholded() {
        // Three vertices whose embeddings put them pairwise at spacetime distance 1 > tau,
        // plus a masked-out one that would join them.
        let dim = 2;
        let emb = [0.0, 0.0, 1.0, 0.0, 2.0, 0.0, 1.0, 0.0];
        // Pairs: d(0,1) = 1, d(1,2) = 1, d(0,2) = 4.
        let positions = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::ONE];
        let normals = [Vec3::Z; 4];
        let decoded = DecodedVertices {
            mask_logits: &[1.0, 2.0, 0.5, -1.0],
            positions: &positions,
            normals: &normals,
            edges: DecodedEdges::Embeddings { values: &emb, dim },
        };
        let (mesh, r) = extract_from_decoded(&decoded, &ExtractOptions::paper()).unwrap();
        assert_eq!((r.input_vertices, r.kept_vertices, r.edges), (4, 3, 3));
        assert_eq!(mesh.faces, vec![[0, 1, 2]]);
        let bad = DecodedVertices {
            edges: DecodedEdges::Embeddings {
                values: &emb,
                dim: 3,
            },
            ..decoded
        };
        assert!(extract_from_decoded(&bad, &ExtractOptions::paper()).is_err());

        // The same edges as the GPU kernel's bit matrix give the same mesh.
        let words = [0b110, 0b100, 0, 0];
        let from_bits = DecodedVertices {
            edges: DecodedEdges::Bits {
                words: &words,
                words_per_row: 1,
            },
            ..decoded
        };
        let (bits_mesh, bits_r) =
            extract_from_decoded(&from_bits, &ExtractOptions::paper()).unwrap();
        assert_eq!(bits_mesh, mesh);
        assert_eq!(bits_r, r);
        // A bit that joins the masked-out vertex 3 is a broken matrix, not an edge.
        let words = [0b1110, 0b100, 0, 0];
        let masked = DecodedVertices {
            edges: DecodedEdges::Bits {
                words: &words,
                words_per_row: 1,
            },
            ..decoded
        };
        assert_eq!(
            extract_from_decoded(&masked, &ExtractOptions::paper()).unwrap_err(),
            ExtractError::MaskedEdge { a: 0, b: 3 }
        );
        // A non-finite row is named in the decoder's numbering, masked rows included.
        let mut nan = positions;
        nan[3].x = f32::NAN;
        let bad = DecodedVertices {
            positions: &nan,
            ..decoded
        };
        let err = extract_from_decoded(&bad, &ExtractOptions::paper()).unwrap_err();
        assert_eq!(
            err,
            ExtractError::NonFinite {
                what: "positions",
                row: 3
            }
        );
    }

    /// Pair distances given as a matrix (a pair head's) extract exactly as the embeddings they
    /// were computed from, with either method, masked vertices included; a matrix of the
    /// wrong size or with a NaN is refused.
    #[test]
    fn pair_distances_extract_as_the_embeddings_they_come_from() {
        let mut rng = crate::rng::Rng::new(17);
        let (n, dim) = (60, 8);
        let emb: Vec<f32> = (0..n * dim).map(|_| rng.normal() as f32 * 0.6).collect();
        let positions: Vec<Vec3> = (0..n)
            .map(|_| Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()))
            .collect();
        let normals = vec![Vec3::Z; n];
        let mask: Vec<f32> = (0..n)
            .map(|i| if i % 7 == 3 { -1.0 } else { 1.0 })
            .collect();
        let h = |i: usize| &emb[i * dim..(i + 1) * dim];
        let mut distances = vec![0f32; n * n];
        for i in 0..n {
            for j in 0..n {
                distances[i * n + j] = spacetime_distance(h(i), h(j));
            }
        }
        let decoded = DecodedVertices {
            mask_logits: &mask,
            positions: &positions,
            normals: &normals,
            edges: DecodedEdges::Embeddings { values: &emb, dim },
        };
        let from_matrix = DecodedVertices {
            edges: DecodedEdges::Distances { values: &distances },
            ..decoded
        };
        for opts in [
            ExtractOptions::paper(),
            ExtractOptions {
                tau: 0.5,
                ..Default::default()
            },
        ] {
            let (mesh, report) = extract_from_decoded(&decoded, &opts).unwrap();
            assert!(!mesh.faces.is_empty());
            assert_eq!(
                extract_from_decoded(&from_matrix, &opts).unwrap(),
                (mesh, report)
            );
        }
        let short = DecodedVertices {
            edges: DecodedEdges::Distances {
                values: &distances[1..],
            },
            ..decoded
        };
        assert!(extract_from_decoded(&short, &ExtractOptions::paper()).is_err());
        distances[5 * n + 9] = f32::NAN;
        let nan = DecodedVertices {
            edges: DecodedEdges::Distances { values: &distances },
            ..decoded
        };
        assert_eq!(
            extract_from_decoded(&nan, &ExtractOptions::paper()).unwrap_err(),
            ExtractError::NonFinite {
                what: "pair distances",
                row: 5
            }
        );
    }
}
