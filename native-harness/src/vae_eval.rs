//! `meshflow reconstruct` and `meshflow eval vae`: VAE round trips with the paper's Table 3
//! figures, CD/HD x100 (docs/design.md section 3), and the topology of the extracted meshes.

use std::fs;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use meshflow::Mesh;
use meshflow::data::dataset::Split;
use meshflow::device::{BackendKind, device};
use meshflow::eval::metrics::{CompareOptions, Comparison};
use meshflow::pipeline::reconstruct::{ReconstructionMetrics, prepare, reconstruct_batch};
use serde::Serialize;

use crate::BadInput;
use crate::extract_args::ExtractArgs;
use crate::train::load_weights;
use meshflow::data::shards::load_split;

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

/// Writes [`EMBEDDED_WEIGHTS`] once into a cache folder named by their checksum
/// (`$XDG_CACHE_HOME` or `~/.cache`, `meshflow/weights-<sha256 prefix>/`) and returns it. The
/// folder is filled under a temporary name and renamed into place, so a reader never sees half
/// of it.
fn embedded_weights_dir() -> Result<PathBuf> {
    let cache = std::env::var_os("XDG_CACHE_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))
        .unwrap_or_else(std::env::temp_dir)
        .join("meshflow");
    // The manifests name their safetensors by sha256, so hashing them (not 25 MB of weights on
    // every run) identifies the pair.
    let manifests: Vec<u8> = EMBEDDED_WEIGHTS
        .iter()
        .filter(|(name, _)| name.ends_with(".manifest.json"))
        .flat_map(|(_, bytes)| bytes.iter().copied())
        .collect();
    let dir = cache.join(format!(
        "weights-{}",
        &meshflow::pipeline::shipped::sha256_hex(&manifests)[..16]
    ));
    if dir.join("dit.safetensors").is_file() {
        return Ok(dir);
    }
    let partial = cache.join(format!("weights-partial-{}", std::process::id()));
    std::fs::create_dir_all(&partial)?;
    for (name, bytes) in EMBEDDED_WEIGHTS {
        std::fs::write(partial.join(name), bytes)?;
    }
    if std::fs::rename(&partial, &dir).is_err() {
        // Another process put it in place first.
        let _ = std::fs::remove_dir_all(&partial);
    }
    Ok(dir)
}

/// The weights folder to use: `--weights` when given, else the first that holds a
/// `vae.manifest.json` of: `$MESHFLOW_WEIGHTS`, `./weights`, `weights/` beside the executable
/// or in `../share/meshflow/` from it; else the copy compiled into the binary (the repository's
/// `weights/` at build time, written once to a cache folder), so `cargo install --path
/// native-harness` works from any folder, with or without the repository.
pub fn weights_dir(flag: Option<&Path>) -> Result<PathBuf> {
    if let Some(dir) = flag {
        return Ok(dir.to_path_buf());
    }
    let mut tried: Vec<PathBuf> = Vec::new();
    if let Some(env) = std::env::var_os("MESHFLOW_WEIGHTS") {
        tried.push(PathBuf::from(env));
    }
    tried.push(PathBuf::from("weights"));
    if let Some(exe_dir) = std::env::current_exe()
        .ok()
        .and_then(|e| e.parent().map(Path::to_path_buf))
    {
        tried.push(exe_dir.join("weights"));
        tried.push(exe_dir.join("../share/meshflow/weights"));
    }
    if let Some(found) = tried.iter().find(|d| d.join("vae.manifest.json").is_file()) {
        return Ok(found.clone());
    }
    embedded_weights_dir().map_err(|e| {
        let list: Vec<String> = tried.iter().map(|d| d.display().to_string()).collect();
        BadInput(format!(
            "no shipped weights found (tried {}) and the built-in copy could not be written \
             ({e}); pass --weights DIR or set MESHFLOW_WEIGHTS",
            list.join(", ")
        ))
        .into()
    })
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
    /// The selected meshes with at most `max_vertices` vertices ([`eval_meshes`]).
    pub fn meshes(&self, max_vertices: usize) -> Result<(NamedMeshes, Vec<String>, String)> {
        eval_meshes(
            self.input.as_deref(),
            &self.split,
            self.data.clone(),
            max_vertices,
            self.limit,
        )
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
    let (vae, manifest) = load_weights(&weights_dir(args.weights.as_deref())?, &device)?;
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
        "vertex dist x100 {:.3}, normal dist x100 {:.3}, edge P/R/F1 {:.3}/{:.3}/{:.3}",
        m.vertex_distance_x100, m.normal_distance_x100, m.edge_precision, m.edge_recall, m.edge_f1
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

/// Mean surface and topology figures over meshes' comparisons with their ground truth;
/// meshes without a comparison (no faces extracted) are counted, not averaged.
#[derive(Default, Serialize)]
pub struct SurfaceSummary {
    /// Meshes whose extraction gave no faces; the figures below are over the others.
    pub no_faces: usize,
    pub chamfer_x100: f64,
    pub hausdorff_x100: f64,
    pub faces_out: f64,
    pub faces_in: f64,
    pub non_manifold_edges: f64,
    pub boundary_edges: f64,
    pub holes: f64,
    pub inconsistent_winding_edges: f64,
    pub degenerate_faces: f64,
    pub components: f64,
    /// The ground truths' own holes and components (artist meshes are often open and in
    /// pieces), the yardstick for the two above.
    pub gt_holes: f64,
    pub gt_components: f64,
    /// Meshes whose ground truth is closed (no boundary edge), and the holes of these
    /// meshes' predictions: holes where there should be none.
    pub gt_closed: usize,
    pub holes_where_gt_closed: f64,
}

impl SurfaceSummary {
    pub fn of(comparisons: &[Option<&Comparison>]) -> Self {
        let surfaces: Vec<&Comparison> = comparisons.iter().flatten().copied().collect();
        let k = surfaces.len().max(1) as f64;
        let mean =
            |f: &dyn Fn(&Comparison) -> f64| surfaces.iter().map(|c| f(c)).sum::<f64>() / k + 0.0;
        let closed: Vec<&&Comparison> = surfaces
            .iter()
            .filter(|c| c.gt_topology.boundary_edges == 0)
            .collect();
        SurfaceSummary {
            no_faces: comparisons.len() - surfaces.len(),
            chamfer_x100: mean(&|c| c.chamfer_x100),
            hausdorff_x100: mean(&|c| c.hausdorff_x100),
            faces_out: mean(&|c| c.pred_topology.faces as f64),
            faces_in: mean(&|c| c.gt_topology.faces as f64),
            non_manifold_edges: mean(&|c| c.pred_topology.non_manifold_edges as f64),
            boundary_edges: mean(&|c| c.pred_topology.boundary_edges as f64),
            holes: mean(&|c| c.pred_topology.holes as f64),
            inconsistent_winding_edges: mean(&|c| {
                c.pred_topology.inconsistent_winding_edges as f64
            }),
            degenerate_faces: mean(&|c| c.pred_topology.degenerate_faces as f64),
            components: mean(&|c| c.pred_topology.components as f64),
            gt_holes: mean(&|c| c.gt_topology.holes as f64),
            gt_components: mean(&|c| c.gt_topology.components as f64),
            gt_closed: closed.len(),
            holes_where_gt_closed: closed
                .iter()
                .map(|c| c.pred_topology.holes as f64)
                .sum::<f64>()
                / closed.len().max(1) as f64,
        }
    }
}

/// Mean figures over a set of meshes.
#[derive(Default, Serialize)]
pub struct Summary {
    pub meshes: usize,
    pub vertex_distance_x100: f64,
    pub normal_distance_x100: f64,
    /// Mean of per-mesh precision / recall / F1.
    pub edge_precision: f64,
    pub edge_recall: f64,
    pub edge_f1: f64,
    /// F1 over all edges of all meshes pooled.
    pub edge_f1_pooled: f64,
    #[serde(flatten)]
    pub surface: SurfaceSummary,
    pub mask_errors: f64,
}

fn summarise(ms: &[&ReconstructionMetrics]) -> Summary {
    let k = ms.len().max(1) as f64;
    let mean =
        |f: &dyn Fn(&ReconstructionMetrics) -> f64| ms.iter().map(|m| f(m)).sum::<f64>() / k + 0.0;
    let (tp, fp, fn_) = ms.iter().fold((0, 0, 0), |(a, b, c), m| {
        (
            a + m.true_positive_edges,
            b + m.false_positive_edges,
            c + m.false_negative_edges,
        )
    });
    let p = tp as f64 / (tp + fp).max(1) as f64;
    let r = tp as f64 / (tp + fn_).max(1) as f64;
    let comparisons: Vec<Option<&Comparison>> = ms.iter().map(|m| m.comparison.as_ref()).collect();
    Summary {
        meshes: ms.len(),
        vertex_distance_x100: mean(&|m| m.vertex_distance_x100),
        normal_distance_x100: mean(&|m| m.normal_distance_x100),
        edge_precision: mean(&|m| m.edge_precision),
        edge_recall: mean(&|m| m.edge_recall),
        edge_f1: mean(&|m| m.edge_f1),
        edge_f1_pooled: if p + r > 0.0 {
            2.0 * p * r / (p + r)
        } else {
            0.0
        },
        surface: SurfaceSummary::of(&comparisons),
        mask_errors: mean(&|m| m.mask_errors as f64),
    }
}

#[derive(Serialize)]
struct EvalReport {
    weights: String,
    weights_sha256: String,
    source: String,
    /// N / number of latents.
    token_compression: f64,
    /// Floats in (N x encoder input channels) over floats in (latents x latent dim).
    float_compression: f64,
    skipped: Vec<String>,
    all: Summary,
    /// Buckets by vertex count: <= 256, <= 512, <= 1024.
    buckets: Vec<(String, Summary)>,
    per_mesh: Vec<(String, ReconstructionMetrics)>,
}

fn parse_split(name: &str) -> Result<Split> {
    Split::ALL
        .into_iter()
        .find(|s| s.name() == name)
        .ok_or_else(|| BadInput(format!("--split {name}: expected train, val or test")).into())
}

/// Named meshes to evaluate.
pub type NamedMeshes = Vec<(String, Mesh)>;

/// Meshes of a folder, prepared like the data build; files that fail are listed as skipped.
fn folder_meshes(dir: &Path, max_vertices: usize) -> Result<(NamedMeshes, Vec<String>)> {
    let mut files: Vec<PathBuf> = fs::read_dir(dir)
        .with_context(|| format!("cannot list {}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    let (mut meshes, mut skipped) = (Vec::new(), Vec::new());
    for f in files {
        let name = f.display().to_string();
        let read = meshflow::io::read_path(&f, &meshflow::io::Limits::default());
        match read
            .map_err(|e| e.to_string())
            .and_then(|m| prepare(&m).map_err(|e| e.to_string()))
        {
            Ok((m, _)) if m.positions.len() <= max_vertices => meshes.push((name, m)),
            Ok((m, _)) => skipped.push(format!(
                "{name}: {} vertices > {max_vertices}",
                m.positions.len()
            )),
            Err(e) => skipped.push(format!("{name}: {e}")),
        }
    }
    Ok((meshes, skipped))
}

/// The meshes an evaluation runs on: every mesh file of `input` (prepared like the data
/// build), or else the named split of a shard build; meshes with more than `max_vertices`
/// are left out and listed as skipped, and at most `limit` are kept (0 = all). Also returns
/// a description of the source. No mesh at all is an error.
pub fn eval_meshes(
    input: Option<&Path>,
    split: &str,
    data: Option<PathBuf>,
    max_vertices: usize,
    limit: usize,
) -> Result<(NamedMeshes, Vec<String>, String)> {
    let (mut meshes, skipped, source) = match input {
        Some(dir) => {
            let (m, s) = folder_meshes(dir, max_vertices)?;
            (m, s, dir.display().to_string())
        }
        None => split_meshes(split, data, max_vertices)?,
    };
    if limit > 0 {
        meshes.truncate(limit);
    }
    if meshes.is_empty() {
        bail!(BadInput("no mesh to evaluate".into()));
    }
    Ok((meshes, skipped, source))
}

/// The meshes of a split with at most `max_vertices` vertices.
fn split_meshes(
    split: &str,
    data: Option<PathBuf>,
    max_vertices: usize,
) -> Result<(NamedMeshes, Vec<String>, String)> {
    let split = parse_split(split)?;
    let data = crate::data::shards_dir(data);
    let all = load_split(&data, split)?;
    let total = all.len();
    let kept: NamedMeshes = all
        .into_iter()
        .enumerate()
        .filter(|(_, m)| m.positions.len() <= max_vertices)
        .map(|(i, m)| (format!("{}#{i}", split.name()), m))
        .collect();
    let skipped = vec![format!(
        "{} of {total} meshes have more than {max_vertices} vertices",
        total - kept.len(),
    )];
    let source = format!("{} split of {}", split.name(), data.display());
    Ok((kept, skipped, source))
}

/// Meshes per reconstruction batch in `eval vae`.
const BATCH: usize = 8;

pub fn eval_vae(args: EvalVaeArgs) -> Result<()> {
    let device = device(args.backend).map_err(|e| anyhow::anyhow!(e))?;
    let weights = weights_dir(args.weights.as_deref())?;
    let (vae, manifest) = load_weights(&weights, &device)?;
    let cfg = &manifest.model;
    let (meshes, mut skipped, source) = args.set.meshes(cfg.num_vertices)?;
    if let Some(dir) = &args.meshes {
        fs::create_dir_all(dir)?;
    }
    let opts = args.extract.options();
    let bar = indicatif::ProgressBar::new(meshes.len() as u64);
    let mut per_mesh = Vec::new();
    // Files are named by position in the split, so a skipped mesh leaves a gap, not a shift.
    let mut keep = |index: usize,
                    name: &str,
                    gt: &Mesh,
                    r: meshflow::pipeline::reconstruct::Reconstruction|
     -> Result<()> {
        if let Some(dir) = &args.meshes {
            meshflow::io::write_path(&r.mesh, &dir.join(format!("{index}.glb")))?;
            meshflow::io::write_path(gt, &dir.join(format!("{index}_gt.glb")))?;
        }
        per_mesh.push((name.to_owned(), r.metrics));
        Ok(())
    };
    for (c, chunk) in meshes.chunks(BATCH).enumerate() {
        let batch: Vec<Mesh> = chunk.iter().map(|(_, m)| m.clone()).collect();
        match reconstruct_batch(
            &vae,
            cfg,
            &batch,
            &opts,
            &CompareOptions::default(),
            &device,
        ) {
            Ok(results) => {
                for (k, ((name, gt), r)) in chunk.iter().zip(results).enumerate() {
                    keep(c * BATCH + k, name, gt, r)?;
                }
            }
            // A batch fails as a whole (e.g. an extracted mesh with no faces to sample);
            // retry its meshes one by one so only the bad one is skipped.
            Err(_) => {
                for (k, (name, m)) in chunk.iter().enumerate() {
                    match reconstruct_batch(
                        &vae,
                        cfg,
                        std::slice::from_ref(m),
                        &opts,
                        &CompareOptions::default(),
                        &device,
                    ) {
                        Ok(mut r) => keep(c * BATCH + k, name, m, r.remove(0))?,
                        Err(e) => skipped.push(format!("{name}: {e}")),
                    }
                }
            }
        }
        bar.inc(chunk.len() as u64);
    }
    bar.finish_and_clear();
    let all: Vec<&ReconstructionMetrics> = per_mesh.iter().map(|(_, m)| m).collect();
    let buckets = [256usize, 512, 1024]
        .iter()
        .map(|&limit| {
            let ms: Vec<&ReconstructionMetrics> = all
                .iter()
                .copied()
                .filter(|m| m.vertices <= limit)
                .collect();
            (format!("<= {limit}"), summarise(&ms))
        })
        .collect();
    let report = EvalReport {
        weights: weights.display().to_string(),
        weights_sha256: manifest.sha256.clone(),
        source,
        token_compression: cfg.merge_ratio() as f64,
        float_compression: (cfg.num_vertices * cfg.in_channels()) as f64
            / (cfg.num_latents * cfg.latent_dim) as f64,
        skipped,
        all: summarise(&all),
        buckets,
        per_mesh,
    };
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
