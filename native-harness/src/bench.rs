//! `meshflow bench extract`: extraction and threshold timings as JSON, beside the reference
//! implementation's figures (docs/design.md section 4). One thread; median of repeated runs.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use clap::Subcommand;
use meshflow::extract::{ExtractMethod, TAU, spacetime_edges};
use meshflow::workloads::{icosphere_edges, over_connected_sphere, random_embeddings};
use serde::Serialize;

#[derive(Subcommand)]
pub enum BenchCommand {
    /// Extraction from ground-truth edges on icospheres (162..10,242 vertices) and the spacetime
    /// threshold on N x 32 embeddings (N = 512..8,192).
    Extract {
        /// Where to write the JSON.
        #[arg(short, long, default_value = "bench/extract.json")]
        output: PathBuf,
        /// Minimum time spent per case, in seconds (more runs, steadier medians).
        #[arg(long, default_value_t = 1.0)]
        seconds: f64,
    },
    /// The whole generation (condition, sample, decode, extract) with the shipped models on
    /// a point cloud, repeated; median per-stage times.
    Generate(crate::generate::BenchGenerateArgs),
    /// One MeshVAE training step on the CPU, part by part (data, encoder, decoder, losses,
    /// pairwise adjacency, backward, optimiser, EMA), with matrix-product FLOP/s against the
    /// CPU backend's measured matmul peak.
    TrainVae(crate::train::BenchTrainVaeArgs),
}

/// The reference implementation's times on one CPU thread (docs/design.md section 4), in ms.
const REFERENCE_EXTRACT_MS: [(usize, f64); 4] =
    [(162, 47.0), (642, 185.0), (2562, 772.0), (10242, 3300.0)];
const REFERENCE_THRESHOLD_MS: [(usize, f64); 4] =
    [(1024, 22.0), (2048, 106.0), (4096, 560.0), (8192, 2700.0)];

#[derive(Serialize)]
struct Timing {
    median_ms: f64,
    min_ms: f64,
    runs: usize,
}

/// Runs `work` once to warm up, then repeatedly for at least `budget` (and at least 5 times).
fn time(budget: Duration, mut work: impl FnMut()) -> Timing {
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

#[derive(Serialize)]
struct Case {
    size: usize,
    /// Edges in (threshold) or faces out (extraction).
    output_count: usize,
    #[serde(flatten)]
    timing: Timing,
    reference_ms: Option<f64>,
    speedup: Option<f64>,
}

#[derive(Serialize)]
struct Report {
    method: &'static str,
    cpu: String,
    avx2: bool,
    threads: usize,
    /// Algorithm 1 (`--extraction paper`) on an icosphere's ground-truth edges: the figure
    /// compared with the reference.
    extraction_from_edges: Vec<Case>,
    /// The default manifold method on the same edges.
    manifold_extraction_from_edges: Vec<Case>,
    /// Both methods on over-connected sphere graphs (8 nearest neighbours), where 3-cliques
    /// overlap everywhere as in an uncertain decoder's edges.
    paper_extraction_over_connected: Vec<Case>,
    manifold_extraction_over_connected: Vec<Case>,
    spacetime_threshold_dim32: Vec<Case>,
}

fn case(size: usize, output_count: usize, timing: Timing, reference: &[(usize, f64)]) -> Case {
    let reference_ms = reference.iter().find(|r| r.0 == size).map(|r| r.1);
    let speedup = reference_ms.map(|r| r / timing.median_ms);
    Case {
        size,
        output_count,
        timing,
        reference_ms,
        speedup,
    }
}

fn has_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    return std::is_x86_feature_detected!("avx2");
    #[cfg(not(target_arch = "x86_64"))]
    false
}

pub fn cpu_name() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_string())
        })
        .unwrap_or_else(|| "unknown".into())
}

pub fn run(which: BenchCommand) -> Result<()> {
    let (output, seconds) = match which {
        BenchCommand::Extract { output, seconds } => (output, seconds),
        BenchCommand::Generate(args) => return crate::generate::bench_generate(args),
        BenchCommand::TrainVae(args) => return crate::train::bench_train_vae(args),
    };
    let budget = Duration::from_secs_f64(seconds);
    let mut report = Report {
        method: "wall-clock median over >= 5 runs and >= `seconds` per case after one warm-up run; \
                 single thread; extraction = extract_mesh (Algorithm 1, and the manifold method) on an \
                 icosphere's ground-truth edges (faces, winding, hole check, compaction) and on \
                 over-connected sphere graphs (8 nearest neighbours); threshold = spacetime_edges on \
                 N(0, 0.12^2) embeddings, tau = 0.6",
        cpu: cpu_name(),
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
            anyhow::ensure!(
                Some(faces) == w.faces,
                "{method:?} extraction lost faces of the icosphere"
            );
            let t = time(budget, || {
                std::hint::black_box(w.extract(method));
            });
            eprintln!(
                "extract ({method:?}) {:>6} vertices: {:8.3} ms",
                w.positions.len(),
                t.median_ms
            );
            let (list, reference) = match method {
                ExtractMethod::Paper => {
                    (&mut report.extraction_from_edges, &REFERENCE_EXTRACT_MS[..])
                }
                ExtractMethod::Manifold => (&mut report.manifold_extraction_from_edges, &[][..]),
            };
            list.push(case(w.positions.len(), faces, t, reference));
        }
    }
    for n in [512, 2048] {
        let w = over_connected_sphere(n, 8);
        for method in [ExtractMethod::Paper, ExtractMethod::Manifold] {
            let faces = w.extract(method).0.faces.len();
            let t = time(budget, || {
                std::hint::black_box(w.extract(method));
            });
            eprintln!(
                "extract ({method:?}) over-connected {n:>5} vertices: {:8.3} ms ({faces} faces)",
                t.median_ms
            );
            let list = match method {
                ExtractMethod::Paper => &mut report.paper_extraction_over_connected,
                ExtractMethod::Manifold => &mut report.manifold_extraction_over_connected,
            };
            list.push(case(n, faces, t, &[]));
        }
    }
    for n in [512, 1024, 2048, 4096, 8192] {
        let emb = random_embeddings(n, 32, 1);
        let count = spacetime_edges(&emb, 32, TAU)?.len();
        let t = time(budget, || {
            std::hint::black_box(spacetime_edges(&emb, 32, TAU).expect("valid"));
        });
        eprintln!("threshold N={n:>5}: {:8.3} ms ({count} edges)", t.median_ms);
        report
            .spacetime_threshold_dim32
            .push(case(n, count, t, &REFERENCE_THRESHOLD_MS));
    }
    if let Some(dir) = output.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    }
    meshflow::io::write_atomic(
        &output,
        (serde_json::to_string_pretty(&report)? + "\n").as_bytes(),
    )
    .with_context(|| format!("cannot write {}", output.display()))?;
    println!("wrote {}", output.display());
    Ok(())
}
