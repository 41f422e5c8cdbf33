//! `meshflow generate`, `meshflow eval generate` and `meshflow eval budget`: point clouds to
//! meshes with the shipped VAE and DiT, and their evaluation against the VAE's reconstruction
//! (the upper bound) and a Poisson + QEM baseline made by `bench/poisson_qem.py`.

use std::fs;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};
use meshflow::Mesh;
use meshflow::budget::{BudgetRule, DEFAULT_RULE, ShapeFeatures, shape_features};
use meshflow::burn::tensor::Device;
use meshflow::device::{BackendKind, device};
use meshflow::generate::{
    CONDITION_POINTS, GenerateOptions, Generated, Generator, StageTimes, input_points,
};
use meshflow::metrics::{CompareOptions, Comparison, compare_meshes};
use meshflow::model::MeshVae;
use meshflow::model::dit::Dit;
use meshflow::model::schedule::ScheduleMode;
use meshflow::reconstruct::reconstruct_batch;
use meshflow::sample::sample_surface;
use serde::Serialize;

use crate::BadInput;
use crate::extract_args::ExtractArgs;
use crate::train::{Backend, load_weights, read_shipped};
use crate::vae_eval::{DEFAULT_WEIGHTS, EvalSetArgs, SurfaceSummary, eval_meshes};
use meshflow::shipped::{DitManifest, VaeManifest};

/// The sampler's end point, as a command-line value.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum Schedule {
    /// Steps down to t = 0 (the default).
    ToZero,
    /// As the reference implementation: stops at t ~ 0.0089.
    Reference,
}

impl From<Schedule> for ScheduleMode {
    fn from(s: Schedule) -> Self {
        match s {
            Schedule::ToZero => ScheduleMode::ToZero,
            Schedule::Reference => ScheduleMode::Reference,
        }
    }
}

/// Options shared by `generate` and `eval generate`.
#[derive(Args, Clone)]
pub struct SamplingArgs {
    /// Folder with the VAE (vae.*) and DiT (dit.*) weights and manifests.
    #[arg(long, default_value = DEFAULT_WEIGHTS)]
    weights: PathBuf,
    /// Euler steps.
    #[arg(long, default_value_t = 28)]
    steps: usize,
    #[arg(long, default_value_t = 0)]
    seed: u64,
    #[arg(long, value_enum, default_value = "to-zero")]
    schedule: Schedule,
    #[command(flatten)]
    extract: ExtractArgs,
    #[arg(long, value_enum, default_value = "cpu")]
    backend: Backend,
}

impl SamplingArgs {
    fn options(&self, vertices: Option<usize>) -> GenerateOptions {
        GenerateOptions {
            vertices,
            steps: self.steps,
            seed: self.seed,
            schedule: self.schedule.into(),
            extract: self.extract.options(),
        }
    }
}

#[derive(Args)]
pub struct GenerateArgs {
    /// A point cloud or mesh file (a mesh is surface-sampled first), or a folder of them.
    input: PathBuf,
    /// Output mesh (.glb, .obj or .ply), or a folder (GLB per input) when INPUT is a folder.
    #[arg(short, long)]
    output: PathBuf,
    /// Vertices to generate [default: a rule on the input's occupancy and curvature, see
    /// BENCHMARKS.md].
    #[arg(long)]
    vertices: Option<usize>,
    #[command(flatten)]
    sampling: SamplingArgs,
    /// Print JSON (timings, budget, topology) instead of text.
    #[arg(long)]
    json: bool,
}

/// The shipped DiT and VAE, loaded.
pub struct Models {
    pub vae: MeshVae,
    pub vae_manifest: VaeManifest,
    pub dit: Dit,
    pub dit_manifest: DitManifest,
}

impl Models {
    pub fn generator<'a>(&'a self, device: &'a Device) -> Generator<'a> {
        Generator::from_shipped(
            &self.vae,
            &self.vae_manifest,
            &self.dit,
            &self.dit_manifest,
            device,
        )
    }
}

/// Loads `dir`'s VAE and DiT, checking each file against its manifest's sha256 and the DiT
/// against the VAE it was trained on.
pub fn load_models(dir: &Path, device: &Device) -> Result<Models> {
    let (vae, vae_manifest) = load_weights(dir, device)?;
    let (manifest, weights) = read_shipped(dir, "dit")?;
    let (dit, dit_manifest) =
        meshflow::shipped::load_dit(&manifest, &weights, &vae_manifest, device)
            .map_err(|e| BadInput(format!("{}: {e}", dir.display())))?;
    Ok(Models {
        vae,
        vae_manifest,
        dit,
        dit_manifest,
    })
}

/// What `generate --json` prints per input.
#[derive(Serialize)]
struct GenerateReport<'a> {
    input: String,
    output: String,
    vertex_budget: usize,
    features: ShapeFeatures,
    load_s: f64,
    times: &'a StageTimes,
    extract: &'a meshflow::extract::ExtractReport,
    topology: &'a meshflow::topology::TopologyReport,
}

fn read_input(path: &Path) -> Result<Mesh> {
    meshflow::io::read_path(path, &meshflow::io::Limits::default())
        .map_err(|e| BadInput(format!("{}: {e}", path.display())).into())
}

pub fn generate(args: GenerateArgs) -> Result<()> {
    let started = Instant::now();
    let device =
        device(BackendKind::from(args.sampling.backend)).map_err(|e| anyhow::anyhow!(e))?;
    let models = load_models(&args.sampling.weights, &device)?;
    let load_model_s = started.elapsed().as_secs_f64();
    let jobs: Vec<(PathBuf, PathBuf)> = if args.input.is_dir() {
        fs::create_dir_all(&args.output)
            .with_context(|| format!("cannot create {}", args.output.display()))?;
        let mut files: Vec<PathBuf> = fs::read_dir(&args.input)?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.is_file() && meshflow::io::Format::from_path(p).is_some())
            .collect();
        files.sort();
        if files.is_empty() {
            bail!(BadInput(format!(
                "{}: no mesh or point-cloud file in the folder",
                args.input.display()
            )));
        }
        files
            .into_iter()
            .map(|f| {
                let stem = f
                    .file_stem()
                    .unwrap_or_default()
                    .to_string_lossy()
                    .to_string();
                let out = args.output.join(format!("{stem}.glb"));
                (f, out)
            })
            .collect()
    } else {
        vec![(args.input.clone(), args.output.clone())]
    };
    let generator = models.generator(&device);
    let opts = args.sampling.options(args.vertices);
    let batch = jobs.len() > 1;
    let mut failures = 0;
    for (input, output) in &jobs {
        let started = Instant::now();
        let result = read_input(input).and_then(|mesh| {
            let points = input_points(&mesh, opts.seed).map_err(|e| BadInput(e.to_string()))?;
            let load_s = load_model_s + started.elapsed().as_secs_f64();
            let bar = crate::progress::step_bar(opts.steps, args.json);
            let mut out = generator
                .generate(&[points], &opts, &mut |i, _| {
                    bar.set_position(i as u64);
                    true
                })
                .map_err(|e| BadInput(format!("{}: {e}", input.display())))?;
            bar.finish_and_clear();
            let g = out.remove(0);
            meshflow::io::write_path(&g.mesh, output)
                .with_context(|| format!("cannot write {}", output.display()))?;
            Ok((g, load_s))
        });
        match result {
            Ok((g, load_s)) => report(&g, input, output, load_s, args.json)?,
            // In batch mode one bad file is reported and the rest still run.
            Err(e) if batch => {
                eprintln!("error: {e:#}");
                failures += 1;
            }
            Err(e) => return Err(e),
        }
    }
    if failures > 0 {
        bail!(BadInput(format!(
            "{failures} of {} inputs failed",
            jobs.len()
        )));
    }
    Ok(())
}

fn report(g: &Generated, input: &Path, output: &Path, load_s: f64, json: bool) -> Result<()> {
    if json {
        let r = GenerateReport {
            input: input.display().to_string(),
            output: output.display().to_string(),
            vertex_budget: g.vertex_budget,
            features: g.features,
            load_s,
            times: &g.times,
            extract: &g.extract,
            topology: &g.topology,
        };
        println!("{}", serde_json::to_string(&r)?);
        return Ok(());
    }
    let t = &g.times;
    let topo = &g.topology;
    println!("{} -> {}", input.display(), output.display());
    println!(
        "  vertex budget {} (occupancy {}, surface variation {:.4})",
        g.vertex_budget, g.features.occupied_voxels, g.features.surface_variation
    );
    println!(
        "  times: load {:.3} s, condition {:.3} s, sample {:.3} s, decode {:.3} s, extract {:.3} s",
        load_s, t.condition_s, t.sample_s, t.decode_s, t.extract_s
    );
    println!(
        "  {} vertices, {} faces, {} components; {} boundary edges, {} holes, {} non-manifold \
         edges, {} inconsistent winding, {} degenerate faces",
        topo.vertices,
        topo.faces,
        topo.components,
        topo.boundary_edges,
        topo.holes,
        topo.non_manifold_edges,
        topo.inconsistent_winding_edges,
        topo.degenerate_faces
    );
    Ok(())
}

/// Where the vertex budget of `eval generate` comes from.
#[derive(Clone, Copy, Debug, ValueEnum, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum BudgetSource {
    /// The default rule on the conditioning points, as a user gets it.
    Rule,
    /// The ground truth's vertex count (an oracle, for comparison).
    GroundTruth,
}

#[derive(Args)]
pub struct EvalGenerateArgs {
    #[command(flatten)]
    set: EvalSetArgs,
    #[arg(long, value_enum, default_value = "rule")]
    budget: BudgetSource,
    /// Meshes per sampling batch.
    #[arg(long, default_value_t = 8)]
    batch: usize,
    #[command(flatten)]
    sampling: SamplingArgs,
    /// Write, per mesh K: K.points.ply (the conditioning points), K.ours.glb, K.vae.glb,
    /// K.gt.glb, and targets.json (our face counts, for bench/poisson_qem.py).
    #[arg(long)]
    meshes: Option<PathBuf>,
    /// A folder with K.poisson.ply from bench/poisson_qem.py: scored as the baseline.
    #[arg(long)]
    baseline: Option<PathBuf>,
    /// Write the JSON report here.
    #[arg(short, long)]
    output: Option<PathBuf>,
}

#[derive(Serialize)]
struct MeshResult {
    name: String,
    gt_vertices: usize,
    vertex_budget: usize,
    ours: Option<Comparison>,
    vae: Option<Comparison>,
    baseline: Option<Comparison>,
}

#[derive(Serialize)]
struct MethodSummaries {
    meshes: usize,
    ours: SurfaceSummary,
    vae_upper_bound: SurfaceSummary,
    baseline: Option<SurfaceSummary>,
}

#[derive(Serialize)]
struct EvalGenerateReport {
    source: String,
    weights_vae_sha256: String,
    weights_dit_sha256: String,
    options: GenerateOptions,
    budget: BudgetSource,
    backend: String,
    skipped: Vec<String>,
    /// Mean stage times per mesh (batched sampling divided by the batch size).
    mean_times: StageTimes,
    all: MethodSummaries,
    buckets: Vec<(String, MethodSummaries)>,
    per_mesh: Vec<MeshResult>,
}

fn summaries(results: &[&MeshResult], with_baseline: bool) -> MethodSummaries {
    let pick = |f: &dyn Fn(&MeshResult) -> Option<&Comparison>| -> Vec<Option<&Comparison>> {
        results.iter().map(|r| f(r)).collect()
    };
    MethodSummaries {
        meshes: results.len(),
        ours: SurfaceSummary::of(&pick(&|r| r.ours.as_ref())),
        vae_upper_bound: SurfaceSummary::of(&pick(&|r| r.vae.as_ref())),
        baseline: with_baseline.then(|| SurfaceSummary::of(&pick(&|r| r.baseline.as_ref()))),
    }
}

pub fn eval_generate(args: EvalGenerateArgs) -> Result<()> {
    let dev = device(BackendKind::from(args.sampling.backend)).map_err(|e| anyhow::anyhow!(e))?;
    let models = load_models(&args.sampling.weights, &dev)?;
    let vcfg = &models.vae_manifest.model;
    let (meshes, mut skipped, source) = args.set.meshes(vcfg.num_vertices)?;
    if let Some(dir) = &args.meshes {
        fs::create_dir_all(dir)?;
    }
    let generator = models.generator(&dev);
    let base_opts = args.sampling.options(None);
    let compare = CompareOptions::default();
    let bar = indicatif::ProgressBar::new(meshes.len() as u64);
    let mut per_mesh = Vec::new();
    let mut targets = serde_json::Map::new();
    let mut total = StageTimes::default();
    let mut timed = 0usize;
    for (c, chunk) in meshes.chunks(args.batch.max(1)).enumerate() {
        let first = c * args.batch.max(1);
        // Conditioning points: the ground truth's surface, seeded per mesh.
        let points: Vec<Vec<glam::Vec3>> = chunk
            .iter()
            .enumerate()
            .map(|(k, (_, m))| {
                sample_surface(m, CONDITION_POINTS, (first + k) as u64).map(|s| s.points)
            })
            .collect::<Result<_, _>>()?;
        // One budget per batch row: sample each mesh alone when budgets come from the ground
        // truth (options are per batch).
        let generated: Vec<Generated> = match args.budget {
            BudgetSource::Rule => generator.generate(&points, &base_opts, &mut |_, _| true)?,
            BudgetSource::GroundTruth => chunk
                .iter()
                .zip(&points)
                .map(|((_, m), p)| {
                    let opts = args.sampling.options(Some(m.positions.len()));
                    generator
                        .generate(std::slice::from_ref(p), &opts, &mut |_, _| true)
                        .map(|mut g| g.remove(0))
                })
                .collect::<Result<_, _>>()?,
        };
        let t = &generated[0].times;
        let rows = if matches!(args.budget, BudgetSource::Rule) {
            1
        } else {
            chunk.len()
        };
        total.condition_s += t.condition_s * rows as f64;
        total.sample_s += t.sample_s * rows as f64;
        total.decode_s += t.decode_s * rows as f64;
        total.extract_s += t.extract_s * rows as f64;
        timed += chunk.len();
        let gts: Vec<Mesh> = chunk.iter().map(|(_, m)| m.clone()).collect();
        let vae = reconstruct_batch(
            &models.vae,
            vcfg,
            &gts,
            // The upper bound extracts exactly as our meshes do.
            &base_opts.extract,
            &compare,
            &dev,
        )
        .ok();
        for (k, ((name, gt), g)) in chunk.iter().zip(generated).enumerate() {
            let index = first + k;
            let score = |m: &Mesh| -> Option<Comparison> {
                (!m.faces.is_empty())
                    .then(|| compare_meshes(m, gt, &compare).ok())
                    .flatten()
            };
            let vae_mesh = vae.as_ref().map(|v| &v[k].mesh);
            let baseline = args.baseline.as_ref().and_then(|dir| {
                let file = dir.join(format!("{index}.poisson.ply"));
                meshflow::io::read_path(&file, &meshflow::io::Limits::default()).ok()
            });
            if let Some(dir) = &args.meshes {
                let write = |m: &Mesh, what: &str| {
                    meshflow::io::write_path(m, &dir.join(format!("{index}.{what}")))
                };
                write(&Mesh::from_points(points[k].clone()), "points.ply")?;
                write(&g.mesh, "ours.glb")?;
                write(gt, "gt.glb")?;
                if let Some(v) = vae_mesh {
                    write(v, "vae.glb")?;
                }
                targets.insert(index.to_string(), g.mesh.faces.len().into());
            }
            per_mesh.push(MeshResult {
                name: name.clone(),
                gt_vertices: gt.positions.len(),
                vertex_budget: g.vertex_budget,
                ours: score(&g.mesh),
                vae: vae_mesh.and_then(score),
                baseline: baseline.as_ref().and_then(score),
            });
        }
        bar.inc(chunk.len() as u64);
    }
    bar.finish_and_clear();
    if let Some(dir) = &args.meshes {
        fs::write(
            dir.join("targets.json"),
            serde_json::to_string_pretty(&targets)?,
        )?;
    }
    let with_baseline = args.baseline.is_some();
    if with_baseline && per_mesh.iter().all(|r| r.baseline.is_none()) {
        skipped.push("no baseline mesh could be read from --baseline".into());
    }
    let n = timed.max(1) as f64;
    let mean_times = StageTimes {
        condition_s: total.condition_s / n,
        sample_s: total.sample_s / n,
        decode_s: total.decode_s / n,
        extract_s: total.extract_s / n,
    };
    let all: Vec<&MeshResult> = per_mesh.iter().collect();
    let buckets = [256usize, 512, 1024]
        .iter()
        .map(|&limit| {
            let rs: Vec<&MeshResult> = all
                .iter()
                .copied()
                .filter(|r| r.gt_vertices <= limit)
                .collect();
            (format!("<= {limit}"), summaries(&rs, with_baseline))
        })
        .collect();
    let report = EvalGenerateReport {
        source,
        weights_vae_sha256: models.vae_manifest.sha256.clone(),
        weights_dit_sha256: models.dit_manifest.sha256.clone(),
        options: base_opts,
        budget: args.budget,
        backend: BackendKind::from(args.sampling.backend).name().into(),
        skipped,
        mean_times,
        all: summaries(&all, with_baseline),
        buckets,
        per_mesh,
    };
    let line = |what: &str, s: &SurfaceSummary| {
        println!(
            "  {what:<16} CD x100 {:7.3}  HD x100 {:7.3}  faces {:7.1}  holes {:6.2}  \
             non-manifold {:6.2}  components {:6.2}  no faces {}",
            s.chamfer_x100,
            s.hausdorff_x100,
            s.faces_out,
            s.holes,
            s.non_manifold_edges,
            s.components,
            s.no_faces
        )
    };
    println!("{} meshes ({})", report.all.meshes, report.source);
    line("ours", &report.all.ours);
    line("VAE upper bound", &report.all.vae_upper_bound);
    if let Some(b) = &report.all.baseline {
        line("Poisson + QEM", b);
    }
    let t = &report.mean_times;
    println!(
        "  mean per mesh: condition {:.3} s, sample {:.3} s, decode {:.3} s, extract {:.3} s",
        t.condition_s, t.sample_s, t.decode_s, t.extract_s
    );
    if let Some(out) = &args.output {
        fs::write(out, serde_json::to_string_pretty(&report)?)?;
        println!("-> {}", out.display());
    }
    Ok(())
}

#[derive(Args)]
pub struct EvalBudgetArgs {
    /// Split of the shard build to fit on.
    #[arg(long, default_value = "train")]
    split: String,
    /// The build's output folder [default: ~/.cache/meshflow/data/shards].
    #[arg(long)]
    data: Option<PathBuf>,
    /// Only meshes with at most this many vertices (the shipped VAE's N).
    #[arg(long, default_value_t = 512)]
    max_vertices: usize,
    /// Write the JSON report here.
    #[arg(short, long)]
    output: Option<PathBuf>,
}

#[derive(Serialize)]
struct BudgetReport {
    source: String,
    meshes: usize,
    fitted: BudgetRule,
    r_squared_log: f64,
    shipped: BudgetRule,
    /// Median of |ln(budget / true vertex count)| for each rule: exp of it is the typical
    /// factor by which a budget misses.
    fitted_median_log_error: f64,
    shipped_median_log_error: f64,
}

/// Fits the default vertex-budget rule on a split and compares it with the shipped one.
pub fn eval_budget(args: EvalBudgetArgs) -> Result<()> {
    let (meshes, _, source) =
        eval_meshes(None, &args.split, args.data.clone(), args.max_vertices, 0)?;
    let bar = indicatif::ProgressBar::new(meshes.len() as u64);
    let examples: Vec<(ShapeFeatures, usize)> = meshes
        .iter()
        .enumerate()
        .filter_map(|(i, (_, m))| {
            bar.inc(1);
            let points = sample_surface(m, CONDITION_POINTS, i as u64).ok()?.points;
            Some((shape_features(&points, i as u64), m.positions.len()))
        })
        .collect();
    bar.finish_and_clear();
    let (fitted, r2) = BudgetRule::fit(&examples)
        .ok_or_else(|| BadInput("too few meshes to fit a rule".into()))?;
    let median_error = |rule: &BudgetRule| {
        let mut e: Vec<f64> = examples
            .iter()
            .map(|(f, v)| {
                (rule.budget(f, args.max_vertices) as f64 / *v as f64)
                    .ln()
                    .abs()
            })
            .collect();
        e.sort_by(f64::total_cmp);
        e[e.len() / 2]
    };
    let report = BudgetReport {
        source,
        meshes: examples.len(),
        fitted,
        r_squared_log: r2,
        shipped: DEFAULT_RULE,
        fitted_median_log_error: median_error(&fitted),
        shipped_median_log_error: median_error(&DEFAULT_RULE),
    };
    println!("{}", serde_json::to_string_pretty(&report)?);
    if let Some(out) = &args.output {
        fs::write(out, serde_json::to_string_pretty(&report)?)?;
    }
    Ok(())
}

#[derive(Args)]
pub struct BenchGenerateArgs {
    /// The point cloud or mesh to generate from.
    #[arg(long, default_value = "tests/fixtures/points/stone_lantern_2048.ply")]
    input: PathBuf,
    /// Timed runs (after one warm-up run).
    #[arg(long, default_value_t = 5)]
    runs: usize,
    #[arg(long)]
    vertices: Option<usize>,
    #[command(flatten)]
    sampling: SamplingArgs,
    /// Where to write the JSON.
    #[arg(short, long)]
    output: PathBuf,
}

#[derive(Serialize)]
struct BenchGenerateReport {
    input: String,
    backend: String,
    steps: usize,
    runs: usize,
    vertex_budget: usize,
    faces: usize,
    load_s: f64,
    /// Medians over the timed runs.
    median: StageTimes,
    median_total_s: f64,
    machine: String,
}

/// Times the whole generation on one input; the first run (shader compilation on wgpu,
/// allocator warm-up) is not counted.
pub fn bench_generate(args: BenchGenerateArgs) -> Result<()> {
    let started = Instant::now();
    let dev = device(BackendKind::from(args.sampling.backend)).map_err(|e| anyhow::anyhow!(e))?;
    let models = load_models(&args.sampling.weights, &dev)?;
    let load_s = started.elapsed().as_secs_f64();
    let points = input_points(&read_input(&args.input)?, args.sampling.seed)
        .map_err(|e| BadInput(e.to_string()))?;
    let generator = models.generator(&dev);
    let opts = args.sampling.options(args.vertices);
    let mut runs = Vec::new();
    for _ in 0..=args.runs.max(1) {
        let g = generator
            .generate(std::slice::from_ref(&points), &opts, &mut |_, _| true)
            .map_err(|e| BadInput(e.to_string()))?;
        runs.push(g.into_iter().next().expect("one input, one output"));
    }
    let last = runs.remove(0);
    let median = |f: &dyn Fn(&StageTimes) -> f64| {
        let mut v: Vec<f64> = runs.iter().map(|g| f(&g.times)).collect();
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let report = BenchGenerateReport {
        input: args.input.display().to_string(),
        backend: BackendKind::from(args.sampling.backend).name().into(),
        steps: opts.steps,
        runs: runs.len(),
        vertex_budget: last.vertex_budget,
        faces: last.mesh.faces.len(),
        load_s,
        median: StageTimes {
            condition_s: median(&|t| t.condition_s),
            sample_s: median(&|t| t.sample_s),
            decode_s: median(&|t| t.decode_s),
            extract_s: median(&|t| t.extract_s),
        },
        median_total_s: median(&|t| t.condition_s + t.sample_s + t.decode_s + t.extract_s),
        machine: crate::train::machine_description(),
    };
    let json = serde_json::to_string_pretty(&report)?;
    println!("{json}");
    fs::write(&args.output, json)
        .with_context(|| format!("cannot write {}", args.output.display()))?;
    Ok(())
}
