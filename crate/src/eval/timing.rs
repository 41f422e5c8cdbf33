//! Extraction and threshold timings (`meshflow bench extract`) beside the reference
//! implementation's figures (docs/design.md section 4): one thread, the median of repeated
//! runs of the [`crate::workloads`] inputs, so the criterion benches and the CLI time the same
//! work.

use std::time::{Duration, Instant};

use serde::Serialize;

use crate::extract::{ExtractError, ExtractMethod, TAU, spacetime_edges};
use crate::workloads::{icosphere_edges, over_connected_sphere, random_embeddings};

/// The reference implementation's extraction times on one CPU thread by icosphere vertex
/// count (docs/design.md section 4), in ms.
pub const REFERENCE_EXTRACT_MS: [(usize, f64); 4] =
    [(162, 47.0), (642, 185.0), (2562, 772.0), (10242, 3300.0)];

/// The reference implementation's spacetime-threshold times on one CPU thread by vertex
/// count, 32-dimensional embeddings (docs/design.md section 4), in ms.
pub const REFERENCE_THRESHOLD_MS: [(usize, f64); 4] =
    [(1024, 22.0), (2048, 106.0), (4096, 560.0), (8192, 2700.0)];

/// How the timings are taken, recorded in the report so the figures can be read alone.
const METHOD: &str = "wall-clock median over >= 5 runs and >= `seconds` per case after one warm-up run; \
                 single thread; extraction = extract_mesh (Algorithm 1, and the manifold method) on an \
                 icosphere's ground-truth edges (faces, winding, hole check, compaction) and on \
                 over-connected sphere graphs (8 nearest neighbours); threshold = spacetime_edges on \
                 N(0, 0.12^2) embeddings, tau = 0.6";

/// Wall-clock statistics of repeated runs.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Timing {
    /// Median run time.
    pub median_ms: f64,
    /// Fastest run time.
    pub min_ms: f64,
    /// Timed runs (the warm-up run not counted).
    pub runs: usize,
}

/// Runs `work` once to warm up, then repeatedly for at least `budget` (and at least 5 times).
pub fn time(budget: Duration, mut work: impl FnMut()) -> Timing {
    work();
    let mut samples = Vec::new();
    let start = Instant::now();
    while samples.len() < 5 || start.elapsed() < budget {
        let t = Instant::now();
        work();
        samples.push(t.elapsed().as_secs_f64() * 1e3);
    }
    samples.sort_by(f64::total_cmp);
    Timing {
        median_ms: samples[samples.len() / 2],
        min_ms: samples[0],
        runs: samples.len(),
    }
}

/// One timed input size.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Case {
    /// Vertices of the input.
    pub size: usize,
    /// Edges in (threshold) or faces out (extraction).
    pub output_count: usize,
    /// The time taken.
    #[serde(flatten)]
    pub timing: Timing,
    /// The reference implementation's time for this size, where it has one.
    pub reference_ms: Option<f64>,
    /// `reference_ms / median_ms`.
    pub speedup: Option<f64>,
}

impl Case {
    /// A case compared with the `reference` figure (size, ms) of the same size, if any.
    pub fn new(
        size: usize,
        output_count: usize,
        timing: Timing,
        reference: &[(usize, f64)],
    ) -> Self {
        let reference_ms = reference.iter().find(|r| r.0 == size).map(|r| r.1);
        let speedup = reference_ms.map(|r| r / timing.median_ms);
        Self {
            size,
            output_count,
            timing,
            reference_ms,
            speedup,
        }
    }
}

/// The report of [`bench_extract`], written as JSON.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ExtractBench {
    /// How the figures were taken.
    pub method: &'static str,
    /// The CPU's model name.
    pub cpu: String,
    /// Whether the CPU has AVX2 (the threshold's vector path).
    pub avx2: bool,
    /// Threads used (always 1, as the reference's figures).
    pub threads: usize,
    /// Algorithm 1 (`--extraction paper`) on an icosphere's ground-truth edges: the figure
    /// compared with the reference.
    pub extraction_from_edges: Vec<Case>,
    /// The default manifold method on the same edges.
    pub manifold_extraction_from_edges: Vec<Case>,
    /// Both methods on over-connected sphere graphs (8 nearest neighbours), where 3-cliques
    /// overlap everywhere as in an uncertain decoder's edges.
    pub paper_extraction_over_connected: Vec<Case>,
    /// The manifold method on the over-connected graphs.
    pub manifold_extraction_over_connected: Vec<Case>,
    /// [`spacetime_edges`] on N x 32 embeddings.
    pub spacetime_threshold_dim32: Vec<Case>,
}

/// Which list of [`ExtractBench`] a finished case went to, for progress output.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Series {
    /// Extraction from an icosphere's ground-truth edges.
    FromEdges(ExtractMethod),
    /// Extraction from an over-connected sphere graph.
    OverConnected(ExtractMethod),
    /// The spacetime threshold.
    Threshold,
}

/// Why the benchmark stopped.
#[derive(Debug, thiserror::Error)]
pub enum TimingError {
    /// Extraction did not give back an icosphere's faces from its own edges: timing it would
    /// time a bug.
    #[error("{0:?} extraction lost faces of the icosphere")]
    LostFaces(ExtractMethod),
    /// The threshold refused its input.
    #[error(transparent)]
    Extract(#[from] ExtractError),
}

/// Whether the CPU has AVX2, which the threshold uses when present.
pub fn has_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    return std::is_x86_feature_detected!("avx2");
    #[cfg(not(target_arch = "x86_64"))]
    false
}

/// Times extraction (both methods) on icospheres of 162..10,242 vertices and on over-connected
/// sphere graphs of 512 and 2,048 vertices, and the spacetime threshold on N x 32 embeddings
/// (N = 512..8,192), spending at least `budget` per case. `cpu` is recorded as given;
/// `on_case` sees each case as it finishes.
pub fn bench_extract(
    budget: Duration,
    cpu: String,
    on_case: &mut dyn FnMut(Series, &Case),
) -> Result<ExtractBench, TimingError> {
    let mut report = ExtractBench {
        method: METHOD,
        cpu,
        avx2: has_avx2(),
        threads: 1,
        extraction_from_edges: Vec::new(),
        manifold_extraction_from_edges: Vec::new(),
        paper_extraction_over_connected: Vec::new(),
        manifold_extraction_over_connected: Vec::new(),
        spacetime_threshold_dim32: Vec::new(),
    };
    for subdivisions in 2..=5 {
        let w = icosphere_edges(subdivisions);
        for method in [ExtractMethod::Paper, ExtractMethod::Manifold] {
            let faces = w.extract(method).0.faces.len();
            if Some(faces) != w.faces {
                return Err(TimingError::LostFaces(method));
            }
            let t = time(budget, || {
                std::hint::black_box(w.extract(method));
            });
            // Only Algorithm 1 has reference figures: the reference has no manifold method.
            let (list, reference) = match method {
                ExtractMethod::Paper => {
                    (&mut report.extraction_from_edges, &REFERENCE_EXTRACT_MS[..])
                }
                ExtractMethod::Manifold => (&mut report.manifold_extraction_from_edges, &[][..]),
            };
            let case = Case::new(w.positions.len(), faces, t, reference);
            on_case(Series::FromEdges(method), &case);
            list.push(case);
        }
    }
    for n in [512, 2048] {
        let w = over_connected_sphere(n, 8);
        for method in [ExtractMethod::Paper, ExtractMethod::Manifold] {
            let faces = w.extract(method).0.faces.len();
            let t = time(budget, || {
                std::hint::black_box(w.extract(method));
            });
            let list = match method {
                ExtractMethod::Paper => &mut report.paper_extraction_over_connected,
                ExtractMethod::Manifold => &mut report.manifold_extraction_over_connected,
            };
            let case = Case::new(n, faces, t, &[]);
            on_case(Series::OverConnected(method), &case);
            list.push(case);
        }
    }
    for n in [512, 1024, 2048, 4096, 8192] {
        let emb = random_embeddings(n, 32, 1);
        let count = spacetime_edges(&emb, 32, TAU)?.len();
        let t = time(budget, || {
            std::hint::black_box(spacetime_edges(&emb, 32, TAU).expect("valid"));
        });
        let case = Case::new(n, count, t, &REFERENCE_THRESHOLD_MS);
        on_case(Series::Threshold, &case);
        report.spacetime_threshold_dim32.push(case);
    }
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_warms_up_then_runs_at_least_five_times() {
        let mut calls = 0;
        let t = time(Duration::ZERO, || calls += 1);
        assert_eq!(t.runs, 5);
        assert_eq!(calls, 6, "one warm-up run, not counted");
        assert!(t.min_ms <= t.median_ms);
    }

    #[test]
    fn a_case_is_compared_with_the_reference_of_its_size() {
        let timing = |ms| Timing {
            median_ms: ms,
            min_ms: ms,
            runs: 5,
        };
        let c = Case::new(642, 1280, timing(18.5), &REFERENCE_EXTRACT_MS);
        assert_eq!(c.reference_ms, Some(185.0));
        assert_eq!(c.speedup, Some(10.0));
        let c = Case::new(643, 1280, timing(18.5), &REFERENCE_EXTRACT_MS);
        assert_eq!((c.reference_ms, c.speedup), (None, None));
    }

    #[test]
    fn a_case_serialises_with_its_timing_inline() {
        let c = Case::new(
            1024,
            7,
            Timing {
                median_ms: 2.0,
                min_ms: 1.0,
                runs: 9,
            },
            &REFERENCE_THRESHOLD_MS,
        );
        // The JSON's field names and order are what readers of bench/extract.json expect.
        assert_eq!(
            serde_json::to_string(&c).unwrap(),
            r#"{"size":1024,"output_count":7,"median_ms":2.0,"min_ms":1.0,"runs":9,"reference_ms":22.0,"speedup":11.0}"#
        );
    }
}
