//! DiT training by conditional flow matching on cached VAE latents.
//!
//! Each training mesh is encoded once with the shipped VAE (posterior mean), normalised by the
//! latent mean/std of the VAE's manifest, and stored with its latent tokens' RoPE positions
//! ([`crate::model::condition::latent_positions`]) and its vertex count. A step draws `t` from a
//! logit-normal (`sigmoid(N(0, 1))`), forms `x_t = (1 - t) x_0 + t eps` and regresses the
//! velocity `eps - x_0` with mean squared error (docs/design.md section 2).
//!
//! Conditioning augmentation ([`PositionAugment`], issue 15 item 3): inference gives the
//! tokens positions drawn from the user's points ([`crate::model::condition::inference_positions`]),
//! which real scans make noisy, uneven and partial. With it, a share of the training examples
//! get their positions the same way, from their own surface samples thinned, shifted by noise
//! and with a region cut away, so the model learns from what it will be given.

use std::collections::BTreeMap;
use std::ops::Range;
use std::path::Path;

use burn::optim::GradientsParams;
use burn::tensor::{Device, Tensor, TensorData};
use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::adamw::{AdamW, AdamWState};
use super::run::{Schedule, StepOutcome, Task, Trained, run_training};
use super::sub_batches::{gradients_in_parallel, sub_batches};
use super::{TrainError, TrainObserver, scalar};
use crate::Mesh;
use crate::data::degrade::{Degradation, degrade};
use crate::geometry::sample::{sample_surface, subsample_points};
use crate::model::condition::{
    context_points, inference_positions, latent_positions, vertex_condition,
};
use crate::model::dit::{Condition, Dit, DitConfig, is_image_path};
use crate::model::sampler::normal_noise;
use crate::model::tokens::build_tokens;
use crate::model::weights::{TensorMap, WeightsError};
use crate::model::{MeshVae, Trace, VaeConfig, load_module, seeded_init};
use crate::rng::Rng;
use crate::train::vae::{NonEdgeWeights, make_batch};

/// One cached training example.
#[derive(Clone, Debug, PartialEq)]
pub struct LatentExample {
    /// `L x latent_dim`, normalised; L is `num_latents`, or with length buckets the mesh's
    /// bucket.
    pub latents: Vec<f32>,
    /// RoPE voxel position of each latent token.
    pub positions: Vec<[f32; 3]>,
    pub vertex_count: usize,
    /// Vertices merged into one latent token (the VAE's `N / num_latents`).
    pub merge_ratio: usize,
    /// Surface samples of the mesh (model frame), which [`PositionAugment`] draws positions
    /// from; empty when the example has none.
    pub surface: Vec<Vec3>,
}

/// Surface samples kept per training mesh for [`PositionAugment`].
pub const SURFACE_SAMPLES: usize = 2048;

/// Encodes `meshes` (model frame, at most N vertices each; others are skipped) with `vae`
/// and normalises by `mean`/`std` per channel.
pub fn encode_latents(
    vae: &MeshVae,
    cfg: &VaeConfig,
    meshes: &[Mesh],
    mean: &[f32],
    std: &[f32],
    device: &Device,
) -> Vec<LatentExample> {
    let mut tokens: Vec<_> = meshes
        .iter()
        .enumerate()
        .filter_map(|(i, m)| {
            let t = build_tokens(m, &cfg.tokens_for(m.positions.len()), i as u64).ok()?;
            Some((t, i))
        })
        .collect();
    // One length per forward pass (length buckets); examples are sampled, so order is free.
    tokens.sort_by_key(|(t, _)| t.mask.len());
    let d = cfg.latent_dim;
    let mut out = Vec::with_capacity(tokens.len());
    let chunks = tokens
        .chunk_by(|(a, _), (b, _)| a.mask.len() == b.mask.len())
        .flat_map(|same| same.chunks(16));
    for chunk in chunks {
        let l = chunk[0].0.mask.len() / cfg.merge_ratio();
        let chunk_tokens: Vec<_> = chunk.iter().map(|(t, _)| t.clone()).collect();
        let batch = make_batch(&chunk_tokens, NonEdgeWeights::uniform(1.0), device);
        let z = vae.encode(batch.features, &mut Trace::default()).mean;
        let values = z
            .into_data()
            .convert::<f32>()
            .try_into_vec::<f32>()
            .expect("f32 latents");
        for (k, (t, mesh_index)) in chunk.iter().enumerate() {
            let latents = values[k * l * d..(k + 1) * l * d]
                .iter()
                .enumerate()
                .map(|(i, &v)| (v - mean[i % d]) / std[i % d].max(1e-6))
                .collect();
            let surface = sample_surface(&meshes[*mesh_index], SURFACE_SAMPLES, *mesh_index as u64)
                .map(|s| s.points)
                .unwrap_or_default();
            out.push(LatentExample {
                latents,
                positions: latent_positions(t, cfg.merge_ratio()),
                vertex_count: t.num_real,
                merge_ratio: cfg.merge_ratio(),
                surface,
            });
        }
    }
    out
}

/// Conditioning augmentation: how often and how badly a training example's token positions
/// are drawn from a degraded copy of its surface (see the module doc).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PositionAugment {
    /// Chance that an example's positions are drawn from its surface samples the way
    /// inference draws them; otherwise they are its own vertices' ([`latent_positions`]).
    pub probability: f64,
    /// Fewest surface samples kept (uneven density): the count is drawn uniformly between
    /// this and all [`SURFACE_SAMPLES`].
    pub min_points: usize,
    /// Largest noise: its standard deviation is drawn uniformly in `[0, max_noise]` (a fraction
    /// of the bounding box's longest side, as [`Degradation::noise`]).
    pub max_noise: f32,
    /// Chance that a region is missing.
    pub missing_probability: f64,
    /// Largest missing fraction, drawn uniformly in `[0, max_missing]` ([`Degradation::missing`]).
    pub max_missing: f32,
}

impl PositionAugment {
    /// Every chance and fraction in [0, 1], naming the first field that is not.
    pub fn validate(&self) -> Result<(), String> {
        let unit = [
            ("augment.probability", self.probability),
            ("augment.max_noise", f64::from(self.max_noise)),
            ("augment.missing_probability", self.missing_probability),
            ("augment.max_missing", f64::from(self.max_missing)),
        ];
        match unit.iter().find(|(_, v)| !(0.0..=1.0).contains(v)) {
            Some((name, v)) => Err(format!("{name} must be in [0, 1], got {v}")),
            None => Ok(()),
        }
    }

    /// Token positions for `example`, drawn with `rng`: its own, or from its degraded surface.
    pub fn positions(&self, example: &LatentExample, rng: &mut Rng) -> Vec<[f32; 3]> {
        if example.surface.is_empty() || rng.next_f64() >= self.probability {
            return example.positions.clone();
        }
        let all = example.surface.len();
        let fewest = self.min_points.clamp(1, all);
        let count = fewest + rng.below(all - fewest + 1);
        let points = subsample_points(&example.surface, count, rng.next_u64());
        let how = Degradation {
            noise: rng.next_f32() * self.max_noise,
            missing: if rng.next_f64() < self.missing_probability {
                rng.next_f32() * self.max_missing
            } else {
                0.0
            },
        };
        let points = degrade(&points, &how, rng.next_u64());
        inference_positions(
            &points,
            example.vertex_count,
            example.positions.len(),
            example.merge_ratio,
            rng.next_u64(),
        )
    }
}

/// Everything that defines a DiT training run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DitTrainConfig {
    pub model: DitConfig,
    pub batch_size: usize,
    pub steps: usize,
    pub learning_rate: f64,
    pub warmup_steps: usize,
    pub final_lr_ratio: f64,
    pub weight_decay: f64,
    pub grad_clip: f64,
    pub ema_decay: Option<f32>,
    pub seed: u64,
    pub checkpoint_every: usize,
    pub eval_every: usize,
    /// Conditioning augmentation; none when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub augment: Option<PositionAugment>,
    /// Each batch's gradient summed from this many sub-batches run at once on the CPU's
    /// threads ([`super::sub_batches`]; 1, the default: the whole batch in one pass).
    #[serde(
        default = "super::sub_batches::one_pass",
        skip_serializing_if = "super::sub_batches::is_one_pass"
    )]
    pub data_parallel: usize,
}

impl DitTrainConfig {
    /// The paper's optimiser settings (AdamW, lr 1e-4) around a model size.
    pub fn new(model: DitConfig) -> Self {
        Self {
            model,
            batch_size: 16,
            steps: 10_000,
            learning_rate: 1e-4,
            warmup_steps: 200,
            final_lr_ratio: 0.1,
            weight_decay: 0.01,
            grad_clip: 1.0,
            ema_decay: Some(0.999),
            seed: 0,
            checkpoint_every: 500,
            eval_every: 500,
            augment: None,
            data_parallel: 1,
        }
    }
}

impl DitTrainConfig {
    /// The schedule part, for [`run_training`].
    pub fn schedule(&self) -> Schedule {
        Schedule {
            steps: self.steps,
            learning_rate: self.learning_rate,
            warmup_steps: self.warmup_steps,
            final_lr_ratio: self.final_lr_ratio,
            weight_decay: self.weight_decay,
            grad_clip: self.grad_clip,
            ema_decay: self.ema_decay,
            seed: self.seed,
            checkpoint_every: self.checkpoint_every,
            eval_every: self.eval_every,
        }
    }

    /// Checks the model's sizes and the schedule before any step runs; the message names the
    /// offending field.
    pub fn validate(&self) -> Result<(), String> {
        self.model.validate()?;
        if let Some(a) = &self.augment {
            a.validate()?;
        }
        super::check_schedule(
            &[
                ("batch_size", self.batch_size),
                ("data_parallel", self.data_parallel),
                ("steps", self.steps),
                ("checkpoint_every", self.checkpoint_every),
                ("eval_every", self.eval_every),
            ],
            self.learning_rate,
            self.ema_decay,
        )
    }
}

/// A batch of flow-matching inputs and targets.
struct FlowBatch {
    x_t: Tensor<3>,
    target: Tensor<3>,
    t: Vec<f32>,
    cond: Tensor<2>,
    condition: Condition,
}

/// A batch's random draws for flow matching, from which [`FlowDraws::batch`] builds the inputs
/// of the whole batch or of any contiguous part of it ([`super::sub_batches`]).
struct FlowDraws {
    /// `b x tokens` RoPE positions.
    positions: Vec<[f32; 3]>,
    /// One row of input points per example (empty for a DiT without point tokens).
    points: Vec<Vec<Vec3>>,
    /// `[b, tokens, latent_dim]`: the clean latents and the noise.
    x0: Tensor<3>,
    eps: Tensor<3>,
    t: Vec<f32>,
    cond: Vec<f32>,
}

/// The tokens' RoPE positions are each example's own, or drawn by `augment` (first, from
/// `rng`); a DiT that reads input points gets a fresh subset of each example's surface
/// samples (next, from `rng`; nothing is drawn for one that does not, so such runs reproduce
/// those from before points existed).
fn flow_draws(
    examples: &[&LatentExample],
    augment: Option<&PositionAugment>,
    cfg: &DitConfig,
    rng: &mut Rng,
    device: &Device,
) -> FlowDraws {
    let positions: Vec<[f32; 3]> = examples
        .iter()
        .flat_map(|e| match augment {
            Some(augment) => augment.positions(e, rng),
            None => e.positions.clone(),
        })
        .collect();
    let points: Vec<Vec<Vec3>> = match cfg.point_tokens {
        0 => Vec::new(),
        count => examples
            .iter()
            .map(|e| context_points(&e.surface, count, rng.next_u64()))
            .collect(),
    };
    let (b, l, d) = (examples.len(), examples[0].positions.len(), cfg.latent_dim);
    let x0: Vec<f32> = examples
        .iter()
        .flat_map(|e| e.latents.iter().copied())
        .collect();
    let x0 = Tensor::<3>::from_data(TensorData::new(x0, [b, l, d]), device);
    let eps = normal_noise(rng, [b, l, d], device);
    // Logit-normal t.
    let t: Vec<f32> = (0..b)
        .map(|_| (1.0 / (1.0 + (-rng.normal()).exp())) as f32)
        .collect();
    let cond: Vec<f32> = examples
        .iter()
        .map(|e| vertex_condition(e.vertex_count, cfg.count_scale()))
        .collect();
    FlowDraws {
        positions,
        points,
        x0,
        eps,
        t,
        cond,
    }
}

impl FlowDraws {
    /// The flow-matching inputs and targets of examples `rows`.
    fn batch(&self, rows: Range<usize>, cfg: &DitConfig, device: &Device) -> FlowBatch {
        let b = rows.len();
        let cut = |x: &Tensor<3>| x.clone().narrow(0, rows.start, b);
        let (x0, eps) = (cut(&self.x0), cut(&self.eps));
        let t = self.t[rows.clone()].to_vec();
        let tt = Tensor::<1>::from_data(TensorData::new(t.clone(), [b]), device).reshape([b, 1, 1]);
        let x_t = x0.clone() * (tt.clone().neg() + 1.0) + eps.clone() * tt;
        let cond = self.cond[rows.clone()].to_vec();
        let tokens = self.x0.dims()[1];
        let positions = &self.positions[rows.start * tokens..rows.end * tokens];
        let points = self.points.get(rows).unwrap_or(&[]);
        FlowBatch {
            x_t,
            target: eps - x0,
            t,
            cond: Tensor::from_data(TensorData::new(cond, [b, 1]), device),
            condition: Condition::new(cfg, positions, points, b, device),
        }
    }
}

/// Mean squared error of the predicted velocity.
fn flow_loss(dit: &Dit, batch: &FlowBatch) -> Tensor<1> {
    let v = dit.forward(
        batch.x_t.clone(),
        &batch.t,
        batch.cond.clone(),
        &batch.condition,
        &mut Trace::default(),
    );
    (v - batch.target.clone()).square().mean()
}

/// Validation loss on fixed draws of t and noise (seeded), so successive evaluations compare.
pub fn validate_dit(
    dit: &Dit,
    cfg: &DitTrainConfig,
    val: &[LatentExample],
    device: &Device,
) -> f64 {
    let mut rng = Rng::new(cfg.seed ^ 0x5eed);
    let (mut sum, mut n) = (0.0, 0.0);
    let mut val: Vec<&LatentExample> = val.iter().collect();
    val.sort_by_key(|e| e.positions.len());
    let chunks = val
        .chunk_by(|a, b| a.positions.len() == b.positions.len())
        .flat_map(|same| same.chunks(cfg.batch_size.max(1)));
    for chunk in chunks {
        let refs: Vec<&LatentExample> = chunk.to_vec();
        let batch = flow_draws(&refs, None, &cfg.model, &mut rng, device).batch(
            0..refs.len(),
            &cfg.model,
            device,
        );
        sum += scalar(flow_loss(dit, &batch)) * chunk.len() as f64;
        n += chunk.len() as f64;
    }
    sum / n.max(1.0)
}

/// A validation line of the metrics file.
#[derive(Clone, Debug, Serialize)]
pub struct DitValidation {
    pub step: usize,
    /// Flow-matching loss on fixed draws of t and noise.
    pub val_loss: f64,
    /// The same with the token positions drawn as inference draws them, from clean surface
    /// samples (fixed seeds): the condition the model meets in use.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub val_loss_inference_positions: Option<f64>,
}

/// The DiT's part of [`run_training`]: batches of one token count, flow matching.
struct DitTask<'a> {
    cfg: &'a DitTrainConfig,
    train: Vec<&'a LatentExample>,
    /// The training examples by token count.
    by_length: BTreeMap<usize, Vec<&'a LatentExample>>,
    val: &'a [LatentExample],
    /// `val` with inference's token positions (examples without surface samples left out).
    val_inference: Vec<LatentExample>,
    ad_device: Device,
    device: Device,
}

impl Task for DitTask<'_> {
    type Model = Dit;
    /// Batches are drawn at random from the run's RNG, so there is no data position.
    type Position = NoPosition;
    type Validation = DitValidation;
    const THROUGHPUT: &'static str = "examples_per_s";

    fn step(
        &mut self,
        dit: Dit,
        _: &mut NoPosition,
        rng: &mut Rng,
        (optim, optim_state): (&AdamW, &mut AdamWState),
        lr: f64,
    ) -> (Dit, Option<StepOutcome>) {
        // The first example is drawn uniformly and the rest from its token count, so every
        // example keeps the same chance and a batch holds one length (length buckets).
        let first = self.train[rng.below(self.train.len())];
        let same = &self.by_length[&first.positions.len()];
        let batch: Vec<&LatentExample> = std::iter::once(first)
            .chain((1..self.cfg.batch_size).map(|_| same[rng.below(same.len())]))
            .collect();
        let (augment, model) = (self.cfg.augment.as_ref(), &self.cfg.model);
        let draws = flow_draws(&batch, augment, model, rng, &self.ad_device);
        let parts = sub_batches(batch.len(), self.cfg.data_parallel);
        let (loss, grads) = if parts.len() == 1 {
            let loss = flow_loss(&dit, &draws.batch(0..batch.len(), model, &self.ad_device));
            let grads = GradientsParams::from_grads(loss.clone().backward(), &dit);
            (scalar(loss), grads)
        } else {
            // The loss is a mean over equal-sized examples, so it splits by their share.
            let examples = batch.len() as f64;
            let work: Vec<_> = parts
                .into_iter()
                .map(|r| {
                    (
                        r.len() as f64 / examples,
                        draws.batch(r, model, &self.ad_device),
                    )
                })
                .collect();
            let (losses, grads) = gradients_in_parallel(&dit, work, |copy, fb| {
                let loss = flow_loss(copy, &fb);
                let value = scalar(loss.clone());
                (loss, value)
            });
            let loss = losses.into_iter().map(|(share, l)| share * l).sum();
            (loss, grads)
        };
        let (dit, grad_norm) = optim.step(optim_state, dit, grads, lr);
        let outcome = StepOutcome {
            loss,
            grad_norm,
            examples: batch.len(),
            terms: Vec::new(),
            summary: format!("loss {loss:.4}, grad norm {grad_norm:.2}"),
        };
        (dit, Some(outcome))
    }

    fn validate(&self, dit: &Dit, step: usize) -> Option<DitValidation> {
        (!self.val.is_empty()).then(|| DitValidation {
            step,
            val_loss: validate_dit(dit, self.cfg, self.val, &self.device),
            val_loss_inference_positions: (!self.val_inference.is_empty())
                .then(|| validate_dit(dit, self.cfg, &self.val_inference, &self.device)),
        })
    }

    fn describe(v: &DitValidation) -> String {
        let inference = v
            .val_loss_inference_positions
            .map(|l| format!(" ({l:.4} with inference's positions)"))
            .unwrap_or_default();
        format!(
            "step {}: validation flow loss {:.4}{inference}",
            v.step, v.val_loss
        )
    }
}

/// The DiT draws its batches from the run's RNG alone: nothing to save.
#[derive(Default, Serialize, Deserialize)]
pub struct NoPosition {}

/// Trains the DiT on cached latents ([`run_training`]), with checkpoints and `metrics.jsonl`
/// under `out_dir`; resumes from `out_dir/checkpoint` when its configuration matches. Starts
/// from `init` (trained weights of the same configuration, to fine-tune) or a seeded
/// initialisation. Returns the weights to ship (the EMA when enabled), the steps, the last
/// validation record and the time earlier processes spent on a resumed run.
pub fn train_dit(
    cfg: &DitTrainConfig,
    init: Option<&TensorMap>,
    train: &[LatentExample],
    val: &[LatentExample],
    out_dir: &Path,
    device: &Device,
    observer: &mut dyn TrainObserver,
) -> Result<Trained<DitValidation>, TrainError> {
    cfg.validate()
        .map_err(|e| TrainError::Weights(WeightsError::Config(e)))?;
    let d = cfg.model.latent_dim;
    let train: Vec<&LatentExample> = train
        .iter()
        .filter(|e| {
            let l = e.positions.len();
            l > 0 && l <= cfg.model.num_latents && e.latents.len() == l * d
        })
        .collect();
    if train.is_empty() {
        return Err(TrainError::NoData(cfg.model.num_latents));
    }
    let mut by_length: BTreeMap<usize, Vec<&LatentExample>> = BTreeMap::new();
    for e in &train {
        by_length.entry(e.positions.len()).or_default().push(e);
    }
    let ad_device = device.clone().autodiff();
    let mut dit = seeded_init(Dit::new(&cfg.model, &ad_device), cfg.seed);
    if let Some(init) = init {
        dit = load_module(dit, init, &is_image_path).map_err(TrainError::Weights)?;
    }
    let val_inference = val
        .iter()
        .enumerate()
        .filter(|(_, e)| !e.surface.is_empty())
        .map(|(i, e)| LatentExample {
            positions: inference_positions(
                &e.surface,
                e.vertex_count,
                e.positions.len(),
                e.merge_ratio,
                i as u64,
            ),
            ..e.clone()
        })
        .collect();
    let mut task = DitTask {
        cfg,
        train,
        by_length,
        val,
        val_inference,
        ad_device,
        device: device.clone(),
    };
    let trained = run_training(
        &mut task,
        cfg,
        &cfg.schedule(),
        dit,
        out_dir,
        device,
        observer,
    )?;
    Ok(trained)
}
