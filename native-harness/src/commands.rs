//! The geometry commands: inspect, sample, convert, compare, extract.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;
use meshflow::Mesh;
use meshflow::eval::metrics::{CompareOptions, compare_meshes};
use meshflow::extract::round_trip::{RoundTripError, round_trip};
use meshflow::geometry::clean::{CleanOptions, clean};
use meshflow::geometry::inspect::Inspection;
use meshflow::geometry::sample::sample_surface;
use serde::Serialize;

use crate::BadInput;
use crate::args::ExtractionArgs;
use crate::files::{print_json, read_mesh, write_mesh};
use crate::progress::step;

#[derive(Args)]
pub struct InspectArgs {
    file: PathBuf,
    /// Print JSON instead of text.
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
pub struct SampleArgs {
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
}

#[derive(Args)]
pub struct ConvertArgs {
    input: PathBuf,
    output: PathBuf,
    /// Weld vertices and drop degenerate, duplicate and back-to-back faces first.
    #[arg(long)]
    clean: bool,
}

#[derive(Args)]
pub struct CompareArgs {
    pred: PathBuf,
    gt: PathBuf,
    /// Points sampled on each surface.
    #[arg(long, default_value_t = 5000)]
    samples: usize,
    #[arg(long, default_value_t = 0)]
    seed: u64,
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
pub struct ExtractArgs {
    mesh: PathBuf,
    /// Write the extracted mesh here.
    #[arg(short, long)]
    output: Option<PathBuf>,
    #[command(flatten)]
    extract: ExtractionArgs,
    #[arg(long)]
    json: bool,
}

/// A report as printed: the file it is about, then the report's own fields.
#[derive(Serialize)]
struct OfFile<'a, T> {
    file: String,
    #[serde(flatten)]
    report: &'a T,
}

/// `meshflow inspect`: the summary of a mesh or point cloud, as text or JSON.
pub fn inspect(args: InspectArgs) -> Result<()> {
    let mesh = read_mesh(&args.file)?;
    let report = Inspection::of(&mesh);
    let file = args.file.display().to_string();
    if args.json {
        return print_json(&OfFile {
            file,
            report: &report,
        });
    }
    println!("{file}\n{report}");
    Ok(())
}

/// `meshflow sample`.
pub fn sample(args: SampleArgs) -> Result<()> {
    if args.count == 0 {
        bail!(BadInput(
            "the number of points (-n) must be at least 1".into()
        ));
    }
    let mesh = read_mesh(&args.mesh)?;
    let samples = step("sampling", || sample_surface(&mesh, args.count, args.seed))
        .with_context(|| format!("cannot sample {}", args.mesh.display()))?;
    let mut cloud = Mesh::from_points(samples.points);
    if args.normals {
        cloud.normals = samples.normals;
    }
    write_mesh(&cloud, &args.output)?;
    println!(
        "wrote {} points to {}",
        cloud.positions.len(),
        args.output.display()
    );
    Ok(())
}

/// `meshflow convert`.
pub fn convert(args: ConvertArgs) -> Result<()> {
    let mut mesh = read_mesh(&args.input)?;
    if args.clean {
        let (cleaned, report) = clean(&mesh, &CleanOptions::default());
        println!("cleaned: {}", serde_json::to_string(&report)?);
        mesh = cleaned;
    }
    write_mesh(&mesh, &args.output)?;
    println!(
        "wrote {} ({} vertices, {} faces)",
        args.output.display(),
        mesh.positions.len(),
        mesh.faces.len()
    );
    Ok(())
}

/// `meshflow compare`.
pub fn compare(args: CompareArgs) -> Result<()> {
    let (p, g) = (read_mesh(&args.pred)?, read_mesh(&args.gt)?);
    let options = CompareOptions {
        samples: args.samples,
        seed: args.seed,
        ..Default::default()
    };
    let cmp = step("comparing", || compare_meshes(&p, &g, &options)).context("cannot compare")?;
    if args.json {
        return print_json(&cmp);
    }
    println!("{} vs {}\n{cmp}", args.pred.display(), args.gt.display());
    Ok(())
}

/// `meshflow extract`: the round trip of a mesh through its own edges, as text or JSON;
/// optionally writes the extracted mesh.
pub fn extract(args: ExtractArgs) -> Result<()> {
    let mesh = read_mesh(&args.mesh)?;
    let file = args.mesh.display().to_string();
    let (result, report) = match round_trip(&mesh, &args.extract.options()) {
        Ok(done) => done,
        // Input the command cannot work with exits with status 2; the messages name the file.
        Err(RoundTripError::PointCloud) => {
            let msg = format!("{file} is a point cloud: extract needs a mesh with faces");
            bail!(BadInput(msg));
        }
        Err(RoundTripError::Empty) => {
            bail!(BadInput(format!("{file} is empty after cleaning")));
        }
        Err(RoundTripError::Extract(e)) => return Err(e.into()),
    };
    if let Some(path) = &args.output {
        write_mesh(&result, path)?;
    }
    if args.json {
        return print_json(&OfFile {
            file,
            report: &report,
        });
    }
    println!("{file}\n{report}");
    if let Some(path) = &args.output {
        println!("wrote {}", path.display());
    }
    Ok(())
}
