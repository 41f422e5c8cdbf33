//! `eval generate`: generation from each test mesh's surface samples (degraded as asked),
//! scored against the ground truth beside the VAE's own reconstruction of it (the upper bound
//! generation can reach with this decoder) and, when given, a Poisson + QEM baseline made by
//! `bench/poisson_qem.py`.

use std::path::Path;

use burn::tensor::Device;
use glam::Vec3;
use serde::Serialize;

use crate::Mesh;
use crate::data::degrade::{Degradation, degrade};
use crate::eval::metrics::{CompareOptions, Comparison, compare_meshes};
use crate::eval::sets::EvalSet;
use crate::eval::summary::{SurfaceSummary, bucketed};
use crate::geometry::sample::sample_surface;
use crate::pipeline::generate::{
    CONDITION_POINTS, GenerateError, GenerateOptions, Generated, StageTimes, faces_range,
};
use crate::pipeline::reconstruct::reconstruct_batch;
use crate::pipeline::shipped::ShippedModels;

/// Where the vertex budget of each generated mesh comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum BudgetSource {
    /// The default rule on the conditioning points, as a user gets it.
    Rule,
    /// The ground truth's vertex count (an oracle, for comparison).
    GroundTruth,
    /// The ground truth's face count, asked for as `faces` (how well face counts steer).
    GroundTruthFaces,
}

impl BudgetSource {
    pub const ALL: [BudgetSource; 3] = [Self::Rule, Self::GroundTruth, Self::GroundTruthFaces];

    /// The command-line name (`rule`, `ground-truth`, `ground-truth-faces`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Rule => "rule",
            Self::GroundTruth => "ground-truth",
            Self::GroundTruthFaces => "ground-truth-faces",
        }
    }
}

impl std::str::FromStr for BudgetSource {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|b| b.name() == s)
            .ok_or_else(|| format!("unknown budget source {s:?}"))
    }
}

/// How `eval generate` runs.
pub struct GenerationEval<'a> {
    /// Options of every generation (`vertices` and `faces` are set per mesh by `budget`).
    pub options: GenerateOptions,
    pub budget: BudgetSource,
    /// Meshes per sampling batch (with the rule; oracle budgets sample one mesh at a time).
    pub batch: usize,
    /// The conditioning points' degradation (noise, a missing region).
    pub degradation: Degradation,
    /// A folder with `K.poisson.ply` per mesh K, scored as the baseline.
    pub baseline: Option<&'a Path>,
    /// Write, per mesh K: `K.points.ply` (the conditioning points), `K.ours.glb`,
    /// `K.vae.glb`, `K.gt.glb`, and `targets.json` (our face counts, for
    /// `bench/poisson_qem.py`).
    pub meshes: Option<&'a Path>,
    /// The backend's name, for the report.
    pub backend: &'a str,
}

/// Why an evaluation stopped.
#[derive(Debug, thiserror::Error)]
pub enum GenerationEvalError {
    #[error(transparent)]
    Generate(#[from] GenerateError),
    #[error(transparent)]
    Sample(#[from] crate::geometry::sample::SampleError),
    #[error(transparent)]
    Write(#[from] crate::io::WriteError),
    #[error("{0}")]
    Io(#[from] std::io::Error),
}

/// The summary `meshflow eval generate` prints: one line per method (ours, the VAE's bound,
/// the baseline when scored), the ground truth's topology, the mean stage times.
impl std::fmt::Display for GenerationEvalReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let line = |f: &mut std::fmt::Formatter<'_>, what: &str, s: &SurfaceSummary| {
            writeln!(
                f,
                "  {what:<16} CD x100 {:7.3}  HD x100 {:7.3}  NC {:.4}  ECD x100 {:7.3}  EF1 \
                 {:.4}  faces {:7.1} ({:.2}x gt)  holes {:6.2}  non-manifold {:6.2}  \
                 folded {:6.2} (in {})  components {:6.2}  no faces {}",
                s.chamfer_x100,
                s.hausdorff_x100,
                s.normal_consistency,
                s.edge_chamfer_x100,
                s.edge_f_score,
                s.faces_out,
                s.faces_ratio,
                s.holes,
                s.non_manifold_edges,
                s.folded_edges,
                s.folded_meshes,
                s.components,
                s.no_faces
            )
        };
        writeln!(f, "{} meshes ({})", self.all.meshes, self.source)?;
        line(f, "ours", &self.all.ours)?;
        line(f, "VAE upper bound", &self.all.vae_upper_bound)?;
        if let Some(b) = &self.all.baseline {
            line(f, "Poisson + QEM", b)?;
        }
        let o = &self.all.ours;
        writeln!(
            f,
            "  ground truth     holes {:6.2}  components {:6.2}; closed in {} meshes, where ours \
             has {:.2} holes",
            o.gt_holes, o.gt_components, o.gt_closed, o.holes_where_gt_closed
        )?;
        let t = &self.mean_times;
        writeln!(
            f,
            "  mean per mesh: condition {:.3} s, sample {:.3} s, decode {:.3} s, extract {:.3} \
             s, fit {:.3} s",
            t.condition_s, t.sample_s, t.decode_s, t.extract_s, t.fit_s
        )
    }
}

/// One mesh's result.
#[derive(Clone, Debug, Serialize)]
pub struct MeshResult {
    pub name: String,
    pub gt_vertices: usize,
    pub vertex_budget: usize,
    /// With [`BudgetSource::GroundTruthFaces`]: the faces asked for.
    pub faces_asked: Option<usize>,
    pub faces_made: usize,
    /// What sharpening did to our mesh, and whether it was kept.
    pub sharpen: crate::surface::sharpen::SharpenReport,
    pub ours: Option<Comparison>,
    pub vae: Option<Comparison>,
    pub baseline: Option<Comparison>,
}

/// Means per method over a set of results.
#[derive(Clone, Debug, Serialize)]
pub struct MethodSummaries {
    pub meshes: usize,
    pub ours: SurfaceSummary,
    pub vae_upper_bound: SurfaceSummary,
    pub baseline: Option<SurfaceSummary>,
}

impl MethodSummaries {
    /// The means over `results`; the baseline's only `with_baseline`.
    pub fn of(results: &[&MeshResult], with_baseline: bool) -> Self {
        let pick = |f: &dyn Fn(&MeshResult) -> Option<&Comparison>| -> Vec<Option<&Comparison>> {
            results.iter().map(|r| f(r)).collect()
        };
        Self {
            meshes: results.len(),
            ours: SurfaceSummary::of(&pick(&|r| r.ours.as_ref())),
            vae_upper_bound: SurfaceSummary::of(&pick(&|r| r.vae.as_ref())),
            baseline: with_baseline.then(|| SurfaceSummary::of(&pick(&|r| r.baseline.as_ref()))),
        }
    }
}

/// What `eval generate` writes as JSON.
#[derive(Serialize)]
pub struct GenerationEvalReport {
    pub source: String,
    pub weights_vae_sha256: String,
    pub weights_dit_sha256: String,
    pub options: GenerateOptions,
    pub budget: BudgetSource,
    /// The conditioning points' degradation (`--noise`, `--missing`).
    pub noise: f32,
    pub missing: f32,
    pub backend: String,
    pub skipped: Vec<String>,
    /// Mean stage times per mesh (batched sampling divided by the batch size).
    pub mean_times: StageTimes,
    pub all: MethodSummaries,
    pub buckets: Vec<(String, MethodSummaries)>,
    pub per_mesh: Vec<MeshResult>,
}

/// Generates from every mesh of `set` (conditioning points: its surface, seeded by its
/// position in the set, degraded as asked; generation seeded by the options' seed plus that
/// position), scores ours, the VAE's reconstruction (extracted exactly as ours) and the
/// baseline against it, and summarises. `progress` is called with the meshes done after each
/// batch.
pub fn evaluate_generation(
    models: &ShippedModels,
    set: EvalSet,
    eval: &GenerationEval,
    device: &Device,
    progress: &mut dyn FnMut(usize),
) -> Result<GenerationEvalReport, GenerationEvalError> {
    let vcfg = &models.vae_manifest.model;
    let EvalSet {
        meshes,
        mut skipped,
        source,
    } = set;
    // The ground truth's face count, within what the model can be asked for.
    let faces_asked = |m: &Mesh| {
        let range = faces_range(vcfg.num_vertices);
        m.faces.len().clamp(*range.start(), *range.end())
    };
    let options_for = |m: &Mesh| {
        let mut o = eval.options.clone();
        match eval.budget {
            BudgetSource::Rule => {}
            BudgetSource::GroundTruth => o.vertices = Some(m.positions.len()),
            BudgetSource::GroundTruthFaces => o.faces = Some(faces_asked(m)),
        }
        o
    };
    if let Some(dir) = eval.meshes {
        std::fs::create_dir_all(dir)?;
    }
    let generator = models.generator(device);
    let compare = CompareOptions::default();
    let batch = eval.batch.max(1);
    let mut per_mesh = Vec::new();
    let mut targets = serde_json::Map::new();
    let mut total = StageTimes::default();
    for (c, chunk) in meshes.chunks(batch).enumerate() {
        let first = c * batch;
        let points: Vec<Vec<Vec3>> = chunk
            .iter()
            .enumerate()
            .map(|(k, (_, m))| {
                let seed = (first + k) as u64;
                sample_surface(m, CONDITION_POINTS, seed)
                    .map(|s| degrade(&s.points, &eval.degradation, seed))
            })
            .collect::<Result<_, _>>()?;
        // Options are per batch: with budgets from the ground truth each mesh samples alone.
        // Mesh `first + k` is generated at seed `seed + first + k`, as `meshflow generate` on
        // its points with that seed would (input k of a batch is the input alone at seed + k).
        let chunk_options = GenerateOptions {
            seed: eval.options.seed + first as u64,
            ..eval.options.clone()
        };
        let generated: Vec<Generated> = match eval.budget {
            BudgetSource::Rule => generator.generate(&points, &chunk_options, &mut |_, _| true)?,
            _ => chunk
                .iter()
                .zip(&points)
                .enumerate()
                .map(|(k, ((_, m), p))| {
                    let options = GenerateOptions {
                        seed: chunk_options.seed + k as u64,
                        ..options_for(m)
                    };
                    generator
                        .generate(std::slice::from_ref(p), &options, &mut |_, _| true)
                        .map(|mut g| g.remove(0))
                })
                .collect::<Result<_, _>>()?,
        };
        let t = &generated[0].times;
        let rows = match eval.budget {
            BudgetSource::Rule => 1,
            _ => chunk.len(),
        } as f64;
        total.condition_s += t.condition_s * rows;
        total.sample_s += t.sample_s * rows;
        total.decode_s += t.decode_s * rows;
        total.extract_s += t.extract_s * rows;
        total.fit_s += t.fit_s * rows;
        let gts: Vec<Mesh> = chunk.iter().map(|(_, m)| m.clone()).collect();
        let vae = reconstruct_batch(
            &models.vae,
            vcfg,
            &gts,
            // The upper bound extracts exactly as our meshes do.
            &eval.options.extract,
            &compare,
            device,
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
            let baseline = eval.baseline.and_then(|dir| {
                let file = dir.join(format!("{index}.poisson.ply"));
                crate::io::read_path(&file, &crate::io::Limits::default()).ok()
            });
            if let Some(dir) = eval.meshes {
                let write = |m: &Mesh, what: &str| {
                    crate::io::write_path(m, &dir.join(format!("{index}.{what}")))
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
                faces_asked: (eval.budget == BudgetSource::GroundTruthFaces)
                    .then(|| faces_asked(gt)),
                faces_made: g.mesh.faces.len(),
                sharpen: g.sharpen,
                ours: score(&g.mesh),
                vae: vae_mesh.and_then(score),
                baseline: baseline.as_ref().and_then(score),
            });
        }
        progress(first + chunk.len());
    }
    if let Some(dir) = eval.meshes {
        crate::io::write_atomic(
            &dir.join("targets.json"),
            serde_json::to_string_pretty(&targets)
                .map_err(std::io::Error::from)?
                .as_bytes(),
        )?;
    }
    let with_baseline = eval.baseline.is_some();
    if with_baseline && per_mesh.iter().all(|r| r.baseline.is_none()) {
        skipped.push("no baseline mesh could be read from --baseline".into());
    }
    let n = per_mesh.len().max(1) as f64;
    let mean_times = StageTimes {
        condition_s: total.condition_s / n,
        sample_s: total.sample_s / n,
        decode_s: total.decode_s / n,
        extract_s: total.extract_s / n,
        fit_s: total.fit_s / n,
    };
    let (all, buckets) = bucketed(
        &per_mesh,
        |r| r.gt_vertices,
        |some| MethodSummaries::of(some, with_baseline),
    );
    Ok(GenerationEvalReport {
        source,
        weights_vae_sha256: models.vae_manifest.sha256.clone(),
        weights_dit_sha256: models.dit_manifest.sha256.clone(),
        // Extraction ran at the VAE's tau, whatever the options said (ExtractOptions::tau).
        options: GenerateOptions {
            extract: eval.options.extract.at_tau_of(&models.vae_manifest.model),
            ..eval.options.clone()
        },
        budget: eval.budget,
        noise: eval.degradation.noise,
        missing: eval.degradation.missing,
        backend: eval.backend.into(),
        skipped,
        mean_times,
        all,
        buckets,
        per_mesh,
    })
}

/// What `bench generate` writes as JSON.
#[derive(Serialize)]
pub struct GenerationTiming {
    pub input: String,
    pub backend: String,
    pub steps: usize,
    pub solver: crate::model::sampler::Solver,
    pub runs: usize,
    pub vertex_budget: usize,
    pub faces: usize,
    pub load_s: f64,
    /// Medians over the timed runs.
    pub median: StageTimes,
    pub median_total_s: f64,
    pub machine: String,
}

/// Generates from `points` once untimed (shader compilation on wgpu, allocator warm-up) and
/// then `runs` times (at least once), and returns the last generation and the median of each
/// stage's time over the timed runs (the caller fills in the descriptive fields).
pub fn time_generation(
    models: &ShippedModels,
    points: &[Vec3],
    options: &GenerateOptions,
    runs: usize,
    device: &Device,
) -> Result<(Generated, StageTimes, f64), GenerateError> {
    let generator = models.generator(device);
    let mut done = Vec::new();
    for _ in 0..=runs.max(1) {
        let g = generator.generate(&[points.to_vec()], options, &mut |_, _| true)?;
        done.push(g.into_iter().next().expect("one input, one output"));
    }
    let warm_up = done.remove(0);
    let median = |f: &dyn Fn(&StageTimes) -> f64| {
        let mut v: Vec<f64> = done.iter().map(|g| f(&g.times)).collect();
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let times = StageTimes {
        condition_s: median(&|t| t.condition_s),
        sample_s: median(&|t| t.sample_s),
        decode_s: median(&|t| t.decode_s),
        extract_s: median(&|t| t.extract_s),
        fit_s: median(&|t| t.fit_s),
    };
    let total = median(&|t| t.condition_s + t.sample_s + t.decode_s + t.extract_s + t.fit_s);
    Ok((warm_up, times, total))
}
