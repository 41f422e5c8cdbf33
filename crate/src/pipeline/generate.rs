//! Point cloud -> artist-like mesh: the whole MeshFlow inference path, shared by the CLI and
//! the browser.
//!
//! 1. **Condition**: the input points (a mesh is surface-sampled first, [`input_points`]) are
//!    mapped into the model frame by their bounding box; the vertex budget is the caller's or
//!    [`crate::pipeline::budget::DEFAULT_RULE`]'s; latent RoPE positions come from
//!    [`crate::model::condition::inference_positions`].
//! 2. **Sample**: seeded Gaussian noise integrated by the Euler sampler with the DiT.
//! 3. **Decode**: latents are de-normalised with the VAE manifest's mean/std and decoded.
//! 4. **Extract**: faces from the decoded vertices and edges ([`crate::extract`]: the manifold
//!    extraction by default, Algorithm 1 on request). For Algorithm 1 on a wgpu device the
//!    spacetime threshold runs there (`threshold_gpu`) and only the edge bits are read back;
//!    otherwise the embeddings are read back and thresholded on the host.
//! 5. **Fit**: the vertices are moved onto the input points' surface ([`crate::surface::fit`]);
//!    with the manifold extraction the surface is completed between them
//!    ([`crate::surface::complete`], fitted and completed again twice) and the holes left where
//!    the input goes on are closed ([`crate::surface::close`], which may add vertices beyond
//!    the budget); then the mesh goes back to the input's frame.

use burn::tensor::{Device, Int, Tensor, TensorData};
use glam::Vec3;
use serde::{Deserialize, Serialize};
use web_time::{Duration, Instant};

use crate::Mesh;
use crate::eval::metrics::chamfer_hausdorff;
use crate::extract::{
    DecodedEdges, DecodedVertices, ExtractMethod, ExtractOptions, ExtractReport,
    extract_from_decoded,
};
use crate::geometry::normalize::Normalization;
use crate::geometry::orient::orient_outward;
use crate::geometry::sample::{sample_surface, subsample_points};
use crate::geometry::snap::snap_mesh;
use crate::geometry::topology::{TopologyReport, boundary_loops};
use crate::model::condition::{context_points, inference_positions, vertex_condition};
use crate::model::dit::{Condition, Dit, DitConfig};
use crate::model::sampler::{SampleError, Solver, normal_noise, sample};
use crate::model::schedule::ScheduleMode;
use crate::model::{MeshVae, Trace, VaeConfig};
use crate::parallel::map_in_parallel;
use crate::pipeline::budget::{BudgetRule, DEFAULT_RULE, ShapeFeatures, shape_features};
use crate::rng::Rng;
use crate::surface::close::{CloseOptions, CloseReport, close_holes};
use crate::surface::complete::{CompleteOptions, CompleteReport, complete_surface, seed_uncovered};
use crate::surface::fit::{FitOptions, FitReport, fit_to_points};
use crate::surface::input::InputPoints;
use crate::surface::sharpen::{PointPlanes, SharpenOptions, SharpenReport, sharpen_judged};

/// Points drawn from a mesh's surface (or kept from a point cloud) to condition on.
pub const CONDITION_POINTS: usize = 4096;

/// Fewest input points accepted: fewer say too little about a surface to place vertices on
/// (and the fitting takes 8 nearest points around each vertex).
pub const MIN_POINTS: usize = 16;

/// Faces the full pipeline makes per budgeted vertex, asked for the ground truth's face count
/// (median over the validation split, 1.64 with the 64-wide VAE, whose mask keeps more of a
/// budget's vertex slots than the 32-wide one's did at 1.25; `meshflow eval generate --split
/// val --budget ground-truth-faces`): how a face count asked for becomes a vertex budget.
pub const FACES_PER_VERTEX: f32 = 1.64;

/// Fewest vertices a face count may ask for.
pub const MIN_BUDGET: usize = 8;

/// Why a generation failed.
#[derive(Debug, thiserror::Error)]
pub enum GenerateError {
    #[error("the input has no points")]
    NoPoints,
    #[error("the input has a non-finite coordinate (point {0})")]
    NonFinite(usize),
    #[error("all input points coincide; there is no shape to mesh")]
    Degenerate,
    #[error("the input has {got} points; at least {min} are needed to place a surface")]
    TooFewPoints { got: usize, min: usize },
    #[error("{asked} faces is outside what the model can make: {min}..={max}")]
    Faces {
        asked: usize,
        min: usize,
        max: usize,
    },
    #[error("ask for vertices or for faces, not both")]
    VerticesAndFaces,
    #[error("vertex budget {asked} is outside 1..={max} (the VAE's vertex count)")]
    Budget { asked: usize, max: usize },
    #[error(transparent)]
    Sampling(#[from] SampleError),
    #[error(transparent)]
    Surface(#[from] crate::geometry::sample::SampleError),
    #[error(transparent)]
    Extract(#[from] crate::extract::ExtractError),
    #[error("the VAE makes {} latents of {} floats but the DiT takes {} of {}", vae.0, vae.1, dit.0, dit.1)]
    Mismatch {
        vae: (usize, usize),
        dit: (usize, usize),
    },
    #[error("reading back from the device failed: {0}")]
    Readback(String),
    #[error("samples must be 1..={MAX_SAMPLES}, got {0}")]
    Samples(usize),
}

/// Most candidates [`GenerateOptions::samples`] may ask for (each costs a whole generation).
pub const MAX_SAMPLES: usize = 16;

/// [`GenerateError::Samples`] unless `samples` is in `1..=MAX_SAMPLES`.
pub fn check_samples(samples: usize) -> Result<(), GenerateError> {
    if (1..=MAX_SAMPLES).contains(&samples) {
        Ok(())
    } else {
        Err(GenerateError::Samples(samples))
    }
}

/// What the caller chooses (missing JSON fields take the defaults).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GenerateOptions {
    /// Vertices to ask for; `None` uses `faces`, or else the default rule on the input's
    /// shape.
    pub vertices: Option<usize>,
    /// Faces to ask for, turned into a vertex budget by [`FACES_PER_VERTEX`]; the result
    /// comes near it, not exactly on it (the model decides the connectivity).
    pub faces: Option<usize>,
    /// Sampler steps, each a [`Self::solver`] step. The paper's default is 28 Euler steps;
    /// here 4 midpoint steps (8 DiT evaluations), since one more candidate (`samples`) buys
    /// far more than more steps for the same time
    /// (docs/experiments/2026-11-26-candidates-and-steps.md), and at about the cost of 7 Euler
    /// steps the midpoint rule lands closer to the input (validation CD x100 4.52 / 4.56 at two
    /// seeds against 4.74 / 4.74; docs/experiments/2026-11-27-second-order-sampling.md).
    pub steps: usize,
    pub seed: u64,
    /// Candidates drawn per input, each from its own noise; the one kept lies closest to the
    /// input points, each hole counting against it ([`keep_best`]). 1 draws one (candidate `j`
    /// of input `k` is seeded by [`candidate_seed`]`(seed + k, j)`, so the first is the
    /// one-sample mesh, and an input's candidates depend neither on the rest of its batch nor
    /// on the candidates of the next seed). Default 12: the holes target of issue 15 needs
    /// about that many (8 leave 1.5 holes a mesh on the test split, 12 leave 1.3).
    pub samples: usize,
    pub schedule: ScheduleMode,
    /// How each step integrates the flow: Euler (one DiT evaluation a step, as the paper) or
    /// a second-order solver (two); midpoint by default.
    pub solver: Solver,
    pub extract: ExtractOptions,
    /// Fitting the extracted vertices to the input points (`iterations: 0` turns it off).
    pub fit: FitOptions,
    /// Completing the manifold extraction's faces with triangles on the input surface
    /// (ignored with Algorithm 1).
    pub complete: CompleteOptions,
    /// Closing the holes left after completion where the input goes on
    /// ([`crate::surface::close`]; with completion only, so never with Algorithm 1).
    pub close: CloseOptions,
    /// Sharpening the surface against the input points' planes, last
    /// ([`crate::surface::sharpen`]; after the manifold extraction only).
    pub sharpen: SharpenOptions,
}

impl Default for GenerateOptions {
    fn default() -> Self {
        Self {
            vertices: None,
            faces: None,
            steps: 4,
            seed: 0,
            samples: 12,
            schedule: ScheduleMode::ToZero,
            solver: Solver::Midpoint,
            extract: ExtractOptions::default(),
            fit: FitOptions::default(),
            complete: CompleteOptions::default(),
            close: CloseOptions::default(),
            sharpen: SharpenOptions::default(),
        }
    }
}

/// Wall time of each stage, in seconds.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StageTimes {
    /// Normalisation, budget, RoPE positions.
    pub condition_s: f64,
    pub sample_s: f64,
    pub decode_s: f64,
    pub extract_s: f64,
    /// Fitting to the input points, completing the surface, closing its holes and
    /// sharpening it.
    pub fit_s: f64,
}

impl StageTimes {
    /// The times of two runs of one batch that ran at the same time: the conditioning, done
    /// per input, adds up; every other stage lasts as long as the longer run's.
    pub fn beside(&self, other: &StageTimes) -> StageTimes {
        StageTimes {
            condition_s: self.condition_s + other.condition_s,
            sample_s: self.sample_s.max(other.sample_s),
            decode_s: self.decode_s.max(other.decode_s),
            extract_s: self.extract_s.max(other.extract_s),
            fit_s: self.fit_s.max(other.fit_s),
        }
    }
}

/// The meshes of runs of one batch that ran at the same time, in order, each with the runs'
/// stage times together ([`StageTimes::beside`]); the first run that failed, failed.
#[cfg(any(not(target_arch = "wasm32"), feature = "threads"))]
pub(crate) fn runs_side_by_side(
    outs: Vec<Result<Vec<Generated>, GenerateError>>,
) -> Result<Vec<Generated>, GenerateError> {
    let mut all = Vec::new();
    let mut times = StageTimes::default();
    for out in outs {
        let out = out?;
        if let Some(g) = out.first() {
            times = times.beside(&g.times);
        }
        all.extend(out);
    }
    for g in &mut all {
        g.times = times.clone();
    }
    Ok(all)
}

/// One generated mesh, in the input's frame.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Generated {
    pub mesh: Mesh,
    pub vertex_budget: usize,
    pub features: ShapeFeatures,
    pub extract: ExtractReport,
    pub fit: FitReport,
    pub complete: CompleteReport,
    pub close: CloseReport,
    pub sharpen: SharpenReport,
    pub topology: TopologyReport,
    /// Its distance from the input as [`keep_best`] measured it, when it was measured.
    pub input_score: Option<f64>,
    /// Stage times of the whole batch this mesh was generated in.
    pub times: StageTimes,
}

/// The points to condition on: a mesh's surface samples, or a point cloud's own points
/// (subsampled to [`CONDITION_POINTS`] when larger). A mesh whose faces have no area counts
/// as a point cloud of its vertices.
pub fn input_points(input: &Mesh, seed: u64) -> Result<Vec<Vec3>, GenerateError> {
    if !input.faces.is_empty() {
        match sample_surface(input, CONDITION_POINTS, seed) {
            Ok(s) => return Ok(s.points),
            Err(crate::geometry::sample::SampleError::ZeroArea { .. }) => {}
            Err(e) => return Err(e.into()),
        }
    }
    let points = &input.positions;
    if points.len() > CONDITION_POINTS {
        Ok(subsample_points(points, CONDITION_POINTS, seed))
    } else {
        Ok(points.clone())
    }
}

/// Maps `points` into the model frame; returns them with the transform back.
pub fn to_model_frame(points: &[Vec3]) -> Result<(Vec<Vec3>, Normalization), GenerateError> {
    if points.is_empty() {
        return Err(GenerateError::NoPoints);
    }
    if let Some(i) = points.iter().position(|p| !p.is_finite()) {
        return Err(GenerateError::NonFinite(i));
    }
    let aabb = crate::Aabb::of(points).ok_or(GenerateError::NoPoints)?;
    if aabb.max_extent() <= f32::EPSILON * aabb.center().abs().max_element().max(1.0) {
        return Err(GenerateError::Degenerate);
    }
    if points.len() < MIN_POINTS {
        return Err(GenerateError::TooFewPoints {
            got: points.len(),
            min: MIN_POINTS,
        });
    }
    let norm = Normalization::to_model_frame(aabb);
    Ok((
        points.iter().map(|&p| norm.apply(p)).collect(),
        norm.inverse(),
    ))
}

/// A loaded VAE and DiT, ready to generate.
pub struct Generator<'a> {
    pub vae: &'a MeshVae,
    pub vae_config: &'a VaeConfig,
    /// Per latent channel, from the VAE manifest: the DiT samples normalised latents.
    pub latent_mean: &'a [f32],
    pub latent_std: &'a [f32],
    pub dit: &'a Dit,
    pub dit_config: &'a DitConfig,
    pub budget_rule: BudgetRule,
    pub device: &'a Device,
}

#[derive(Clone)]
struct Conditioned {
    to_input: Normalization,
    /// The input in the model frame, where the token positions are drawn.
    model_points: Vec<Vec3>,
    /// The same points as fitting, completion and hole closing search them (built once for
    /// all candidates).
    model_input: InputPoints,
    budget: usize,
    features: ShapeFeatures,
    /// Time spent conditioning this input (zero for a candidate that shares an earlier
    /// one's), so each batch's stage time counts its own inputs.
    took: Duration,
}

/// A batch after conditioning: the sampler's inputs, and what extraction needs afterwards.
pub struct Prepared {
    conditioned: Vec<Conditioned>,
    /// Vertex slots per row of the decoded outputs (N, or the batch's length bucket).
    pub slots: usize,
    /// `[B, L, D]` seeded noise at t = 1 (row `k` from `seed + k`).
    pub noise: Tensor<3>,
    /// `[B, 1]` vertex-count conditions.
    pub cond: Tensor<2>,
    /// Token positions (and input points, for a DiT that reads them).
    pub condition: Condition,
    pub times: StageTimes,
}

/// The decoder's outputs on the device, as [`Generator::decode`] leaves them for readback.
pub struct DecodedDevice {
    /// `[B, N, 1]`, `[B, N, 3]`, `[B, N, 3]`.
    pub mask_logits: Tensor<3>,
    pub positions: Tensor<3>,
    pub normals: Tensor<3>,
    pub edges: DeviceEdges,
}

/// The edges as they leave the device.
// One value per generated batch, moved once: boxing the larger variant would buy nothing.
#[allow(clippy::large_enum_variant)]
pub enum DeviceEdges {
    /// `[B, N, E]` edge embeddings, thresholded on the host (the CPU backend, or when the
    /// non-manifold filter needs the margins).
    Embeddings(Tensor<3>),
    /// `[B, N, ceil(N / 32)]` u32 edge bits from the GPU threshold.
    Bits(Tensor<3, Int>),
    /// A VAE with a pair head ([`crate::model::VaeConfig::pair_head`]): `[B, N, E]` edge
    /// embeddings and `[B, N, W]` vertex features, refined into pair distances once the mask
    /// is on the host ([`kept_slots`], [`MeshVae::pair_corrections`]).
    PairHead {
        embeddings: Tensor<3>,
        features: Tensor<3>,
    },
}

/// The decoder's outputs read back to the host, row-major `[B, N, C]` each.
pub struct DecodedHost {
    pub mask_logits: Vec<f32>,
    pub positions: Vec<f32>,
    pub normals: Vec<f32>,
    pub edges: HostEdges,
}

/// [`DeviceEdges`] read back.
pub enum HostEdges {
    Embeddings(Vec<f32>),
    Bits(Vec<u32>),
    /// `[B, N, N]` pair distances refined by the pair head.
    Distances(Vec<f32>),
}

/// The seed of candidate `j` of an input seeded by `seed`: `seed` itself for the first, so that
/// one sample is the first candidate, and one derived from both for the others. Until
/// 2026-12-07 candidate `j` took `seed + j`, so neighbouring seeds shared 11 of their 12
/// candidates: `meshflow generate --seed 2` to `--seed 9` gave the box the same mesh.
pub fn candidate_seed(seed: u64, j: usize) -> u64 {
    if j == 0 {
        seed
    } else {
        Rng::derived(seed, j as u64)
    }
}

/// The slots of each of the `rows` rows of `[rows, n]` mask logits that the mask keeps (logit
/// > 0): the vertices a pair head picks its candidates among.
pub fn kept_slots(mask_logits: &[f32], n: usize) -> Vec<Vec<u32>> {
    mask_logits
        .chunks_exact(n.max(1))
        .map(crate::extract::kept_vertices)
        .collect()
}

impl Generator<'_> {
    /// Generates one mesh per input point set (input frame, e.g. from [`input_points`]), in
    /// one batch per length bucket (one batch without length buckets): every input gets the
    /// same steps and options, and its own seeded noise (`seed + index`), so its mesh does not
    /// depend on the rest of the batch. `on_step(step, steps)` runs after every sampler step
    /// (of each bucket's batch); returning false cancels. Reads back synchronously (native);
    /// the browser drives the same stages ([`Self::prepare`],
    /// [`step`](crate::model::sampler::step), [`Self::decode`],
    /// [`Self::extract`]) with asynchronous readback.
    pub fn generate(
        &self,
        inputs: &[Vec<Vec3>],
        opts: &GenerateOptions,
        on_step: &mut dyn FnMut(usize, usize) -> bool,
    ) -> Result<Vec<Generated>, GenerateError> {
        if inputs.is_empty() {
            return Ok(Vec::new());
        }
        check_samples(opts.samples)?;
        self.check_run(opts)?;
        if opts.samples > 1 {
            // Every candidate is an input of its own: input k's candidates sit at k, k + n, ...
            let n = inputs.len();
            // Candidates are drawn and chosen unsharpened; only the kept one is sharpened.
            let mut one = GenerateOptions {
                samples: 1,
                ..opts.clone()
            };
            one.sharpen.enabled = false;
            let expanded: Vec<Vec<Vec3>> = (0..opts.samples)
                .flat_map(|_| inputs.iter().cloned())
                .collect();
            let seeds: Vec<u64> = (0..opts.samples)
                .flat_map(|j| (0..n).map(move |k| candidate_seed(opts.seed + k as u64, j)))
                .collect();
            let mut all: Vec<Option<Generated>> = self
                .generate_seeded(&expanded, &seeds, &one, on_step)?
                .into_iter()
                .map(Some)
                .collect();
            let candidates: Vec<Vec<Generated>> = (0..n)
                .map(|k| {
                    (0..opts.samples)
                        .filter_map(|j| all[k + j * n].take())
                        .collect()
                })
                .collect();
            return Ok(keep_sharpened_all(candidates, inputs, opts));
        }
        let seeds: Vec<u64> = (0..inputs.len()).map(|k| opts.seed + k as u64).collect();
        self.generate_seeded(inputs, &seeds, opts, on_step)
    }

    /// [`Self::generate`] with one candidate (`opts.samples` is not read), input `k` seeded by
    /// `seeds[k]`.
    fn generate_seeded(
        &self,
        inputs: &[Vec<Vec3>],
        seeds: &[u64],
        opts: &GenerateOptions,
        on_step: &mut dyn FnMut(usize, usize) -> bool,
    ) -> Result<Vec<Generated>, GenerateError> {
        let conditioned = self.condition_all(inputs, opts)?;
        let slots: Vec<usize> = conditioned
            .iter()
            .map(|c| self.vae_config.slots_for(c.budget))
            .collect();
        let mut lengths = slots.clone();
        lengths.sort_unstable();
        lengths.dedup();
        if lengths.len() == 1 {
            let out = self.generate_batch(conditioned, seeds, opts, on_step)?;
            return Ok(keep_sharpened_all(
                out.into_iter().map(|g| vec![g]).collect(),
                inputs,
                opts,
            ));
        }
        let mut out: Vec<Option<Generated>> = (0..inputs.len()).map(|_| None).collect();
        for len in lengths {
            let members: Vec<usize> = (0..inputs.len()).filter(|&k| slots[k] == len).collect();
            let group: Vec<Conditioned> = members.iter().map(|&k| conditioned[k].clone()).collect();
            let group_seeds: Vec<u64> = members.iter().map(|&k| seeds[k]).collect();
            let done = self.generate_batch(group, &group_seeds, opts, on_step)?;
            for (k, g) in members.into_iter().zip(done) {
                out[k] = Some(g);
            }
        }
        let out = out
            .into_iter()
            .map(|g| vec![g.expect("every input is in one group")])
            .collect();
        Ok(keep_sharpened_all(out, inputs, opts))
    }

    /// Stage 2: the latents of a prepared batch, read back (which ends the stage on
    /// asynchronous backends). `on_step(step, steps)` as in [`Self::generate`].
    pub fn sample(
        &self,
        prepared: &Prepared,
        opts: &GenerateOptions,
        on_step: &mut dyn FnMut(usize, usize) -> bool,
    ) -> Result<Tensor<3>, GenerateError> {
        let latents = sample(
            self.dit,
            prepared.noise.clone(),
            prepared.cond.clone(),
            &prepared.condition,
            opts.steps,
            opts.schedule,
            opts.solver,
            &mut |i, n, _| on_step(i, n),
        )?;
        Ok(Tensor::<3>::from_data(read(latents)?, self.device))
    }

    /// [`Self::generate`] for conditioned inputs that share one length, input `k` seeded by
    /// `seeds[k]`: on the CPU, in one run per thread at once (a row does not depend on the
    /// rest of its batch, `tests/candidate_split.rs`, so the meshes are the one batch's). Two
    /// runs of 6 candidates on one thread each beat one batch of 12 on two: the model's
    /// element-wise work and attention, which Burn's CPU backend runs on one thread, then run
    /// on both (docs/experiments/2026-12-04-wasm-threads-build.md).
    #[cfg(any(not(target_arch = "wasm32"), feature = "threads"))]
    fn generate_batch(
        &self,
        conditioned: Vec<Conditioned>,
        seeds: &[u64],
        opts: &GenerateOptions,
        on_step: &mut dyn FnMut(usize, usize) -> bool,
    ) -> Result<Vec<Generated>, GenerateError> {
        use std::sync::atomic::{AtomicBool, Ordering};
        let runs = if crate::device::is_cpu(self.device) {
            crate::parallel::threads().min(conditioned.len())
        } else {
            1
        };
        if runs <= 1 {
            return self.generate_run(conditioned, seeds, opts, on_step);
        }
        // The first run reports progress; a cancel there stops the others at their next step.
        let cancelled = AtomicBool::new(false);
        let items: Vec<(Conditioned, u64)> = conditioned.into_iter().zip(seeds.to_vec()).collect();
        let outs = crate::parallel::in_parts(
            items,
            runs,
            |run| {
                let (c, s): (Vec<Conditioned>, Vec<u64>) = run.into_iter().unzip();
                self.generate_run(c, &s, opts, &mut |i, n| {
                    let go = !cancelled.load(Ordering::Relaxed) && on_step(i, n);
                    if !go {
                        cancelled.store(true, Ordering::Relaxed);
                    }
                    go
                })
            },
            |run| {
                let (c, s): (Vec<Conditioned>, Vec<u64>) = run.into_iter().unzip();
                self.generate_run(c, &s, opts, &mut |_, _| !cancelled.load(Ordering::Relaxed))
            },
        );
        runs_side_by_side(outs)
    }

    /// [`Self::generate`] for conditioned inputs that share one length (no threads to split
    /// them over in this module).
    #[cfg(all(target_arch = "wasm32", not(feature = "threads")))]
    fn generate_batch(
        &self,
        conditioned: Vec<Conditioned>,
        seeds: &[u64],
        opts: &GenerateOptions,
        on_step: &mut dyn FnMut(usize, usize) -> bool,
    ) -> Result<Vec<Generated>, GenerateError> {
        self.generate_run(conditioned, seeds, opts, on_step)
    }

    /// [`Self::generate_batch`] as one batch on this thread (the model's matrix products still
    /// use every thread).
    fn generate_run(
        &self,
        conditioned: Vec<Conditioned>,
        seeds: &[u64],
        opts: &GenerateOptions,
        on_step: &mut dyn FnMut(usize, usize) -> bool,
    ) -> Result<Vec<Generated>, GenerateError> {
        let mut prepared = self.prepare_conditioned(conditioned, seeds)?;
        let started = Instant::now();
        let latents = self.sample(&prepared, opts, on_step)?;
        prepared.times.sample_s = started.elapsed().as_secs_f64();
        self.decode_and_extract(prepared, latents, opts)
    }

    /// Stages 3 to 5 of a prepared batch sampled to `latents`, read back synchronously (native
    /// backends and the CPU modules in wasm): decoded, extracted and fitted.
    pub fn decode_and_extract(
        &self,
        mut prepared: Prepared,
        latents: Tensor<3>,
        opts: &GenerateOptions,
    ) -> Result<Vec<Generated>, GenerateError> {
        let started = Instant::now();
        let out = self.decode(latents, &opts.extract);
        let mask_logits = read_vec(out.mask_logits)?;
        let edges = match out.edges {
            DeviceEdges::Embeddings(t) => HostEdges::Embeddings(read_vec(t)?),
            DeviceEdges::Bits(t) => HostEdges::Bits(read_bits(t.try_into_data())?),
            DeviceEdges::PairHead {
                embeddings,
                features,
            } => {
                let kept = kept_slots(&mask_logits, prepared.slots);
                HostEdges::Distances(
                    self.vae
                        .edge_distances(embeddings, features, &kept)
                        .map_err(GenerateError::Readback)?,
                )
            }
        };
        let host = DecodedHost {
            mask_logits,
            positions: read_vec(out.positions)?,
            normals: read_vec(out.normals)?,
            edges,
        };
        prepared.times.decode_s = started.elapsed().as_secs_f64();
        self.extract(prepared, &host, opts)
    }

    /// Stage 1: checks the models fit together, conditions every input (model frame, budget,
    /// RoPE positions) and draws the noise (input `k` seeded by `seed + k`). No input at all
    /// is [`GenerateError::NoPoints`]. With length buckets the batch takes the bucket of its
    /// largest budget; [`Self::generate`] splits batches by bucket first. For the
    /// `opts.samples` candidates of one input that [`Self::generate`] draws, use
    /// [`Self::prepare_runs`] and keep one with [`keep_sharpened`] after [`Self::extract`].
    pub fn prepare(
        &self,
        inputs: &[Vec<Vec3>],
        opts: &GenerateOptions,
    ) -> Result<Prepared, GenerateError> {
        check_samples(opts.samples)?;
        self.check_run(opts)?;
        let seeds: Vec<u64> = (0..inputs.len()).map(|k| opts.seed + k as u64).collect();
        let conditioned = self.condition_all(inputs, opts)?;
        self.prepare_conditioned(conditioned, &seeds)
    }

    /// [`Self::prepare`] for the candidates of one input drawn in runs, run `(first, count)` a
    /// batch of its own whose row `k` is candidate `first + k`, seeded by
    /// [`candidate_seed`]`(opts.seed, first + k)` as in [`Self::generate`]: the input is
    /// conditioned once for every run, and the runs are prepared side by side where there are
    /// threads.
    pub fn prepare_runs(
        &self,
        points: &[Vec3],
        opts: &GenerateOptions,
        runs: &[(usize, usize)],
    ) -> Result<Vec<Prepared>, GenerateError> {
        check_samples(opts.samples)?;
        self.check_run(opts)?;
        let conditioned = self.condition(points, opts)?;
        let prepared = map_in_parallel(runs.to_vec(), |r, (first, count)| {
            // The conditioning's time counts once, in the first row of the first run.
            let rows: Vec<Conditioned> = (0..count)
                .map(|k| Conditioned {
                    took: if r == 0 && k == 0 {
                        conditioned.took
                    } else {
                        Duration::ZERO
                    },
                    ..conditioned.clone()
                })
                .collect();
            let seeds: Vec<u64> = (0..count)
                .map(|k| candidate_seed(opts.seed, first + k))
                .collect();
            self.prepare_conditioned(rows, &seeds)
        });
        prepared.into_iter().collect()
    }

    /// The checks that need no input: the models fit together and there is a step to take.
    fn check_run(&self, opts: &GenerateOptions) -> Result<(), GenerateError> {
        let (vae, dit) = (self.vae_config, self.dit_config);
        let (l, d) = (vae.num_latents, vae.latent_dim);
        if (l, d) != (dit.num_latents, dit.latent_dim) {
            return Err(GenerateError::Mismatch {
                vae: (l, d),
                dit: (dit.num_latents, dit.latent_dim),
            });
        }
        if opts.steps == 0 {
            return Err(SampleError::NoSteps.into());
        }
        Ok(())
    }

    /// [`Self::prepare`] for conditioned inputs (after [`Self::check_run`]), input `k` seeded
    /// by `seeds[k]`; the stage's time includes their conditioning.
    fn prepare_conditioned(
        &self,
        conditioned: Vec<Conditioned>,
        seeds: &[u64],
    ) -> Result<Prepared, GenerateError> {
        let started = Instant::now();
        let (vae, dit) = (self.vae_config, self.dit_config);
        let d = vae.latent_dim;
        if conditioned.is_empty() {
            return Err(GenerateError::NoPoints);
        }
        let b = conditioned.len();
        let conditioned_in: Duration = conditioned.iter().map(|c| c.took).sum();
        let slots = conditioned
            .iter()
            .map(|c| vae.slots_for(c.budget))
            .max()
            .unwrap_or(vae.num_vertices);
        let l_used = slots / vae.merge_ratio();
        let positions: Vec<[f32; 3]> = conditioned
            .iter()
            .enumerate()
            .flat_map(|(k, c)| {
                inference_positions(
                    &c.model_points,
                    c.budget,
                    l_used,
                    vae.merge_ratio(),
                    seeds[k],
                )
            })
            .collect();
        let cond: Vec<f32> = conditioned
            .iter()
            .map(|c| vertex_condition(c.budget, dit.count_scale()))
            .collect();
        // Drawn from a seed of their own (`seed ^ 0x901`): the token positions and the noise
        // draw from `seed` itself.
        let points: Vec<Vec<Vec3>> = conditioned
            .iter()
            .zip(seeds)
            .map(|(c, &seed)| context_points(&c.model_points, dit.point_tokens, seed ^ 0x901))
            .collect();
        let mut condition = Condition::new(dit, &positions, &points, b, self.device);
        self.dit.cache_points(&mut condition);
        let noise: Vec<Tensor<3>> = (0..b)
            .map(|k| normal_noise(&mut Rng::new(seeds[k]), [1, l_used, d], self.device))
            .collect();
        Ok(Prepared {
            conditioned,
            slots,
            noise: Tensor::cat(noise, 0),
            cond: Tensor::from_data(TensorData::new(cond, [b, 1]), self.device),
            condition,
            times: StageTimes {
                condition_s: (conditioned_in + started.elapsed()).as_secs_f64(),
                ..Default::default()
            },
        })
    }

    /// Stage 3: de-normalises sampled latents with the VAE manifest's mean/std and decodes.
    /// On a wgpu device the spacetime threshold (at the VAE's tau) runs there too, unless
    /// `extract` ranks faces by the embeddings' margins (the default manifold method does),
    /// which it does on the host, or the VAE has a pair head, whose candidates are chosen on
    /// the host.
    pub fn decode(&self, latents: Tensor<3>, extract: &ExtractOptions) -> DecodedDevice {
        let d = self.vae_config.latent_dim;
        let channel = |v: &[f32]| {
            Tensor::<1>::from_data(TensorData::new(v.to_vec(), [d]), self.device).reshape([1, 1, d])
        };
        let latents = latents * channel(self.latent_std) + channel(self.latent_mean);
        let out = self.vae.decode(latents, &mut Trace::default());
        let edges = if self.vae.decoder.pair_head.is_some() {
            DeviceEdges::PairHead {
                embeddings: out.edge_embeddings,
                features: out.features,
            }
        } else if extract.uses_margins() {
            DeviceEdges::Embeddings(out.edge_embeddings)
        } else {
            edges_on_device(
                out.edge_embeddings,
                out.mask_logits.clone(),
                self.vae_config.tau,
            )
        };
        DecodedDevice {
            mask_logits: out.mask_logits,
            positions: out.positions,
            normals: out.normals,
            edges,
        }
    }

    /// Stages 4 and 5: faces from each decoded row (`opts.extract`), its vertices fitted to
    /// its input points (`opts.fit`), mapped back to its input's frame.
    pub fn extract(
        &self,
        prepared: Prepared,
        host: &DecodedHost,
        opts: &GenerateOptions,
    ) -> Result<Vec<Generated>, GenerateError> {
        let started = Instant::now();
        let (n, e) = (prepared.slots, self.vae_config.edge_dim);
        let words = n.div_ceil(32);
        let opts = &GenerateOptions {
            extract: opts.extract.at_tau_of(self.vae_config),
            ..opts.clone()
        };
        // Each input's extraction and fitting are independent of the others', and a batch of
        // candidates (`opts.samples`) is where most of a generation's fitting time goes.
        let finished = map_in_parallel(prepared.conditioned.iter().collect(), |k, c| {
            let rows = k * n..(k + 1) * n;
            let pos = vec3s(&host.positions[rows.start * 3..rows.end * 3]);
            let nrm = vec3s(&host.normals[rows.start * 3..rows.end * 3]);
            let edges = match &host.edges {
                HostEdges::Embeddings(values) => DecodedEdges::Embeddings {
                    values: &values[rows.start * e..rows.end * e],
                    dim: e,
                },
                HostEdges::Bits(bits) => DecodedEdges::Bits {
                    words: &bits[rows.start * words..rows.end * words],
                    words_per_row: words,
                },
                HostEdges::Distances(values) => DecodedEdges::Distances {
                    values: &values[rows.start * n..rows.end * n],
                },
            };
            let decoded = DecodedVertices {
                mask_logits: &host.mask_logits[rows.clone()],
                positions: &pos,
                normals: &nrm,
                edges,
            };
            finish_one(&decoded, c, opts)
        });
        let wall_s = started.elapsed().as_secs_f64();
        let mut done = Vec::with_capacity(finished.len());
        let (mut extract_cpu_s, mut fit_cpu_s) = (0.0, 0.0);
        for f in finished {
            let f = f?;
            extract_cpu_s += f.extract_s;
            fit_cpu_s += f.fit_s;
            done.push(f);
        }
        // Stage times are wall-clock; with inputs finished side by side, the wall time is
        // split between the two stages in proportion to the time each input spent in them.
        let mut times = prepared.times;
        let cpu_s = extract_cpu_s + fit_cpu_s;
        times.fit_s = if cpu_s > 0.0 {
            wall_s * fit_cpu_s / cpu_s
        } else {
            0.0
        };
        times.extract_s = wall_s - times.fit_s;
        Ok(done
            .into_iter()
            .zip(prepared.conditioned)
            .map(|(f, c)| Generated {
                topology: TopologyReport::of(&f.mesh),
                mesh: f.mesh,
                vertex_budget: c.budget,
                features: c.features,
                extract: f.extract,
                fit: f.fit,
                complete: f.complete,
                close: f.close,
                sharpen: SharpenReport::default(),
                input_score: None,
                times: times.clone(),
            })
            .collect())
    }

    /// [`Self::condition`] for every input; an input equal to an earlier one (the candidates
    /// of one input) shares its conditioning instead of measuring it again.
    fn condition_all(
        &self,
        inputs: &[Vec<Vec3>],
        opts: &GenerateOptions,
    ) -> Result<Vec<Conditioned>, GenerateError> {
        let mut conditioned: Vec<Conditioned> = Vec::with_capacity(inputs.len());
        for (k, points) in inputs.iter().enumerate() {
            let c = match inputs[..k].iter().position(|earlier| earlier == points) {
                Some(j) => Conditioned {
                    took: Duration::ZERO,
                    ..conditioned[j].clone()
                },
                None => self.condition(points, opts)?,
            };
            conditioned.push(c);
        }
        Ok(conditioned)
    }

    /// The model frame, shape features and vertex budget of one input: a function of the
    /// input and `opts` alone, so every candidate and every seed gets the same budget.
    fn condition(
        &self,
        points: &[Vec3],
        opts: &GenerateOptions,
    ) -> Result<Conditioned, GenerateError> {
        let started = Instant::now();
        let vae = self.vae_config;
        let (model_points, to_input) = to_model_frame(points)?;
        let features = shape_features(&model_points, FEATURE_SEED);
        let max = vae.num_vertices;
        let budget = match (opts.vertices, opts.faces) {
            (Some(_), Some(_)) => return Err(GenerateError::VerticesAndFaces),
            (Some(v), None) if v == 0 || v > max => {
                return Err(GenerateError::Budget { asked: v, max });
            }
            (Some(v), None) => v,
            (None, Some(f)) => budget_for_faces(f, max)?,
            (None, None) => self.budget_rule.budget(&features, max),
        };
        Ok(Conditioned {
            to_input,
            model_input: InputPoints::new(&model_points),
            model_points,
            budget,
            features,
            took: started.elapsed(),
        })
    }
}

impl<'a> Generator<'a> {
    /// A generator with the shipped default budget rule.
    pub fn new(
        vae: &'a MeshVae,
        vae_config: &'a VaeConfig,
        latent_mean: &'a [f32],
        latent_std: &'a [f32],
        dit: &'a Dit,
        dit_config: &'a DitConfig,
        device: &'a Device,
    ) -> Self {
        Self {
            vae,
            vae_config,
            latent_mean,
            latent_std,
            dit,
            dit_config,
            budget_rule: DEFAULT_RULE,
            device,
        }
    }
}

impl<'a> Generator<'a> {
    /// A generator over shipped models and their manifests ([`crate::pipeline::shipped`]).
    pub fn from_shipped(
        vae: &'a MeshVae,
        vae_manifest: &'a crate::pipeline::shipped::VaeManifest,
        dit: &'a Dit,
        dit_manifest: &'a crate::pipeline::shipped::DitManifest,
        device: &'a Device,
    ) -> Self {
        Self::new(
            vae,
            &vae_manifest.model,
            &vae_manifest.latent_mean,
            &vae_manifest.latent_std,
            dit,
            &dit_manifest.model,
            device,
        )
    }
}

/// The vertex budget for `faces` faces ([`FACES_PER_VERTEX`]), or the range a model of `max`
/// vertices can make when it is outside.
pub fn budget_for_faces(faces: usize, max: usize) -> Result<usize, GenerateError> {
    let range = faces_range(max);
    if !range.contains(&faces) {
        return Err(GenerateError::Faces {
            asked: faces,
            min: *range.start(),
            max: *range.end(),
        });
    }
    Ok(((faces as f32 / FACES_PER_VERTEX).round() as usize).clamp(MIN_BUDGET, max))
}

/// The seed of the neighbourhoods [`shape_features`] samples. Fixed, so that the default
/// budget is a property of the input: with a seed per candidate, the candidates of one input
/// could get different budgets, even different length buckets.
const FEATURE_SEED: u64 = 0;

/// One input's mesh after [`Generator::extract`]'s stages, in its input's frame.
struct Finished {
    mesh: Mesh,
    extract: ExtractReport,
    fit: FitReport,
    complete: CompleteReport,
    close: CloseReport,
    /// Seconds spent extracting, and fitting (with completion and closing).
    extract_s: f64,
    fit_s: f64,
}

/// Whether stage 5 completes the surface: only after the manifold method.
fn completes(opts: &GenerateOptions) -> bool {
    opts.complete.enabled && opts.extract.method == ExtractMethod::Manifold
}

/// The extraction options stage 4 runs with for each candidate: `opts.extract` (already at
/// the VAE's tau, [`ExtractOptions::at_tau_of`]), adjusted for completion when it follows.
pub fn candidate_extraction(opts: &GenerateOptions) -> ExtractOptions {
    // Completion may use vertices the model gave no face, so they stay until then; and the
    // model's faces are chosen by their margins under completion's overlap test (completion
    // keeps them in that order, first).
    if completes(opts) {
        ExtractOptions {
            compact: false,
            overlap_tolerance: opts.complete.overlap_tolerance,
            ..opts.extract.clone()
        }
    } else {
        opts.extract.clone()
    }
}

/// Completion once more, without welding (the first completion welded the decoder's
/// near-duplicates; the vertices since are apart on purpose).
fn complete_again(mesh: &Mesh, c: &Conditioned, opts: &GenerateOptions) -> Mesh {
    let again = CompleteOptions {
        weld_ratio: 0.0,
        ..opts.complete
    };
    complete_surface(
        mesh,
        &c.model_input,
        &again,
        &opts.extract.manifold_options(),
    )
    .0
}

/// Refinement of a completed mesh: the completed faces now hold the fit's fold test, so
/// vertices the model's sparse faces held back can reach the surface, and the completed
/// faces compete with the candidates around the moved vertices.
fn refine_completion(mesh: &mut Mesh, c: &Conditioned, opts: &GenerateOptions) {
    for _ in 0..opts.complete.refine_passes {
        let refit = FitOptions {
            smoothing: opts.complete.refine_smoothing,
            ..opts.fit
        };
        fit_to_points(&mut mesh.positions, &mesh.faces, &c.model_input, &refit);
        *mesh = complete_again(mesh, c, opts);
    }
}

/// Extraction, fitting, completion and closing of one decoded row (stages 4 and 5).
fn finish_one(
    decoded: &DecodedVertices<'_>,
    c: &Conditioned,
    opts: &GenerateOptions,
) -> Result<Finished, GenerateError> {
    let started = Instant::now();
    let completing = completes(opts);
    let (mut mesh, report) = extract_from_decoded(decoded, &candidate_extraction(opts))?;
    let fitting = Instant::now();
    let fit = fit_to_points(&mut mesh.positions, &mesh.faces, &c.model_input, &opts.fit);
    let mut complete = CompleteReport::default();
    if completing {
        (mesh, complete) = complete_surface(
            &mesh,
            &c.model_input,
            &opts.complete,
            &opts.extract.manifold_options(),
        );
        refine_completion(&mut mesh, c, opts);
        // With `seed_gap` (off by default): where the model left out a part the input has (a
        // leg, a pole, the far side of a slab), vertices at the input points there, completed
        // and refined like the rest (docs/experiments/2026-12-07-seed-uncovered.md).
        complete.seeded = seed_uncovered(&mut mesh, &c.model_input, opts.complete.seed_gap);
        if complete.seeded > 0 {
            mesh = complete_again(&mesh, c, opts);
            refine_completion(&mut mesh, c, opts);
        }
    }
    let mut close = CloseReport::default();
    if completing {
        close = close_holes(&mut mesh, &c.model_input, &opts.close);
    }
    if completing && opts.extract.compact {
        mesh.remove_unreferenced_vertices();
    }
    // Extraction winds each piece the way the decoder's normals vote, and they can vote for
    // the inside (a closed L-bracket came back inside out); sharpening keeps the winding.
    if opts.extract.method == ExtractMethod::Manifold {
        orient_outward(&mut mesh);
    }
    let fit_s = fitting.elapsed().as_secs_f64();
    Ok(Finished {
        mesh: c.to_input.apply_mesh(&mesh),
        extract: report,
        fit,
        complete,
        close,
        extract_s: fitting.duration_since(started).as_secs_f64(),
        fit_s,
    })
}

/// Stage 6: the candidate a user would keep ([`keep_best`]), sharpened against its input
/// `points` ([`sharpen_kept`]); the input's planes are fitted once for both. With
/// [`SharpenOptions::candidates`] above 1, that many candidates, the nearest the input first,
/// are sharpened side by side and the one nearest the input afterwards is kept (sharpening
/// reorders them: a crumpled candidate that flattens onto the points overtakes one that
/// cannot). With one candidate and sharpening off, nothing is measured.
pub fn keep_sharpened(
    candidates: Vec<Generated>,
    points: &[Vec3],
    opts: &GenerateOptions,
) -> Generated {
    if candidates.len() == 1 && !sharpens(opts) {
        return candidates.into_iter().next().expect("one candidate");
    }
    let planes = PointPlanes::new(points, opts.sharpen.plane_neighbours);
    let keep = if sharpens(opts) {
        opts.sharpen.candidates.max(1)
    } else {
        1
    };
    let ranked = rank_by_input(candidates, points, &planes);
    let best: Vec<Generated> = ranked.into_iter().take(keep).collect();
    let sharpened = map_in_parallel(best, |_, g| sharpen_kept(g, points, &planes, opts));
    sharpened
        .into_iter()
        .reduce(|a, b| if b.input_score < a.input_score { b } else { a })
        .expect("at least one candidate")
}

/// The grids that the kept mesh is snapped to before sharpening ([`snap_mesh`], on the input
/// points' bounding box): the coarsest (a step of `2^-8` of the box's longest side, so at
/// most 0.2% of it off) that takes no face's area, down to `2^-12`. The browser's CPU path
/// and the CLI part where a coordinate lies within the few ulps they differ by of a cell's
/// boundary: the finer the grid, the more often (1 of 6 inputs at about `2^-12`).
pub const SHARPEN_GRID_BITS: (i32, i32) = (8, 12);

/// Whether [`sharpen_kept`] edits: sharpening on, after the manifold extraction only (its
/// edits keep a manifold mesh manifold).
fn sharpens(opts: &GenerateOptions) -> bool {
    opts.sharpen.enabled && opts.extract.method == ExtractMethod::Manifold
}

/// The kept mesh sharpened against its input `points` (input frame, with their `planes`;
/// [`crate::surface::sharpen`]). Only the kept candidate is sharpened, so the stage costs
/// one mesh's sharpening however many candidates were drawn; its time counts in `fit_s`. The
/// mesh of the last round of sharpening that is no farther from the input by [`keep_best`]'s
/// measure (times [`SharpenOptions::accept_ratio`]) replaces the kept one: where the model's
/// mesh was too far off for the edits (loose flaps, crumpled sheets, thin parts the collapses
/// would flatten), an earlier round or, when none passes, the mesh as it was stays
/// ([`SharpenReport::accepted`] and [`SharpenReport::rounds_kept`] say which), without the
/// vertices its flat faces do not need ([`SharpenReport::redundant_removed`]). Sharpening
/// starts from the kept mesh snapped to a grid ([`SHARPEN_GRID_BITS`]), so that the browser's
/// CPU path and the CLI, whose fitted positions differ by a few ulps, sharpen the same mesh.
/// The holes the kept round still has are closed once more (`close_sharpened`:
/// [`SharpenReport::holes_closed`] counts them).
pub fn sharpen_kept(
    mut g: Generated,
    points: &[Vec3],
    planes: &PointPlanes,
    opts: &GenerateOptions,
) -> Generated {
    if !sharpens(opts) {
        return g;
    }
    let started = Instant::now();
    let mut mesh = g.mesh.clone();
    // The greedy collapses after this would turn the few ulps by which the fitted positions
    // differ natively and inside WebAssembly into different meshes; from a grid of
    // 2^-SHARPEN_GRID_BITS of the input's size both start the same. Sharpening places
    // every vertex again, so the grid is not seen in its mesh.
    snap_mesh(&mut mesh, points, SHARPEN_GRID_BITS.0, SHARPEN_GRID_BITS.1);
    // The last round no farther from the input than the fitted mesh (times the ratio): later
    // rounds are flatter, and where one strays (a flap of the model's the points do not back
    // collapsed away) an earlier round may still be right. Measured on the snapped mesh, so
    // that the limit is the same bits everywhere too.
    let before = input_score(&mesh, g.topology.holes, points, planes);
    let limit = opts.sharpen.accept_ratio * before;
    // Sharpening keeps no round with more folded edges than the mesh it was given, which is
    // the snapped one: where the grid folded a near-flat pair, the fitted mesh's count holds.
    let folded_limit = g.topology.folded_edges;
    let mut last = None;
    let mut report = sharpen_judged(&mut mesh, planes, &opts.sharpen, |m| {
        let topology = TopologyReport::of(m);
        let score = input_score(m, topology.holes, points, planes);
        let ok = score <= limit && topology.folded_edges <= folded_limit;
        if ok || last.is_none() {
            last = Some((score, topology));
        }
        ok
    });
    report.input_distance_before = before;
    // The judge saw the kept round before the vertices it did not need went: its faces and
    // its distance to the input are the shipped mesh's again.
    if report.accepted && report.redundant_removed > 0 {
        let topology = TopologyReport::of(&mesh);
        last = Some((input_score(&mesh, topology.holes, points, planes), topology));
    }
    // The holes the sharpened mesh still has, closed where its flatter rim now lets a patch
    // lie on the input without folding.
    if report.accepted
        && let Some((_, topology)) = last.as_ref()
        && let Some(closed) = close_sharpened(&mesh, topology, points, &opts.close)
    {
        report.holes_closed = closed.holes_closed;
        let (m, t) = (closed.mesh, closed.topology);
        last = Some((input_score(&m, t.holes, points, planes), t));
        mesh = m;
    }
    if let Some((score, topology)) = last {
        report.input_distance_after = score;
        if report.accepted {
            g.mesh = mesh;
            // Sharpening reshapes open pieces enough that the side their bulk says is out
            // can turn (a piece of 36 of the 244 test meshes turned again here).
            orient_outward(&mut g.mesh);
            g.topology = topology;
            g.input_score = Some(score);
        }
    }
    g.sharpen = report;
    g.times.fit_s += started.elapsed().as_secs_f64();
    g
}

/// A sharpened mesh with some of its holes closed ([`close_sharpened`]).
struct ClosedSharpened {
    mesh: Mesh,
    topology: TopologyReport,
    holes_closed: usize,
}

/// The holes that the sharpened `mesh` (with its `topology`) still has, closed by
/// [`close_holes`] against the input `points` with the `close` options but without cutting
/// rim faces. Hole closing before sharpening refuses the patches that would fold onto a
/// crumpled rim; sharpening flattens some of those rims, and then a patch lies flat. No cuts:
/// on the meshes still crumpled after sharpening, cutting rim faces and closing the larger
/// loops capped across their folds (docs/experiments/2026-12-05-close-after-sharpening.md).
/// `None` when closing is off, nothing closes, or the result would have more non-manifold,
/// inconsistently wound, folded or degenerate edges or faces than `mesh`.
fn close_sharpened(
    mesh: &Mesh,
    topology: &TopologyReport,
    points: &[Vec3],
    close: &CloseOptions,
) -> Option<ClosedSharpened> {
    if !close.enabled || topology.holes == 0 {
        return None;
    }
    let mut closed = mesh.clone();
    let opts = CloseOptions {
        max_cut_faces: 0,
        ..*close
    };
    let report = close_holes(&mut closed, &InputPoints::new(points), &opts);
    let after = TopologyReport::of(&closed);
    let clean = after.holes < topology.holes
        && after.non_manifold_edges <= topology.non_manifold_edges
        && after.inconsistent_winding_edges <= topology.inconsistent_winding_edges
        && after.folded_edges <= topology.folded_edges
        && after.degenerate_faces <= topology.degenerate_faces;
    (report.holes_closed > 0 && clean).then_some(ClosedSharpened {
        mesh: closed,
        topology: after,
        holes_closed: report.holes_closed,
    })
}

/// [`keep_sharpened`] of each input's candidates, side by side.
fn keep_sharpened_all(
    candidates: Vec<Vec<Generated>>,
    inputs: &[Vec<Vec3>],
    opts: &GenerateOptions,
) -> Vec<Generated> {
    let pairs: Vec<(Vec<Generated>, &[Vec3])> = candidates
        .into_iter()
        .zip(inputs.iter().map(|p| p.as_slice()))
        .collect();
    map_in_parallel(pairs, |_, (c, points)| keep_sharpened(c, points, opts))
}

/// The candidate a user would keep ([`GenerateOptions::samples`]): the one nearest the input
/// `points` (in the candidates' frame, with their `planes`): the lowest Chamfer distance to
/// them, each loop of its rims ([`boundary_loops`]: a pinched rim is several) adding
/// [`HOLE_WEIGHT`] of it and the disagreement of its normals with the planes
/// [`NORMAL_WEIGHT`] times that, then the first; its score is kept in
/// [`Generated::input_score`]. Only the output and the input decide, never a ground truth.
/// Panics on no candidates.
pub fn keep_best(candidates: Vec<Generated>, points: &[Vec3], planes: &PointPlanes) -> Generated {
    rank_by_input(candidates, points, planes)
        .into_iter()
        .next()
        .expect("at least one candidate")
}

/// The candidates nearest the input first by [`keep_best`]'s measure (ties in their order),
/// each with its score in [`Generated::input_score`]; one candidate is not measured.
fn rank_by_input(
    mut candidates: Vec<Generated>,
    points: &[Vec3],
    planes: &PointPlanes,
) -> Vec<Generated> {
    // One candidate: nothing to choose, so no surface sampling.
    if candidates.len() <= 1 {
        return candidates;
    }
    let scores: Vec<f64> = map_in_parallel(candidates.iter().collect(), |_, g| {
        // The rims as the loops a walk cuts them into, one more at each pinch, rather than
        // the holes: a candidate whose rims pinch often is ragged, and counted by its holes it
        // was kept more often, with 18% more boundary edges on 80 validation meshes
        // (docs/experiments/2026-12-07-hole-count.md).
        input_score(&g.mesh, boundary_loops(&g.mesh.faces).len(), points, planes)
    });
    for (g, s) in candidates.iter_mut().zip(&scores) {
        g.input_score = Some(*s);
    }
    // A stable sort keeps the first of equal scores first, as the choice always did.
    candidates.sort_by(|a, b| a.input_score.unwrap().total_cmp(&b.input_score.unwrap()));
    candidates
}

/// How far a mesh is from the input `points` as [`keep_best`] and [`sharpen_kept`] judge it:
/// the Chamfer distance between its surface and the points, each of its `holes` adding
/// [`HOLE_WEIGHT`] of it (sharpening counts them as [`TopologyReport::holes`], the choice as
/// rim loops), and its disagreement with the input's `planes` (one minus
/// [`PointPlanes::normal_agreement`]) [`NORMAL_WEIGHT`] times that (infinite when it cannot
/// be sampled).
fn input_score(mesh: &Mesh, holes: usize, points: &[Vec3], planes: &PointPlanes) -> f64 {
    let Ok(s) = sample_surface(mesh, SELECTION_SAMPLES, 0) else {
        return f64::INFINITY;
    };
    let Ok(d) = chamfer_hausdorff(&s.points, points) else {
        return f64::INFINITY;
    };
    let disagreement = planes
        .normal_agreement(&s.points, &s.normals)
        .map_or(0.0, |a| 1.0 - a);
    d.chamfer * (1.0 + HOLE_WEIGHT * holes as f64) * (1.0 + NORMAL_WEIGHT * disagreement)
}

/// What a hole costs in [`keep_best`], as a fraction of the candidate's distance to the input.
/// The distance to the input ranks candidates almost exactly as the distance to the ground
/// truth does (correlation 0.99 within a mesh's candidates on the validation split), so it
/// leads; by distance alone 8 candidates keep 3.6 holes a mesh, by holes first 1.3 at 0.2
/// more CD x100; at 0.5, 1.4 holes and most of the distance's gain
/// (docs/experiments/2026-11-26-candidates-and-steps.md).
pub const HOLE_WEIGHT: f64 = 0.5;

/// What disagreeing with the input's planes costs in [`keep_best`] and in sharpening's
/// judge, per unit of mean (1 - |cos|) between the surface's normals and the planes of the
/// input points nearest it, as a fraction of the distance: a crumpled or bumpy candidate
/// loses to a flat one equally near the points
/// (docs/experiments/2026-12-02-normal-agreement.md).
pub const NORMAL_WEIGHT: f64 = 1.0;

/// Surface samples per candidate for [`keep_best`]'s distance to the input.
const SELECTION_SAMPLES: usize = 2048;

/// The face counts a model of `max` vertices can be asked for.
pub fn faces_range(max: usize) -> std::ops::RangeInclusive<usize> {
    let faces = |v: usize| (v as f32 * FACES_PER_VERTEX).round() as usize;
    faces(MIN_BUDGET)..=faces(max)
}

fn read(t: Tensor<3>) -> Result<TensorData, GenerateError> {
    t.try_into_data()
        .map_err(|e| GenerateError::Readback(e.to_string()))
}

pub(crate) fn read_vec(t: Tensor<3>) -> Result<Vec<f32>, GenerateError> {
    read(t)?
        .convert::<f32>()
        .try_into_vec::<f32>()
        .map_err(|e| GenerateError::Readback(e.to_string()))
}

/// The GPU threshold where the tensors live on a wgpu device, the embeddings otherwise.
#[cfg(feature = "wgpu")]
fn edges_on_device(embeddings: Tensor<3>, mask_logits: Tensor<3>, tau: f32) -> DeviceEdges {
    // Not on a wgpu device (or too large for one dispatch): the host thresholds instead, and
    // reports bad shapes with a typed error.
    match crate::extract::threshold_gpu::spacetime_edge_bits(embeddings.clone(), mask_logits, tau) {
        Ok(bits) => DeviceEdges::Bits(bits),
        Err(_) => DeviceEdges::Embeddings(embeddings),
    }
}

#[cfg(not(feature = "wgpu"))]
fn edges_on_device(embeddings: Tensor<3>, _mask_logits: Tensor<3>, _tau: f32) -> DeviceEdges {
    DeviceEdges::Embeddings(embeddings)
}

/// Edge bits from read-back data (u32, or whatever integer type the backend reports).
pub fn read_bits(
    data: Result<TensorData, impl std::fmt::Display>,
) -> Result<Vec<u32>, GenerateError> {
    data.map_err(|e| GenerateError::Readback(e.to_string()))?
        .convert::<u32>()
        .try_into_vec::<u32>()
        .map_err(|e| GenerateError::Readback(e.to_string()))
}

pub(crate) fn vec3s(flat: &[f32]) -> Vec<Vec3> {
    flat.chunks_exact(3).map(Vec3::from_slice).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::primitives::icosphere;

    /// A sphere with the faces around its first vertex taken out (a hole of 5 edges, about
    /// 0.6 of the radius across), and 4,096 points of the whole sphere.
    fn holed_sphere() -> (Mesh, TopologyReport, Vec<Vec3>) {
        let sphere = icosphere(2);
        let points = sample_surface(&sphere, 4096, 7).unwrap().points;
        let mut holed = sphere.clone();
        holed.faces.retain(|f| !f.contains(&0));
        let topology = TopologyReport::of(&holed);
        assert_eq!(topology.holes, 1);
        (holed, topology, points)
    }

    #[test]
    fn the_candidates_of_nearby_seeds_and_inputs_are_seeded_apart() {
        // Input k of a batch is seeded by seed + k, so the candidates of every (seed + k, j)
        // a batch or a seed sweep can reach must differ; the first is the seed itself.
        let mut seen = std::collections::HashSet::new();
        for seed in 0..32u64 {
            assert_eq!(candidate_seed(seed, 0), seed);
            for j in 1..16 {
                let s = candidate_seed(seed, j);
                assert!(s >= 32 && seen.insert(s), "seed {seed}, candidate {j}");
            }
        }
    }

    #[test]
    fn a_hole_where_the_points_go_on_is_closed_after_sharpening() {
        let (holed, topology, points) = holed_sphere();
        let closed =
            close_sharpened(&holed, &topology, &points, &CloseOptions::default()).expect("closed");
        assert_eq!((closed.topology.holes, closed.holes_closed), (0, 1));
        assert_eq!(closed.topology.non_manifold_edges, 0);
        assert_eq!(closed.topology.folded_edges, 0);
        assert_eq!(closed.mesh.faces.len(), holed.faces.len() + 5);
    }

    #[test]
    fn a_hole_the_points_do_not_cover_stays_open_and_closing_can_be_turned_off() {
        let (holed, topology, points) = holed_sphere();
        let hole_centre = holed.positions[0];
        // The input has the hole too, and wider than the gap allowed across it.
        let open: Vec<Vec3> = points
            .iter()
            .copied()
            .filter(|p| p.distance(hole_centre) > 0.5)
            .collect();
        let close = CloseOptions::default();
        assert!(close_sharpened(&holed, &topology, &open, &close).is_none());
        let off = CloseOptions {
            enabled: false,
            ..close
        };
        assert!(close_sharpened(&holed, &topology, &points, &off).is_none());
        let closed_sphere = icosphere(2);
        let whole = TopologyReport::of(&closed_sphere);
        assert!(close_sharpened(&closed_sphere, &whole, &points, &close).is_none());
    }
}
