//! `meshflow bench extract`: extraction and threshold timings as JSON, beside the reference
//! implementation's figures (docs/design.md section 4). One thread; median of repeated runs.
//! The timing is [`meshflow::eval::timing`]; this prints progress and writes the JSON.

use std::path::PathBuf;
use std::time::Duration;

use anyhow::Result;
use clap::Subcommand;
use meshflow::eval::timing::{Series, bench_extract};

use crate::files::write_json;

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
    /// Stage 4 with a pair head: one generation's candidates decoded once, each extracted
    /// (one thread) from the edge embeddings, their distance matrix and the pair head's
    /// distances, with the edges and candidate faces each offers.
    PairHead(crate::generate::BenchPairHeadArgs),
}

/// Runs a benchmark; `extract` prints progress to stderr and writes its JSON atomically.
pub fn run(which: BenchCommand) -> Result<()> {
    let (output, seconds) = match which {
        BenchCommand::Extract { output, seconds } => (output, seconds),
        BenchCommand::Generate(args) => return crate::generate::bench_generate(args),
        BenchCommand::TrainVae(args) => return crate::train::bench_train_vae(args),
        BenchCommand::PairHead(args) => return crate::generate::bench_pair_head(args),
    };
    let report = bench_extract(
        Duration::from_secs_f64(seconds),
        meshflow::device::cpu_name(),
        &mut |series, case| {
            let (n, count, ms) = (case.size, case.output_count, case.timing.median_ms);
            match series {
                Series::FromEdges(method) => {
                    eprintln!("extract ({method:?}) {n:>6} vertices: {ms:8.3} ms")
                }
                Series::OverConnected(method) => eprintln!(
                    "extract ({method:?}) over-connected {n:>5} vertices: {ms:8.3} ms ({count} faces)"
                ),
                Series::Threshold => eprintln!("threshold N={n:>5}: {ms:8.3} ms ({count} edges)"),
            }
        },
    )?;
    write_json(&output, &report)?;
    println!("wrote {}", output.display());
    Ok(())
}
