//! Where stage 4's time goes with a pair head (`meshflow bench pair-head`, issue 15 item 8).
//!
//! A VAE with a pair head hands extraction an `n x n` matrix of refined distances instead of
//! the edge embeddings, and generation's extraction took 1.5x as long with it. This decodes one
//! generation's candidates once and extracts every candidate, single-threaded and repeatedly,
//! from three edge sources of the same decoded rows:
//!
//! 1. the edge embeddings, thresholded on the host: what the VAE without its head extracts;
//! 2. the spacetime distances of those embeddings as a distance matrix: the same graph and the
//!    same margins as 1, so the difference from 1 is the matrix's own cost;
//! 3. the pair head's distances (2 with the head's corrections): what generation extracts.
//!
//! The difference between 2 and 3 is the graph the head leads to: the edges and 3-cliques it
//! offers the manifold method.

use std::time::Duration;

use glam::Vec3;
use serde::Serialize;

use crate::eval::timing::{Timing, time};
use crate::extract::{
    DecodedEdges, DecodedVertices, ExtractError, ExtractOptions, ExtractReport,
    extract_from_decoded,
};
use crate::model::vae::spacetime_distances;
use crate::pipeline::generate::{
    DeviceEdges, GenerateError, GenerateOptions, Generator, candidate_extraction, check_samples,
    kept_slots, read_vec, vec3s,
};

/// How the figures are taken, recorded in the report so it reads alone.
const METHOD: &str = "one generation's candidates (--samples copies of the input, seeds seed + k, \
     all in the largest candidate's length bucket) sampled and decoded once; each candidate \
     extracted with the options generation's stage 4 uses, from each edge source: wall-clock \
     median over >= 5 runs and >= `seconds` per candidate after one warm-up run, one thread";

/// One candidate extracted from one edge source.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SourceTiming {
    /// Candidate edges (above `tau - candidate_slack`).
    pub edges: usize,
    /// 3-cliques of those edges: the candidate faces the manifold method ranks.
    pub clique_faces: usize,
    /// Faces extracted.
    pub faces: usize,
    #[serde(flatten)]
    pub timing: Timing,
}

/// One candidate, from the three edge sources.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CandidateTrace {
    /// Vertices the mask keeps.
    pub kept_vertices: usize,
    /// Source 1: the edge embeddings (the VAE without its head).
    pub embeddings: SourceTiming,
    /// Source 2: the embeddings' spacetime distances as a matrix.
    pub spacetime_distances: SourceTiming,
    /// Source 3: the pair head's distances (what generation extracts).
    pub pair_head_distances: SourceTiming,
}

/// Sums over the candidates of one source: median ms, edges and candidate faces.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct SourceTotal {
    pub median_ms: f64,
    pub edges: usize,
    pub clique_faces: usize,
    pub faces: usize,
}

/// The report of [`trace_pair_head_extraction`], written as JSON.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PairHeadTrace {
    /// How the figures were taken.
    pub method: &'static str,
    /// Vertex slots per decoded row.
    pub slots: usize,
    pub candidates: Vec<CandidateTrace>,
    /// Each source summed over the candidates.
    pub embeddings: SourceTotal,
    pub spacetime_distances: SourceTotal,
    pub pair_head_distances: SourceTotal,
}

/// Why the trace stopped.
#[derive(Debug, thiserror::Error)]
pub enum PairHeadTraceError {
    /// The shipped VAE has no pair head: there is nothing to compare.
    #[error("the VAE has no pair head (weights without one extract from the embeddings)")]
    NoPairHead,
    #[error(transparent)]
    Generate(#[from] GenerateError),
    #[error(transparent)]
    Extract(#[from] ExtractError),
}

/// Samples and decodes `opts.samples` candidates for `points` (input frame) once, then times
/// extracting each from the three edge sources (module doc), at least `per_candidate` each.
pub fn trace_pair_head_extraction(
    generator: &Generator<'_>,
    points: &[Vec3],
    opts: &GenerateOptions,
    per_candidate: Duration,
) -> Result<PairHeadTrace, PairHeadTraceError> {
    if generator.vae.decoder.pair_head.is_none() {
        return Err(PairHeadTraceError::NoPairHead);
    }
    // Generation's candidates: the input once per sample, seeded seed + k.
    check_samples(opts.samples)?;
    let inputs = vec![points.to_vec(); opts.samples];
    let one = GenerateOptions {
        samples: 1,
        ..opts.clone()
    };
    let prepared = generator.prepare(&inputs, &one)?;
    let latents = generator.sample(&prepared, opts, &mut |_, _| true)?;
    let out = generator.decode(latents, &opts.extract);
    let DeviceEdges::PairHead {
        embeddings,
        features,
    } = out.edges
    else {
        return Err(PairHeadTraceError::NoPairHead);
    };
    let n = prepared.slots;
    let mask_logits = read_vec(out.mask_logits)?;
    let positions = read_vec(out.positions)?;
    let normals = read_vec(out.normals)?;
    let dim = embeddings.dims()[2];
    let spacetime = read_vec(spacetime_distances(embeddings.clone()))?;
    let refined = generator
        .vae
        .edge_distances(embeddings.clone(), features, &kept_slots(&mask_logits, n))
        .map_err(GenerateError::Readback)?;
    let embeddings = read_vec(embeddings)?;

    let extract = candidate_extraction(&GenerateOptions {
        extract: opts.extract.at_tau_of(generator.vae_config),
        ..opts.clone()
    });
    let mut candidates = Vec::with_capacity(inputs.len());
    for k in 0..inputs.len() {
        let rows = k * n..(k + 1) * n;
        let (pos, nrm) = (
            vec3s(&positions[rows.start * 3..rows.end * 3]),
            vec3s(&normals[rows.start * 3..rows.end * 3]),
        );
        let decoded = |edges| DecodedVertices {
            mask_logits: &mask_logits[rows.clone()],
            positions: &pos,
            normals: &nrm,
            edges,
        };
        let from_embeddings = decoded(DecodedEdges::Embeddings {
            values: &embeddings[rows.start * dim..rows.end * dim],
            dim,
        });
        let from_spacetime = decoded(DecodedEdges::Distances {
            values: &spacetime[rows.start * n..rows.end * n],
        });
        let from_head = decoded(DecodedEdges::Distances {
            values: &refined[rows.start * n..rows.end * n],
        });
        let (_, report) = extract_from_decoded(&from_head, &extract)?;
        candidates.push(CandidateTrace {
            kept_vertices: report.kept_vertices,
            embeddings: time_source(&from_embeddings, &extract, per_candidate)?,
            spacetime_distances: time_source(&from_spacetime, &extract, per_candidate)?,
            pair_head_distances: time_source(&from_head, &extract, per_candidate)?,
        });
    }
    let total = |pick: fn(&CandidateTrace) -> &SourceTiming| {
        candidates
            .iter()
            .map(pick)
            .fold(SourceTotal::default(), |t, s| SourceTotal {
                median_ms: t.median_ms + s.timing.median_ms,
                edges: t.edges + s.edges,
                clique_faces: t.clique_faces + s.clique_faces,
                faces: t.faces + s.faces,
            })
    };
    Ok(PairHeadTrace {
        method: METHOD,
        slots: n,
        embeddings: total(|c| &c.embeddings),
        spacetime_distances: total(|c| &c.spacetime_distances),
        pair_head_distances: total(|c| &c.pair_head_distances),
        candidates,
    })
}

/// One candidate's extraction from one source: its report's counts and its time.
fn time_source(
    decoded: &DecodedVertices<'_>,
    opts: &ExtractOptions,
    per_candidate: Duration,
) -> Result<SourceTiming, ExtractError> {
    let (_, report): (_, ExtractReport) = extract_from_decoded(decoded, opts)?;
    let timing = time(per_candidate, || {
        // The same input as the run above, so the same result: only its time is wanted.
        let _ = std::hint::black_box(extract_from_decoded(decoded, opts));
    });
    Ok(SourceTiming {
        edges: report.edges,
        clique_faces: report.clique_faces,
        faces: report.faces,
        timing,
    })
}
