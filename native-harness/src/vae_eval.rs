//! `meshflow reconstruct` and `meshflow eval vae`: VAE round trips with the paper's Table 3
//! figures, CD/HD x100 (docs/design.md section 3), and the topology of the extracted meshes.

use std::fs;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use meshflow::burn::tensor::Device;
use meshflow::device::{BackendKind, device};
use meshflow::eval::metrics::CompareOptions;
use meshflow::eval::reconstruction::evaluate_vae;
use meshflow::eval::sets::{EvalSet, EvalSetError, eval_set};
use meshflow::model::MeshVae;
use meshflow::pipeline::reconstruct::{ReconstructionMetrics, prepare, reconstruct_batch};
use meshflow::pipeline::shipped::{ShippedError, VaeManifest, load_vae_dir, locate_weights};

use crate::BadInput;
use crate::extract_args::ExtractArgs;

/// The shipped weights, compiled into the binary: the last resort of [`weights_dir`], so an
/// installed `meshflow` works with no repository and no weights folder beside it.
const EMBEDDED_WEIGHTS: [(&str, &[u8]); 4] = [
    (
        "vae.manifest.json",
        include_bytes!("../../weights/vae.manifest.json"),
    ),
    (
        "vae.safetensors",
        include_bytes!("../../weights/vae.safetensors"),
    ),
    (
        "dit.manifest.json",
        include_bytes!("../../weights/dit.manifest.json"),
    ),
    (
        "dit.safetensors",
        include_bytes!("../../weights/dit.safetensors"),
    ),
];

/// The weights folder to use: `--weights` when given, else the shipped weights found from any
/// folder, else the copy compiled into the binary
/// ([`meshflow::pipeline::shipped::locate_weights`]).
pub fn weights_dir(flag: Option<&Path>) -> Result<PathBuf> {
    locate_weights(flag, &EMBEDDED_WEIGHTS).map_err(|e| BadInput(e.to_string()).into())
}

/// A shipped-weights error as the CLI reports it: a file that cannot be read is an I/O
/// failure, weights that do not check out are bad input (exit status 2).
pub fn shipped_error(dir: &Path, e: ShippedError) -> anyhow::Error {
    match e {
        ShippedError::Read { .. } => anyhow::anyhow!(e),
        e => BadInput(format!("{}: {e}", dir.display())).into(),
    }
}

/// Loads the VAE of a weights folder (sha256, configuration and shapes checked).
pub fn load_vae(dir: &Path, device: &Device) -> Result<(MeshVae, VaeManifest)> {
    load_vae_dir(dir, device).map_err(|e| shipped_error(dir, e))
}

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
    #[arg(long, default_value = "cpu", value_parser = crate::train::backend_parser())]
    backend: BackendKind,
    #[command(flatten)]
    extract: ExtractArgs,
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
        BadInput(e.to_string()).into()
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
    #[arg(long, default_value = "cpu", value_parser = crate::train::backend_parser())]
    backend: BackendKind,
    #[command(flatten)]
    extract: ExtractArgs,
}

pub fn reconstruct(args: ReconstructArgs) -> Result<()> {
    let device = device(args.backend).map_err(|e| anyhow::anyhow!(e))?;
    let (vae, manifest) = load_vae(&weights_dir(args.weights.as_deref())?, &device)?;
    let input = meshflow::io::read_path(&args.mesh, &meshflow::io::Limits::default())
        .with_context(|| format!("cannot read {}", args.mesh.display()))
        .map_err(|e| BadInput(format!("{e:#}")))?;
    let (model_frame, back) =
        prepare(&input).map_err(|e| BadInput(format!("{}: {e}", args.mesh.display())))?;
    let n = manifest.model.num_vertices;
    if model_frame.positions.len() > n {
        bail!(BadInput(format!(
            "{}: {} vertices after welding; this VAE takes at most {n}",
            args.mesh.display(),
            model_frame.positions.len()
        )));
    }
    let mut out = reconstruct_batch(
        &vae,
        &manifest.model,
        &[model_frame],
        &args.extract.options(),
        &CompareOptions::default(),
        &device,
    )
    .map_err(|e| BadInput(format!("{}: {e}", args.mesh.display())))?;
    let r = out.remove(0);
    let mesh = back.apply_mesh(&r.mesh);
    meshflow::io::write_path(&mesh, &args.output)
        .with_context(|| format!("cannot write {}", args.output.display()))?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&r.metrics)?);
    } else {
        print_metrics(&r.metrics);
        println!("-> {}", args.output.display());
    }
    Ok(())
}

fn print_metrics(m: &ReconstructionMetrics) {
    println!(
        "vertex dist x100 {:.3}, normal dist x100 {:.3}, edge P/R/F1 {:.3}/{:.3}/{:.3}, the \
         extracted mesh's edges {:.3}/{:.3}/{:.3}",
        m.vertex_distance_x100,
        m.normal_distance_x100,
        m.edge_precision,
        m.edge_recall,
        m.edge_f1,
        m.mesh_edge_precision,
        m.mesh_edge_recall,
        m.mesh_edge_f1
    );
    let Some(c) = &m.comparison else {
        println!(
            "{} vertices / {} faces in; the extracted mesh has no faces",
            m.vertices, m.faces
        );
        return;
    };
    let t = &c.pred_topology;
    println!(
        "{} vertices / {} faces in; {} vertices / {} faces out",
        m.vertices, m.faces, t.vertices, t.faces
    );
    println!(
        "CD x100 {:.3}, HD x100 {:.3}; boundary edges {}, non-manifold edges {}, holes {}, \
         components {}",
        c.chamfer_x100,
        c.hausdorff_x100,
        t.boundary_edges,
        t.non_manifold_edges,
        t.holes,
        t.components
    );
}

pub fn eval_vae(args: EvalVaeArgs) -> Result<()> {
    let device = device(args.backend).map_err(|e| anyhow::anyhow!(e))?;
    let weights = weights_dir(args.weights.as_deref())?;
    let (vae, manifest) = load_vae(&weights, &device)?;
    let set = args.set.meshes(manifest.model.num_vertices)?;
    if let Some(dir) = &args.meshes {
        fs::create_dir_all(dir)?;
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
    let s = &report.all;
    // The skipped meshes come first, so a reader sees what the figures leave out.
    for reason in &report.skipped {
        println!("skipped: {reason}");
    }
    println!(
        "{} meshes: vertex x100 {:.3}, normal x100 {:.3}, edge P/R/F1 {:.3}/{:.3}/{:.3} (pooled F1 \
         {:.3}), CD x100 {:.3}, HD x100 {:.3}",
        s.meshes,
        s.vertex_distance_x100,
        s.normal_distance_x100,
        s.edge_precision,
        s.edge_recall,
        s.edge_f1,
        s.edge_f1_pooled,
        s.surface.chamfer_x100,
        s.surface.hausdorff_x100
    );
    let percent = |a: usize, b: usize| 100.0 * a as f64 / b.max(1) as f64;
    let w = &s.wrong_edges;
    let share = |k: usize| percent(k, w.total());
    println!(
        "  wrong edges: {:.0}% quad diagonals, {:.0}% two hops, {:.0}% near in space, {:.0}% far \
         (of {})",
        share(w.quad_diagonal),
        share(w.two_hops),
        share(w.near_in_space),
        share(w.far),
        w.total()
    );
    let q = &s.quad_diagonals;
    println!(
        "  quads' diagonals: the artist's scores higher in {:.0}% of {}; both pass tau in {}, \
         the artist's higher in {:.0}% of those",
        percent(q.taken_scores_higher, q.quads),
        q.quads,
        q.both_above_threshold,
        percent(q.both_above_taken_higher, q.both_above_threshold)
    );
    println!(
        "  the extracted meshes' edges: P/R/F1 {:.3}/{:.3}/{:.3}",
        s.mesh_edge_precision, s.mesh_edge_recall, s.mesh_edge_f1
    );
    for (name, b) in &report.buckets {
        println!(
            "  {name:>6} vertices: {:4} meshes, F1 {:.3}, CD x100 {:.3}, HD x100 {:.3}",
            b.meshes, b.edge_f1, b.surface.chamfer_x100, b.surface.hausdorff_x100
        );
    }
    println!(
        "  extracted topology (mean per mesh): {:.1} faces (gt {:.1}), {:.2} non-manifold edges, \
         {:.2} holes, {:.2} components; {} with no faces",
        s.surface.faces_out,
        s.surface.faces_in,
        s.surface.non_manifold_edges,
        s.surface.holes,
        s.surface.components,
        s.surface.no_faces
    );
    if let Some(out) = &args.output {
        meshflow::io::write_atomic(out, serde_json::to_string_pretty(&report)?.as_bytes())?;
        println!("-> {}", out.display());
    }
    Ok(())
}
