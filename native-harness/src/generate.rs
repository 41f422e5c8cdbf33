//! `meshflow generate`, `meshflow eval generate` and `meshflow eval budget`: point clouds to
//! meshes with the shipped VAE and DiT, and their evaluation against the VAE's reconstruction
//! (the upper bound) and a Poisson + QEM baseline made by `bench/poisson_qem.py`.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};
use meshflow::burn::tensor::Device;
use meshflow::data::degrade::Degradation;
use meshflow::device::machine_description;
use meshflow::eval::budget::evaluate_budget_rule;
use meshflow::eval::generation::{
    BudgetSource, GenerationEval, GenerationTiming, evaluate_generation, time_generation,
};
use meshflow::eval::sets::eval_set;
use meshflow::model::sampler::Solver;
use meshflow::model::schedule::ScheduleMode;
use meshflow::pipeline::budget::ShapeFeatures;
use meshflow::pipeline::generate::{GenerateOptions, Generated, StageTimes, input_points};
use meshflow::pipeline::shipped::ShippedModels;
use meshflow::surface::close::CloseOptions;
use meshflow::surface::complete::CompleteOptions;
use meshflow::surface::fit::FitOptions;
use meshflow::surface::sharpen::SharpenOptions;
use serde::Serialize;

use crate::args::{BackendArg, ExtractionArgs, one_of};
use crate::files::{create_dir, print_json, read_mesh, write_json, write_mesh};
use crate::vae_eval::{EvalSetArgs, eval_set_error};
use crate::weights::{load_models, weights_dir};
use crate::{BadInput, bad_input};

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

/// How each sampler step integrates the flow, as a command-line value.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum SolverArg {
    /// One DiT evaluation a step, as the paper.
    Euler,
    /// Heun's second-order step: two evaluations (one on a step that ends at t = 0).
    Heun,
    /// The midpoint rule: two evaluations a step (the default).
    Midpoint,
}

impl From<SolverArg> for Solver {
    fn from(s: SolverArg) -> Self {
        match s {
            SolverArg::Euler => Solver::Euler,
            SolverArg::Heun => Solver::Heun,
            SolverArg::Midpoint => Solver::Midpoint,
        }
    }
}

/// Options shared by `generate` and `eval generate`.
#[derive(Args, Clone)]
pub struct SamplingArgs {
    /// Folder with the VAE (vae.*) and DiT (dit.*) weights and manifests [default: the
    /// shipped weights, found from any folder: see README.md].
    #[arg(long)]
    weights: Option<PathBuf>,
    /// Sampler steps, each of `--solver` (the paper's default is 28 Euler steps; a candidate
    /// more buys more than more steps).
    #[arg(long, default_value_t = GenerateOptions::default().steps)]
    steps: usize,
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Candidates drawn from different noise; the one kept lies closest to the input points,
    /// each hole and its normals' disagreement with the points' planes counting against it
    /// (each costs a whole generation; 1..=16).
    #[arg(long, default_value_t = GenerateOptions::default().samples)]
    samples: usize,
    #[arg(long, value_enum, default_value = "to-zero")]
    schedule: Schedule,
    #[arg(long, value_enum, default_value = "midpoint")]
    solver: SolverArg,
    #[command(flatten)]
    extract: ExtractionArgs,
    /// Rounds of moving the extracted vertices onto the input points' surface (0 = as
    /// decoded; see `--no-fit`).
    #[arg(long, default_value_t = FitOptions::default().iterations)]
    fit_iterations: usize,
    /// Input points that define each vertex's local surface plane when fitting.
    #[arg(long, default_value_t = FitOptions::default().neighbours)]
    fit_neighbours: usize,
    /// Keep the vertices where the model decoded them (same as `--fit-iterations 0`).
    #[arg(long)]
    no_fit: bool,
    /// Keep only the faces the model made: do not complete the surface between its vertices
    /// with triangles on the input points (manifold extraction only).
    #[arg(long)]
    no_complete: bool,
    /// Completion: the longest new edge, in median edges of the model's faces.
    #[arg(long, default_value_t = CompleteOptions::default().max_edge_ratio)]
    complete_max_edge: f32,
    /// Completion: how far a new face may be from the input points, in point spacings.
    #[arg(long, default_value_t = CompleteOptions::default().max_gap)]
    complete_max_gap: f32,
    /// Completion: weld vertices closer than this many median edges first.
    #[arg(long, default_value_t = CompleteOptions::default().weld_ratio)]
    complete_weld: f32,
    /// Completion: refuse a face lying on another one it shares no edge with, within this
    /// many of its longest edges of its plane (a second layer; 0 = no test).
    #[arg(long, default_value_t = CompleteOptions::default().overlap_tolerance)]
    complete_overlap: f32,
    /// Completion: close hole loops of at most this many edges afterwards.
    #[arg(long, default_value_t = CompleteOptions::default().max_hole_edges)]
    complete_hole_edges: usize,
    /// Completion: keep the model's faces even where they leave the input surface.
    #[arg(long)]
    keep_off_surface: bool,
    /// Completion: how far ahead of new triangles the model's faces rank, in local Delaunay
    /// votes (inf: all first).
    #[arg(long, default_value_t = CompleteOptions::default().model_priority)]
    complete_model_priority: f32,
    /// Completion: the local Delaunay test leaves out neighbours farther out of a vertex's
    /// tangent plane than this sine (1: none).
    #[arg(long, default_value_t = CompleteOptions::default().max_slope)]
    complete_max_slope: f32,
    /// Completion: rounds of fitting and completing again afterwards.
    #[arg(long, default_value_t = CompleteOptions::default().refine_passes)]
    complete_passes: usize,
    /// Completion: how far each vertex moves towards its neighbours' centroid in those rounds'
    /// fits (0 to 1).
    #[arg(long, default_value_t = CompleteOptions::default().refine_smoothing)]
    complete_smoothing: f32,
    /// Completion: also offer triangles no vertex's local Delaunay triangulation has.
    #[arg(long)]
    complete_unvoted: bool,
    /// Completion: add vertices at the input points the surface misses (where at least 1/32
    /// of the input is missed together), no two closer than this many median edges, and
    /// complete again, so that a part the model left out (a leg, a pole) is covered; 0.7
    /// measured: nearer and sharper, a few more faces and holes (0 = none).
    #[arg(long, default_value_t = CompleteOptions::default().seed_gap)]
    complete_seed_gap: f32,
    /// Completion: nearest vertices each vertex may make a new face with.
    #[arg(long, default_value_t = CompleteOptions::default().neighbours)]
    complete_neighbours: usize,
    /// Leave open the holes completion could not fill (by default each is closed where the
    /// input goes on, by a fan around one new vertex or a triangulation of its border, never
    /// folded; only when completing; and again, without cuts, after sharpening).
    #[arg(long)]
    no_close_holes: bool,
    /// Hole closing: leave open the loops of more than this many edges (0 = no limit).
    #[arg(long, default_value_t = CloseOptions::default().max_edges)]
    close_max_edges: usize,
    /// Hole closing: leave open a hole whose fan would leave the input surface by more than
    /// this many point spacings (0 = no test).
    #[arg(long, default_value_t = CloseOptions::default().max_gap)]
    close_max_gap: f32,
    /// Hole closing: cut at most this many faces to close a loop whose patch would fold onto
    /// them, closing the larger loop instead (0 = no cuts).
    #[arg(long, default_value_t = CloseOptions::default().max_cut_faces)]
    close_max_cut: usize,
    /// Leave the surface as fitted: do not sharpen it against the input points' planes
    /// (creases snapped, flat regions merged into few faces; manifold extraction only).
    #[arg(long)]
    no_sharpen: bool,
    /// Sharpening: RMS distance a collapse below the incoming face count may cost, as a
    /// share of the input's longest side.
    #[arg(long, default_value_t = SharpenOptions::default().flat_tolerance)]
    sharpen_tolerance: f64,
    /// Sharpening: the same tolerance in multiples of the input points' own RMS spread off
    /// their planes (their noise); the larger of the two holds.
    #[arg(long, default_value_t = SharpenOptions::default().noise_tolerance)]
    sharpen_noise_tolerance: f64,
    /// Sharpening: rounds of splitting, placing, flipping, collapsing and snapping.
    #[arg(long, default_value_t = SharpenOptions::default().passes)]
    sharpen_passes: usize,
    /// Sharpening: keep the sharpened mesh when it is at most this many times as far from the
    /// input points as the fitted one.
    #[arg(long, default_value_t = SharpenOptions::default().accept_ratio)]
    sharpen_accept: f64,
    /// Sharpening: sharpen this many candidates, the nearest the input points first, and keep
    /// the sharpened one nearest them.
    #[arg(long, default_value_t = SharpenOptions::default().candidates)]
    sharpen_candidates: usize,
    /// Sharpening: steps of reach in each round, in which the input points the mesh does not
    /// come near draw it out along the surface (0: none).
    #[arg(long, default_value_t = SharpenOptions::default().reach_steps)]
    sharpen_reach_steps: usize,
    /// Sharpening: most 1-to-4 splits of the faces in each round after the first.
    #[arg(long, default_value_t = SharpenOptions::default().later_refine)]
    sharpen_later_refine: usize,
    #[command(flatten)]
    backend: BackendArg,
}

impl SamplingArgs {
    /// The backend's device and the VAE and DiT of `--weights`.
    fn device_and_models(&self) -> Result<(Device, ShippedModels)> {
        let device = self.backend.device()?;
        let models = load_models(&weights_dir(self.weights.as_deref())?, &device)?;
        Ok((device, models))
    }

    fn options(&self, vertices: Option<usize>, faces: Option<usize>) -> GenerateOptions {
        GenerateOptions {
            vertices,
            faces,
            steps: self.steps,
            seed: self.seed,
            samples: self.samples,
            schedule: self.schedule.into(),
            solver: self.solver.into(),
            extract: self.extract.options(),
            fit: if self.no_fit {
                FitOptions::OFF
            } else {
                FitOptions {
                    iterations: self.fit_iterations,
                    neighbours: self.fit_neighbours,
                    ..FitOptions::default()
                }
            },
            complete: CompleteOptions {
                enabled: !self.no_complete,
                neighbours: self.complete_neighbours,
                max_edge_ratio: self.complete_max_edge,
                max_gap: self.complete_max_gap,
                drop_off_surface: !self.keep_off_surface,
                max_hole_edges: self.complete_hole_edges,
                weld_ratio: self.complete_weld,
                overlap_tolerance: self.complete_overlap,
                model_priority: self.complete_model_priority,
                max_slope: self.complete_max_slope,
                refine_passes: self.complete_passes,
                refine_smoothing: self.complete_smoothing,
                require_vote: !self.complete_unvoted,
                seed_gap: self.complete_seed_gap,
                ..CompleteOptions::default()
            },
            close: CloseOptions {
                enabled: !self.no_close_holes,
                max_edges: self.close_max_edges,
                max_gap: self.close_max_gap,
                max_cut_faces: self.close_max_cut,
            },
            sharpen: SharpenOptions {
                enabled: !self.no_sharpen,
                flat_tolerance: self.sharpen_tolerance,
                noise_tolerance: self.sharpen_noise_tolerance,
                passes: self.sharpen_passes,
                accept_ratio: self.sharpen_accept,
                candidates: self.sharpen_candidates,
                reach_steps: self.sharpen_reach_steps,
                later_refine: self.sharpen_later_refine,
                ..SharpenOptions::default()
            },
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
    #[arg(long, conflicts_with = "faces")]
    vertices: Option<usize>,
    /// Faces to aim for (the result lands near it; the report says what came out).
    #[arg(long)]
    faces: Option<usize>,
    #[command(flatten)]
    sampling: SamplingArgs,
    /// Print JSON (timings, budget, topology) instead of text.
    #[arg(long)]
    json: bool,
}

/// What `generate --json` prints per input.
#[derive(Serialize)]
struct GenerateReport<'a> {
    input: String,
    output: String,
    /// `--faces`, when given (the faces made are in `topology`).
    faces_asked: Option<usize>,
    /// `--samples`: candidates drawn, one kept.
    samples: usize,
    vertex_budget: usize,
    features: ShapeFeatures,
    load_s: f64,
    times: &'a StageTimes,
    extract: &'a meshflow::extract::ExtractReport,
    fit: &'a meshflow::surface::fit::FitReport,
    complete: &'a meshflow::surface::complete::CompleteReport,
    close: &'a meshflow::surface::close::CloseReport,
    sharpen: &'a meshflow::surface::sharpen::SharpenReport,
    topology: &'a meshflow::geometry::topology::TopologyReport,
}

pub fn generate(args: GenerateArgs) -> Result<()> {
    let started = Instant::now();
    let (device, models) = args.sampling.device_and_models()?;
    let load_model_s = started.elapsed().as_secs_f64();
    let jobs: Vec<(PathBuf, PathBuf)> = if args.input.is_dir() {
        create_dir(&args.output)?;
        let files = meshflow::io::mesh_files(&args.input)
            .with_context(|| format!("cannot list {}", args.input.display()))?;
        if files.is_empty() {
            bail!(BadInput(format!(
                "{}: no mesh or point-cloud file in the folder",
                args.input.display()
            )));
        }
        files
            .into_iter()
            .map(|input| {
                let output = meshflow::io::output_in(&args.output, &input, "glb");
                (input, output)
            })
            .collect()
    } else {
        vec![(args.input.clone(), args.output.clone())]
    };
    let generator = models.generator(&device);
    let opts = args.sampling.options(args.vertices, args.faces);
    let batch = jobs.len() > 1;
    let mut failures = 0;
    for (input, output) in &jobs {
        let started = Instant::now();
        let result = read_mesh(input).and_then(|mesh| {
            let points = input_points(&mesh, opts.seed).map_err(bad_input)?;
            if mesh.faces.is_empty() && points.len() < mesh.positions.len() && !args.json {
                println!(
                    "{}: {} points, conditioning on {} of them (an even random subsample)",
                    input.display(),
                    mesh.positions.len(),
                    points.len()
                );
            }
            let load_s = load_model_s + started.elapsed().as_secs_f64();
            let bar = crate::progress::step_bar(opts.steps, args.json);
            let mut out = generator
                .generate(&[points], &opts, &mut |i, _| {
                    bar.set_position(i as u64);
                    true
                })
                .map_err(|e| bad_input(format!("{}: {e}", input.display())))?;
            bar.finish_and_clear();
            let g = out.remove(0);
            write_mesh(&g.mesh, output)?;
            Ok((g, load_s))
        });
        match result {
            Ok((g, load_s)) => report(&g, input, output, load_s, &args)?,
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

/// Prints what `generate` made of `input`: one JSON line with `--json`, else text.
fn report(
    g: &Generated,
    input: &Path,
    output: &Path,
    load_s: f64,
    args: &GenerateArgs,
) -> Result<()> {
    let (faces_asked, samples) = (args.faces, args.sampling.samples);
    if args.json {
        let r = GenerateReport {
            input: input.display().to_string(),
            output: output.display().to_string(),
            faces_asked,
            samples,
            vertex_budget: g.vertex_budget,
            features: g.features,
            load_s,
            times: &g.times,
            extract: &g.extract,
            fit: &g.fit,
            complete: &g.complete,
            close: &g.close,
            sharpen: &g.sharpen,
            topology: &g.topology,
        };
        println!("{}", serde_json::to_string(&r)?);
        return Ok(());
    }
    let t = &g.times;
    let topo = &g.topology;
    println!("{} -> {}", input.display(), output.display());
    match faces_asked {
        Some(f) => println!(
            "  asked for {f} faces: vertex budget {}, {} faces made",
            g.vertex_budget,
            g.mesh.faces.len()
        ),
        None => println!(
            "  vertex budget {} (occupancy {}, surface variation {:.4}, planar share {:.3})",
            g.vertex_budget,
            g.features.occupied_voxels,
            g.features.surface_variation,
            g.features.planar_share
        ),
    }
    if samples > 1 {
        println!(
            "  kept the best of {samples} candidates: closest to the input points, holes counting against them"
        );
    }
    println!(
        "  times: load {:.3} s, condition {:.3} s, sample {:.3} s, decode {:.3} s, extract {:.3} s, \
         fit {:.3} s",
        load_s, t.condition_s, t.sample_s, t.decode_s, t.extract_s, t.fit_s
    );
    if g.fit.iterations > 0 {
        println!(
            "  fitted to the input points: mean vertex distance {:.4} -> {:.4} ({} moves held \
             back in the last round)",
            g.fit.mean_distance_before, g.fit.mean_distance_after, g.fit.held_back
        );
    }
    let c = &g.close;
    if c.holes_closed + c.holes_left > 0 {
        let cut = if c.faces_cut > 0 {
            format!(", {} cut from folded rims", c.faces_cut)
        } else {
            String::new()
        };
        println!(
            "  holes closed: {} ({} faces, {} vertices added{cut}; --no-close-holes keeps them \
             open)",
            c.holes_closed, c.faces_added, c.vertices_added
        );
    }
    if g.sharpen.ran() {
        println!("  {}", g.sharpen);
    }
    println!(
        "  {} vertices, {} faces, {} components; {} boundary edges, {} holes, {} non-manifold \
         edges, {} inconsistent winding, {} degenerate faces, {} folded edges",
        topo.vertices,
        topo.faces,
        topo.components,
        topo.boundary_edges,
        topo.holes,
        topo.non_manifold_edges,
        topo.inconsistent_winding_edges,
        topo.degenerate_faces,
        topo.folded_edges
    );
    Ok(())
}

#[derive(Args)]
pub struct EvalGenerateArgs {
    #[command(flatten)]
    set: EvalSetArgs,
    /// Where each mesh's vertex budget comes from: the default rule (as a user gets it), the
    /// ground truth's vertex count (an oracle), or its face count asked for as `--faces`.
    #[arg(long, default_value = "rule", value_parser = one_of::<BudgetSource>(BudgetSource::ALL.map(BudgetSource::name)))]
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
    /// Gaussian noise added to the conditioning points, as a fraction of their bounding box's
    /// longest side (0.01 = 1% noise, like a scan).
    #[arg(long, default_value_t = 0.0)]
    noise: f32,
    /// Fraction of the conditioning points removed as one region (0.3 = 30% of the surface
    /// missing, like a partial scan).
    #[arg(long, default_value_t = 0.0)]
    missing: f32,
    /// Write the JSON report here.
    #[arg(short, long)]
    output: Option<PathBuf>,
}

pub fn eval_generate(args: EvalGenerateArgs) -> Result<()> {
    let (dev, models) = args.sampling.device_and_models()?;
    let set = args.set.meshes(models.vae_manifest.model.num_vertices)?;
    let bar = indicatif::ProgressBar::new(set.meshes.len() as u64);
    let eval = GenerationEval {
        options: args.sampling.options(None, None),
        budget: args.budget,
        batch: args.batch,
        degradation: Degradation {
            noise: args.noise,
            missing: args.missing,
        },
        baseline: args.baseline.as_deref(),
        meshes: args.meshes.as_deref(),
        backend: args.sampling.backend.kind.name(),
    };
    let report = evaluate_generation(&models, set, &eval, &dev, &mut |done| {
        bar.set_position(done as u64)
    })?;
    bar.finish_and_clear();
    print!("{report}");
    if let Some(out) = &args.output {
        write_json(out, &report)?;
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

/// Fits the default vertex-budget rule on a split and compares it with the shipped one.
pub fn eval_budget(args: EvalBudgetArgs) -> Result<()> {
    let shards = crate::data::shards_dir(args.data.clone());
    let set = eval_set(None, &args.split, &shards, args.max_vertices, 0).map_err(eval_set_error)?;
    let bar = indicatif::ProgressBar::new(set.meshes.len() as u64);
    let report = evaluate_budget_rule(&set.meshes, args.max_vertices, set.source, &mut |done| {
        bar.set_position(done as u64)
    })
    .ok_or_else(|| BadInput("too few meshes to fit a rule".into()))?;
    bar.finish_and_clear();
    print_json(&report)?;
    if let Some(out) = &args.output {
        write_json(out, &report)?;
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

/// Times the whole generation on one input; the first run (shader compilation on wgpu,
/// allocator warm-up) is not counted.
pub fn bench_generate(args: BenchGenerateArgs) -> Result<()> {
    let started = Instant::now();
    let (dev, models) = args.sampling.device_and_models()?;
    let load_s = started.elapsed().as_secs_f64();
    let points = input_points(&read_mesh(&args.input)?, args.sampling.seed).map_err(bad_input)?;
    let opts = args.sampling.options(args.vertices, None);
    let (last, median, median_total_s) =
        time_generation(&models, &points, &opts, args.runs, &dev).map_err(bad_input)?;
    let report = GenerationTiming {
        input: args.input.display().to_string(),
        backend: args.sampling.backend.kind.name().into(),
        steps: opts.steps,
        solver: opts.solver,
        runs: args.runs.max(1),
        vertex_budget: last.vertex_budget,
        faces: last.mesh.faces.len(),
        load_s,
        median,
        median_total_s,
        machine: machine_description(),
    };
    print_json(&report)?;
    write_json(&args.output, &report)
}

#[derive(Args)]
pub struct BenchPairHeadArgs {
    /// The point cloud or mesh to generate from.
    #[arg(long, default_value = "tests/fixtures/points/stone_lantern_2048.ply")]
    input: PathBuf,
    /// Minimum time per candidate and edge source, in seconds.
    #[arg(long, default_value_t = 1.0)]
    seconds: f64,
    #[command(flatten)]
    sampling: SamplingArgs,
    /// Where to write the JSON.
    #[arg(short, long)]
    output: PathBuf,
}

/// Times stage 4 per candidate from the three edge sources of
/// [`meshflow::eval::pair_head_extraction`] and prints the sums.
pub fn bench_pair_head(args: BenchPairHeadArgs) -> Result<()> {
    let (dev, models) = args.sampling.device_and_models()?;
    let points = input_points(&read_mesh(&args.input)?, args.sampling.seed).map_err(bad_input)?;
    let opts = args.sampling.options(None, None);
    let report = meshflow::eval::pair_head_extraction::trace_pair_head_extraction(
        &models.generator(&dev),
        &points,
        &opts,
        Duration::try_from_secs_f64(args.seconds)
            .map_err(|_| BadInput(format!("--seconds {} is not a duration", args.seconds)))?,
    )
    .map_err(bad_input)?;
    println!(
        "{} candidates, {} slots each; sums over the candidates (one thread):",
        report.candidates.len(),
        report.slots
    );
    println!("edge source             median ms  edges  clique faces  faces");
    for (name, t) in [
        ("embeddings", &report.embeddings),
        ("spacetime distances", &report.spacetime_distances),
        ("pair head distances", &report.pair_head_distances),
    ] {
        println!(
            "{name:22} {:>10.2} {:>6} {:>13} {:>6}",
            t.median_ms, t.edges, t.clique_faces, t.faces
        );
    }
    write_json(&args.output, &report)
}
