//! `meshflow reconstruct` and `meshflow eval vae`: VAE round trips with the paper's Table 3
//! figures, CD/HD x100 (docs/design.md section 3), and the topology of the extracted meshes.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use meshflow::eval::reconstruction::evaluate_vae;
use meshflow::eval::sets::{EvalSet, EvalSetError, eval_set};
use meshflow::pipeline::reconstruct::reconstruct_mesh;

use crate::args::{BackendArg, ExtractionArgs};
use crate::bad_input;
use crate::files::{create_dir, print_json, read_mesh, write_json, write_mesh};
use crate::weights::{load_vae, weights_dir};

#[derive(Args)]
pub struct ReconstructArgs {
    mesh: PathBuf,
    /// Output mesh (.glb, .obj or .ply), in the input's frame.
    #[arg(short, long)]
    output: PathBuf,
    /// Folder with vae.safetensors, vae.json and vae.manifest.json [default: the shipped
    /// weights, found from any folder: see README.md].
    #[arg(long)]
    weights: Option<PathBuf>,
    #[command(flatten)]
    backend: BackendArg,
    #[command(flatten)]
    extract: ExtractionArgs,
    #[arg(long)]
    json: bool,
}

/// Which meshes an evaluation runs on (shared by `eval vae` and `eval generate`).
#[derive(Args)]
pub struct EvalSetArgs {
    /// Split of the shard build to evaluate (train, val or test).
    #[arg(long, default_value = "test")]
    split: String,
    /// The build's output folder [default: ~/.cache/meshflow/data/shards].
    #[arg(long)]
    data: Option<PathBuf>,
    /// Evaluate every mesh file in this folder instead (cleaned, normalised and filtered like
    /// the data build).
    #[arg(long)]
    input: Option<PathBuf>,
    /// At most this many meshes (0 = all).
    #[arg(long, default_value_t = 0)]
    limit: usize,
}

impl EvalSetArgs {
    /// The selected meshes with at most `max_vertices` vertices ([`eval_set`]).
    pub fn meshes(&self, max_vertices: usize) -> Result<EvalSet> {
        let shards = crate::data::shards_dir(self.data.clone());
        eval_set(
            self.input.as_deref(),
            &self.split,
            &shards,
            max_vertices,
            self.limit,
        )
        .map_err(eval_set_error)
    }
}

/// An evaluation-set error as the CLI reports it (exit status 2 for a bad selection).
pub fn eval_set_error(e: EvalSetError) -> anyhow::Error {
    if e.is_bad_input() {
        bad_input(e)
    } else {
        anyhow::anyhow!(e)
    }
}

#[derive(Args)]
pub struct EvalVaeArgs {
    /// The weights folder [default: the shipped weights, found from any folder].
    #[arg(long)]
    weights: Option<PathBuf>,
    #[command(flatten)]
    set: EvalSetArgs,
    /// Write the JSON report here.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Write the reconstructed meshes (`I.glb`) and their ground truth (`I_gt.glb`, model
    /// frame) into this folder.
    #[arg(long)]
    meshes: Option<PathBuf>,
    #[command(flatten)]
    backend: BackendArg,
    #[command(flatten)]
    extract: ExtractionArgs,
}

/// `meshflow reconstruct`: one mesh file through the VAE, written in its own frame.
pub fn reconstruct(args: ReconstructArgs) -> Result<()> {
    let device = args.backend.device()?;
    let (vae, manifest) = load_vae(&weights_dir(args.weights.as_deref())?, &device)?;
    let input = read_mesh(&args.mesh)?;
    let extract = args.extract.options();
    let r = reconstruct_mesh(&vae, &manifest.model, &input, &extract, &device)
        .map_err(|e| bad_input(format!("{}: {e}", args.mesh.display())))?;
    write_mesh(&r.mesh, &args.output)?;
    if args.json {
        print_json(&r.metrics)?;
    } else {
        println!("{}\n-> {}", r.metrics, args.output.display());
    }
    Ok(())
}

/// `meshflow eval vae`.
pub fn eval_vae(args: EvalVaeArgs) -> Result<()> {
    let device = args.backend.device()?;
    let weights = weights_dir(args.weights.as_deref())?;
    let (vae, manifest) = load_vae(&weights, &device)?;
    let set = args.set.meshes(manifest.model.num_vertices)?;
    if let Some(dir) = &args.meshes {
        create_dir(dir)?;
    }
    let bar = indicatif::ProgressBar::new(set.meshes.len() as u64);
    let report = evaluate_vae(
        &vae,
        &manifest,
        &weights.display().to_string(),
        set,
        &args.extract.options(),
        args.meshes.as_deref(),
        &device,
        &mut |done| bar.set_position(done as u64),
    )?;
    bar.finish_and_clear();
    println!("{report}");
    if let Some(out) = &args.output {
        write_json(out, &report)?;
        println!("-> {}", out.display());
    }
    Ok(())
}
