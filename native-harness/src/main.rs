//! `meshflow`: the command-line door to the MeshFlow crate.
//!
//! Every command reads any supported mesh or point-cloud format and reports errors as one
//! readable line with a non-zero exit status (2 for bad input, 1 for anything else).

mod args;
mod bench;
mod commands;
mod data;
mod files;
mod generate;
mod progress;
mod train;
mod vae_eval;
mod verify;
mod weights;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "meshflow",
    version,
    about = "Artist-like meshes from point clouds (MeshFlow)"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Counts and the topology report of a mesh or point cloud.
    Inspect(commands::InspectArgs),
    /// Samples points uniformly by area from a mesh's surface and writes them as a point cloud.
    Sample(commands::SampleArgs),
    /// Converts between formats (read: OBJ PLY STL glTF GLB XYZ/PTS/CSV; write: GLB OBJ PLY).
    Convert(commands::ConvertArgs),
    /// Chamfer and Hausdorff distance (x100, docs/design.md section 3) and topology of PRED against GT.
    Compare(commands::CompareArgs),
    /// Round-trips a mesh through its ground-truth adjacency (tokens -> edges -> faces with
    /// Algorithm 1) and reports what was lost.
    Extract(commands::ExtractArgs),
    /// Training data: fetch the allowed sources, build shards (docs/data.md).
    #[command(subcommand)]
    Data(data::DataCommand),
    /// Generates an artist-like mesh from a point cloud (or a mesh, surface-sampled first) with
    /// the shipped DiT and VAE; prints per-stage times and the topology report.
    Generate(generate::GenerateArgs),
    /// Encodes, decodes and extracts a mesh with the VAE; prints the reconstruction figures.
    Reconstruct(vae_eval::ReconstructArgs),
    /// Evaluation with the paper's metrics; JSON out.
    #[command(subcommand)]
    Eval(EvalCommand),
    /// Checks this build's numerics against the reference's golden vectors (vae_small,
    /// dit_small) on a backend.
    Verify(verify::VerifyArgs),
    /// Trains the networks on a shard build (`meshflow data build`).
    #[command(subcommand)]
    Train(train::TrainCommand),
    /// Benchmarks that write JSON.
    #[command(subcommand)]
    Bench(bench::BenchCommand),
}

#[derive(Subcommand)]
enum EvalCommand {
    /// VAE reconstruction of a split (or a folder of meshes): Table 3 metrics, CD/HD x100,
    /// topology, per size bucket.
    Vae(vae_eval::EvalVaeArgs),
    /// Generation from surface samples of a split (or a folder of meshes): CD/HD x100 and
    /// topology beside the VAE's reconstruction and an optional Poisson + QEM baseline.
    // Boxed: its many pipeline options make it several times the size of the others.
    Generate(Box<generate::EvalGenerateArgs>),
    /// Fits the default vertex-budget rule on a split and reports how well it predicts the
    /// meshes' vertex counts.
    Budget(generate::EvalBudgetArgs),
}

/// Input the command cannot work with, beyond what the library's typed errors cover
/// (e.g. a point cloud where a mesh is needed). Exits with status 2 like them.
#[derive(Debug)]
pub struct BadInput(pub String);

impl std::fmt::Display for BadInput {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for BadInput {}

/// `e` as [`BadInput`]: its message alone, exit status 2.
pub fn bad_input(e: impl std::fmt::Display) -> anyhow::Error {
    BadInput(e.to_string()).into()
}

/// A reader that goes away (`meshflow compare A B | head`) ends the process as it ends any
/// Unix tool, by SIGPIPE (status 141 in a shell), quietly: Rust ignores the signal, so the
/// next print would panic with "failed printing to stdout".
fn end_quietly_on_closed_pipe() {
    #[cfg(unix)]
    // SAFETY: restoring a signal's default disposition before any thread starts.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

fn main() -> ExitCode {
    end_quietly_on_closed_pipe();
    // Whether glibc took it changes only the speed.
    meshflow::device::keep_freed_memory();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Inspect(args) => commands::inspect(args),
        Command::Sample(args) => commands::sample(args),
        Command::Convert(args) => commands::convert(args),
        Command::Compare(args) => commands::compare(args),
        Command::Extract(args) => commands::extract(args),
        Command::Data(which) => data::run(which),
        Command::Generate(args) => generate::generate(args),
        Command::Reconstruct(args) => vae_eval::reconstruct(args),
        Command::Eval(EvalCommand::Vae(args)) => vae_eval::eval_vae(args),
        Command::Eval(EvalCommand::Generate(args)) => generate::eval_generate(*args),
        Command::Eval(EvalCommand::Budget(args)) => generate::eval_budget(args),
        Command::Verify(args) => verify::run(args),
        Command::Train(which) => train::run(which),
        Command::Bench(which) => bench::run(which),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {err:#}");
            let is_bad_input = err.chain().any(|e| {
                e.is::<BadInput>()
                    || e.is::<meshflow::io::ReadError>()
                    || e.is::<meshflow::geometry::sample::SampleError>()
                    || e.is::<meshflow::eval::metrics::MetricsError>()
                    || e.downcast_ref::<meshflow::io::WriteError>()
                        .is_some_and(|w| {
                            matches!(w, meshflow::io::WriteError::UnsupportedFormat { .. })
                        })
            });
            ExitCode::from(if is_bad_input { 2 } else { 1 })
        }
    }
}
