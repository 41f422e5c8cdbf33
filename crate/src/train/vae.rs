//! MeshVAE training: batches of vertex tokens (one length bucket per batch), the paper's
//! losses, and a step profiler; the loop itself (schedule, AdamW, EMA, checkpoints, metrics)
//! is [`super::run`], shared with the DiT.
//!
//! Losses (docs/design.md section 2), each averaged per mesh and then over the batch:
//! - mask: binary cross-entropy of the mask logits against real/padding, over all N tokens;
//! - position and normal: squared error over real vertices (mean over vertices and the 3 axes);
//! - adjacency: `(sum_E softplus(tau - d) + lambda_neg sum_notE softplus(d - tau)) / |E|`,
//!   which is `L_pos + lambda_neg (|notE| / |E|) L_neg` with both means written out; pairs are
//!   real i < j. Optionally, non-edges between close vertices weigh more
//!   ([`VaeTrainConfig::near_negative_weight`]);
//! - KL: `0.5 mean(mu^2 + exp(logvar) - 1 - logvar)` over latent channels, weight 1e-3;
//! - with a pair head ([`VaeConfig::pair_head`], not in the paper): the adjacency loss again,
//!   on the refined distances ([`MeshVae::edge_distances`]).

use std::path::Path;
use std::time::Instant;

use burn::module::Module;
use burn::optim::GradientsParams;
use burn::tensor::activation::softplus;
use burn::tensor::{Device, Int, Tensor, TensorData};
use serde::{Deserialize, Serialize};

use super::adamw::{AdamW, AdamWState};
use super::run::{Schedule, StepOutcome, Task, Trained, run_training};
use super::sub_batches::{gradients_in_parallel, sub_batches};
use super::{DeviceEma, TrainError, TrainObserver, scalar, warmup_cosine};
use crate::Mesh;
use crate::data::augment::{AugmentOptions, augment_mesh};
use crate::model::sampler::normal_noise;
use crate::model::tokens::{VertexTokens, build_tokens};
use crate::model::weights::{TensorMap, WeightsError, load_module_keeping};
use crate::model::{MeshVae, Posterior, Trace, VaeConfig, seeded_init, spacetime_distances};
use crate::pipeline::shipped::is_encoder_side;
use crate::rng::Rng;

/// Everything that defines a training run; saved in the checkpoint and the weights manifest.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VaeTrainConfig {
    pub model: VaeConfig,
    pub batch_size: usize,
    pub steps: usize,
    pub learning_rate: f64,
    pub warmup_steps: usize,
    /// The cosine decays to `learning_rate * final_lr_ratio`.
    pub final_lr_ratio: f64,
    pub weight_decay: f64,
    /// Global gradient-norm clip.
    pub grad_clip: f64,
    pub kl_weight: f64,
    pub lambda_neg: f64,
    pub position_weight: f64,
    pub normal_weight: f64,
    /// EMA of the weights, e.g. 0.999; `None` ships the raw weights.
    pub ema_decay: Option<f32>,
    pub seed: u64,
    pub checkpoint_every: usize,
    pub eval_every: usize,
    /// Random rotation about the up axis (Y) and per-axis scale jitter in `[1-j, 1+j]`.
    pub augment: bool,
    pub scale_jitter: f32,
    /// Weight of each non-edge pair whose ground-truth vertices lie closer than
    /// `near_negative_radius` mean edge lengths of its mesh, in place of `lambda_neg`; 0 (the
    /// default) leaves every non-edge at `lambda_neg`. On the validation split such pairs (at
    /// radius 2) are a sixth of the non-edges, and nearly all of the shipped decoder's wrong
    /// edges join such vertices (quad diagonals, the two sides of a thin part;
    /// [`crate::eval::edge_errors`], docs/experiments/2026-11-27-wrong-edges.md).
    #[serde(default)]
    pub near_negative_weight: f64,
    #[serde(default = "default_near_negative_radius")]
    pub near_negative_radius: f32,
    /// Standard deviation of Gaussian noise added to every sampled latent in training steps
    /// (0, the default: none). A DiT's samples are not encoded meshes; a decoder that has seen
    /// latents pushed off the encoder's is meant to decode them more gracefully.
    #[serde(default)]
    pub latent_noise: f32,
    /// Train the decoder side only (post-KL projection, decoder, heads), starting from given
    /// weights: the encoder, and so every latent a DiT was trained on, stays bit for bit as it
    /// was, and the DiT keeps fitting the VAE ([`crate::pipeline::shipped::latent_space_sha256`]).
    #[serde(default)]
    pub decoder_only: bool,
    /// The edge threshold written into the trained VAE's configuration (`model.tau` of
    /// `vae.json` and the manifest), which extraction uses; the loss keeps `model.tau`. `None`
    /// (the default) writes `model.tau`. Weighing near non-edges moves where the decoder's
    /// edge and non-edge scores cross, so such a run is extracted at a threshold chosen on
    /// the validation split ([`ValLog::best_tau`], docs/experiments/2026-11-27-near-non-edges.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub extraction_tau: Option<f32>,
    /// Each batch's gradient summed from this many sub-batches run at once on the CPU's
    /// threads ([`super::sub_batches`]; 1, the default: the whole batch in one pass): the same
    /// gradient up to float rounding, in about 60% of the time with 2 on two cores.
    #[serde(
        default = "super::sub_batches::one_pass",
        skip_serializing_if = "super::sub_batches::is_one_pass"
    )]
    pub data_parallel: usize,
}

fn default_near_negative_radius() -> f32 {
    crate::eval::edge_errors::NEAR_EDGE_LENGTHS
}

impl VaeTrainConfig {
    /// The paper's optimiser settings around a model size.
    pub fn new(model: VaeConfig) -> Self {
        Self {
            model,
            batch_size: 8,
            steps: 10_000,
            learning_rate: 5e-4,
            warmup_steps: 200,
            final_lr_ratio: 0.05,
            weight_decay: 0.01,
            grad_clip: 1.0,
            kl_weight: 1e-3,
            lambda_neg: 0.01,
            position_weight: 1.0,
            normal_weight: 1.0,
            ema_decay: None,
            seed: 0,
            checkpoint_every: 500,
            eval_every: 500,
            augment: true,
            scale_jitter: 0.1,
            near_negative_weight: 0.0,
            near_negative_radius: default_near_negative_radius(),
            latent_noise: 0.0,
            decoder_only: false,
            extraction_tau: None,
            data_parallel: 1,
        }
    }

    /// How [`make_batch`] weighs the non-edge pairs.
    pub fn non_edge_weights(&self) -> NonEdgeWeights {
        if self.near_negative_weight > 0.0 {
            NonEdgeWeights {
                weight: self.lambda_neg as f32,
                near_weight: self.near_negative_weight as f32,
                near_radius: self.near_negative_radius,
            }
        } else {
            NonEdgeWeights::uniform(self.lambda_neg as f32)
        }
    }

    /// The trained VAE's configuration as written beside its weights: `model` with
    /// [`Self::extraction_tau`] as its threshold.
    pub fn trained_model(&self) -> VaeConfig {
        VaeConfig {
            tau: self.extraction_tau.unwrap_or(self.model.tau),
            ..self.model.clone()
        }
    }

    /// Checks the model's sizes and the schedule before any step runs; the message names the
    /// offending field.
    pub fn validate(&self) -> Result<(), String> {
        self.model.validate()?;
        if !(self.near_negative_weight.is_finite() && self.near_negative_weight >= 0.0) {
            return Err(format!(
                "near_negative_weight must be 0 (off) or positive (got {})",
                self.near_negative_weight
            ));
        }
        if !(self.latent_noise.is_finite() && self.latent_noise >= 0.0) {
            return Err(format!(
                "latent_noise must be 0 (off) or positive (got {})",
                self.latent_noise
            ));
        }
        if !(self.near_negative_radius.is_finite() && self.near_negative_radius > 0.0) {
            return Err(format!(
                "near_negative_radius must be positive (got {})",
                self.near_negative_radius
            ));
        }
        if let Some(tau) = self.extraction_tau.filter(|t| !t.is_finite()) {
            return Err(format!("extraction_tau must be finite (got {tau})"));
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

    /// Learning rate at `step` (0-based): linear warm-up, then cosine decay.
    pub fn lr_at(&self, step: usize) -> f64 {
        warmup_cosine(
            step,
            self.learning_rate,
            self.warmup_steps,
            self.steps,
            self.final_lr_ratio,
        )
    }
}

/// One batch on a device.
pub struct VaeBatch {
    /// `[B, N, C]` encoder input.
    pub features: Tensor<3>,
    /// `[B, N, 1]`: 1 for real vertices.
    pub real: Tensor<3>,
    pub positions: Tensor<3>,
    pub normals: Tensor<3>,
    /// `[B, N, N]`: 1 for ground-truth edges (i < j).
    pub edges: Tensor<3>,
    /// `[B, N, N]`: the adjacency loss's weight of each real pair i < j that is not an edge
    /// ([`NonEdgeWeights`]), 0 elsewhere.
    pub non_edges: Tensor<3>,
    /// The real vertex slots of each mesh (the first ones).
    pub real_slots: Vec<Vec<u32>>,
}

/// The weight of a non-edge pair in the adjacency loss: `weight`, or `near_weight` when its two
/// ground-truth vertices are closer than `near_radius` times the mesh's mean edge length.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NonEdgeWeights {
    pub weight: f32,
    pub near_weight: f32,
    pub near_radius: f32,
}

impl NonEdgeWeights {
    /// Every non-edge at `weight` (for batches that only feed the encoder).
    pub fn uniform(weight: f32) -> Self {
        Self {
            weight,
            near_weight: weight,
            near_radius: 0.0,
        }
    }

    /// Fills `plane` (`n x n`, zeros) with the weights of `t`'s non-edges.
    fn fill(&self, t: &VertexTokens, plane: &mut [f32], n: usize) {
        let real = t.num_real;
        for i in 0..real {
            plane[i * n + i + 1..i * n + real].fill(self.weight);
        }
        if self.near_weight != self.weight && !t.edges.is_empty() {
            let length =
                |&[i, j]: &[u32; 2]| t.positions[i as usize].distance(t.positions[j as usize]);
            let mean_edge = t.edges.iter().map(length).sum::<f32>() / t.edges.len() as f32;
            let radius = self.near_radius * mean_edge;
            for i in 0..real {
                for j in i + 1..real {
                    if t.positions[i].distance_squared(t.positions[j]) < radius * radius {
                        plane[i * n + j] = self.near_weight;
                    }
                }
            }
        }
        for &[i, j] in &t.edges {
            plane[i as usize * n + j as usize] = 0.0;
        }
    }
}

/// Stacks token sets (all with the same N) into a batch.
pub fn make_batch(tokens: &[VertexTokens], non_edge: NonEdgeWeights, device: &Device) -> VaeBatch {
    let b = tokens.len();
    let n = tokens[0].mask.len();
    let c = tokens[0].in_channels;
    let mut features = Vec::with_capacity(b * n * c);
    let (mut real, mut pos, mut nrm) = (Vec::new(), Vec::new(), Vec::new());
    let mut edges = vec![0f32; b * n * n];
    let mut non_edges = vec![0f32; b * n * n];
    for (k, t) in tokens.iter().enumerate() {
        assert_eq!(t.mask.len(), n, "every mesh in a batch has the same N");
        features.extend_from_slice(&t.features);
        real.extend(t.mask.iter().map(|&m| m as u8 as f32));
        pos.extend(t.positions.iter().flat_map(|p| p.to_array()));
        nrm.extend(t.normals.iter().flat_map(|p| p.to_array()));
        non_edge.fill(t, &mut non_edges[k * n * n..(k + 1) * n * n], n);
        for &[i, j] in &t.edges {
            edges[k * n * n + i as usize * n + j as usize] = 1.0;
        }
    }
    let t3 = |v: Vec<f32>, d: usize| Tensor::from_data(TensorData::new(v, [b, n, d]), device);
    VaeBatch {
        features: t3(features, c),
        real: t3(real, 1),
        positions: t3(pos, 3),
        normals: t3(nrm, 3),
        edges: t3(edges, n),
        non_edges: t3(non_edges, n),
        real_slots: tokens
            .iter()
            .map(|t| (0..t.num_real as u32).collect())
            .collect(),
    }
}

/// The loss terms of one batch, as scalars (`[1]` tensors).
pub struct VaeLosses {
    pub total: Tensor<1>,
    pub mask: Tensor<1>,
    pub position: Tensor<1>,
    pub normal: Tensor<1>,
    pub adjacency: Tensor<1>,
    /// The adjacency loss again on the pair head's refined distances
    /// ([`MeshVae::edge_distances`]); `None` without a pair head.
    pub pair_adjacency: Option<Tensor<1>>,
    pub kl: Tensor<1>,
}

impl VaeLosses {
    /// Every term times `share`, out of the graph (a sub-batch's part of the batch's losses).
    fn scaled(self, share: f64) -> Self {
        let s = |t: Tensor<1>| t.detach() * share;
        Self {
            total: s(self.total),
            mask: s(self.mask),
            position: s(self.position),
            normal: s(self.normal),
            adjacency: s(self.adjacency),
            pair_adjacency: self.pair_adjacency.map(s),
            kl: s(self.kl),
        }
    }

    /// The terms added one by one.
    fn add(self, other: Self) -> Self {
        Self {
            total: self.total + other.total,
            mask: self.mask + other.mask,
            position: self.position + other.position,
            normal: self.normal + other.normal,
            adjacency: self.adjacency + other.adjacency,
            pair_adjacency: self
                .pair_adjacency
                .zip(other.pair_adjacency)
                .map(|(a, b)| a + b),
            kl: self.kl + other.kl,
        }
    }
}

/// Per-mesh sums over all but the batch axis: `[B, X, Y]` -> `[B]`.
fn per_mesh(t: Tensor<3>) -> Tensor<1> {
    let [b, _, _] = t.dims();
    t.sum_dim(2).sum_dim(1).reshape([b])
}

/// The paper's losses for a batch; `noise` `[B, N/r, D]` is the reparameterisation noise
/// (zeros for the posterior mean).
pub fn vae_losses(
    vae: &MeshVae,
    batch: &VaeBatch,
    noise: Tensor<3>,
    cfg: &VaeTrainConfig,
) -> VaeLosses {
    vae_losses_timed(vae, batch, noise, None, cfg, &mut Laps::off())
}

/// Wall-clock laps through the parts of a training step (for `meshflow bench train-vae`);
/// [`Laps::off`] records nothing. Burn's CPU backend runs eagerly, so a lap is the time of the
/// operations issued since the previous one.
pub struct Laps {
    on: bool,
    last: Instant,
    /// (part, seconds), in order; a part may appear several times.
    pub parts: Vec<(&'static str, f64)>,
}

impl Laps {
    /// Laps that record.
    pub fn on() -> Self {
        Self {
            on: true,
            last: Instant::now(),
            parts: Vec::new(),
        }
    }

    /// Laps that record nothing.
    pub fn off() -> Self {
        Self {
            on: false,
            last: Instant::now(),
            parts: Vec::new(),
        }
    }

    /// Ends the current part, named `part`.
    pub fn lap(&mut self, part: &'static str) {
        if self.on {
            let now = Instant::now();
            self.parts.push((part, (now - self.last).as_secs_f64()));
            self.last = now;
        }
    }
}

/// [`vae_losses`] with a lap after the encoder, the decoder, the pairwise adjacency term and the
/// other loss terms; `latent_jitter` (`[B, N/r, D]`, [`VaeTrainConfig::latent_noise`]) is
/// added to the sampled latents when given.
pub fn vae_losses_timed(
    vae: &MeshVae,
    batch: &VaeBatch,
    noise: Tensor<3>,
    latent_jitter: Option<Tensor<3>>,
    cfg: &VaeTrainConfig,
    laps: &mut Laps,
) -> VaeLosses {
    let posterior = if cfg.decoder_only && batch.features.is_autodiff() {
        // The encoder runs outside the autodiff graph, so no gradient reaches it and AdamW
        // leaves it untouched. (Detaching its outputs instead left the encoder's part of the
        // graph recorded and never released: 40 MB a step.)
        let p = vae
            .valid()
            .encode(batch.features.clone().inner(), &mut Trace::default());
        Posterior {
            mean: p.mean.autodiff(),
            logvar: p.logvar.autodiff(),
        }
    } else {
        vae.encode(batch.features.clone(), &mut Trace::default())
    };
    let std = (posterior.logvar.clone() * 0.5).exp();
    let mut z = posterior.mean.clone() + std * noise;
    if let Some(jitter) = latent_jitter {
        z = z + jitter;
    }
    laps.lap("encoder");
    let out = vae.decode(z, &mut Trace::default());
    laps.lap("decoder");

    let real = batch.real.clone();
    let num_real = per_mesh(real.clone()).clamp_min(1.0);
    // BCE with logits: softplus(x) - x y.
    let logits = out.mask_logits;
    let [_, n, _] = logits.dims();
    let bce = softplus(logits.clone(), 1.0) - logits * real.clone();
    let mask = (per_mesh(bce) / n as f64).mean();
    let squared = |pred: Tensor<3>, gt: Tensor<3>| {
        let err = (pred - gt).square() * real.clone();
        (per_mesh(err) / (num_real.clone() * 3.0)).mean()
    };
    let position = squared(out.positions, batch.positions.clone());
    let normal = squared(out.normals, batch.normals.clone());
    laps.lap("loss: mask, position, normal");

    let tau = cfg.model.tau as f64;
    let num_edges = per_mesh(batch.edges.clone()).clamp_min(1.0);
    let adjacency_of = |d: Tensor<3>| {
        let pos = per_mesh(softplus(d.clone().neg() + tau, 1.0) * batch.edges.clone());
        let neg = per_mesh(softplus(d - tau, 1.0) * batch.non_edges.clone());
        ((pos + neg) / num_edges.clone()).mean()
    };
    let distances = spacetime_distances(out.edge_embeddings.clone());
    let adjacency = adjacency_of(distances.clone());
    // The spacetime distances keep their own loss, so the candidates they pick stay the
    // plausible pairs; the pair head is trained on the refined ones. The refined matrix
    // differs from the plain one only at the candidates, so its loss is the plain one with
    // their terms swapped: the same value and gradients as a second [B, N, N] pass, without it.
    let pair_adjacency = vae.decoder.pair_head.is_some().then(|| {
        let Some(pairs) =
            vae.read_pair_corrections(distances, out.features.clone(), &batch.real_slots)
        else {
            return adjacency.clone();
        };
        let [b, n, _] = batch.edges.dims();
        let at = |t: &Tensor<3>| {
            t.clone()
                .reshape([b * n * n])
                .select(0, pairs.index.clone())
        };
        let meshes: Vec<i64> = pairs.pairs.iter().map(|p| p[0] as i64).collect();
        let per_edge = num_edges.clone().recip().select(
            0,
            Tensor::<1, Int>::from_data(
                TensorData::new(meshes, [pairs.pairs.len()]),
                &pairs.index.device(),
            ),
        );
        let (plain, refined) = (pairs.distances.clone(), pairs.distances + pairs.corrections);
        let swap = |d: Tensor<1>| {
            softplus(d.clone().neg() + tau, 1.0) * at(&batch.edges)
                + softplus(d - tau, 1.0) * at(&batch.non_edges)
        };
        adjacency.clone() + ((swap(refined) - swap(plain)) * per_edge).sum() / b as f64
    });
    laps.lap("adjacency: pairwise distances and loss");

    let kl = ((posterior.mean.square() + posterior.logvar.clone().exp() - 1.0 - posterior.logvar)
        * 0.5)
        .mean();
    let mut total = mask.clone()
        + position.clone() * cfg.position_weight
        + normal.clone() * cfg.normal_weight
        + adjacency.clone()
        + kl.clone() * cfg.kl_weight;
    if let Some(pair) = &pair_adjacency {
        total = total + pair.clone();
    }
    laps.lap("loss: KL and total");
    VaeLosses {
        total,
        mask,
        position,
        normal,
        adjacency,
        pair_adjacency,
        kl,
    }
}

/// Validation figures: losses with the posterior mean, and edge precision/recall/F1 of the
/// spacetime distances among the real vertices, thresholded where extraction will threshold
/// them ([`VaeTrainConfig::trained_model`]'s tau: `extraction_tau` when set, so a manifest's
/// final validation scores the VAE as it ships).
#[derive(Clone, Debug, Serialize)]
pub struct ValLog {
    pub step: usize,
    pub val_loss: f64,
    pub val_position: f64,
    /// Mean squared error of the unit normals (the normal loss term).
    pub val_normal: f64,
    pub val_adjacency: f64,
    pub edge_precision: f64,
    pub edge_recall: f64,
    pub edge_f1: f64,
    /// The best pooled F1 over the thresholds of [`TAU_GRID`], and its tau: a loss that weighs
    /// non-edges differently moves where edge and non-edge scores cross, so runs are compared
    /// here as well as at the scored threshold above.
    pub edge_f1_best_tau: f64,
    pub best_tau: f32,
    pub mask_accuracy: f64,
}

/// The thresholds [`ValLog::edge_f1_best_tau`] tries: -3 to 3 in steps of 0.25.
pub const TAU_GRID: [f32; 25] = {
    let mut grid = [0.0; 25];
    let mut k = 0;
    while k < 25 {
        grid[k] = -3.0 + 0.25 * k as f32;
        k += 1;
    }
    grid
};

/// Tokens of `mesh` for the model (None when it has too many vertices or is invalid).
fn tokens_of(mesh: &Mesh, cfg: &VaeConfig, seed: u64) -> Option<VertexTokens> {
    build_tokens(mesh, &cfg.tokens_for(mesh.positions.len()), seed).ok()
}

/// A training mesh's tokens: augmented (rotation about Y, scale jitter) when the
/// configuration asks for it. None when the mesh does not fit.
fn training_tokens(mesh: &Mesh, cfg: &VaeTrainConfig, rng: &mut Rng) -> Option<VertexTokens> {
    let augmented;
    let mesh = if cfg.augment {
        let opts = AugmentOptions {
            rotate: true,
            scale_jitter: cfg.scale_jitter,
            points: 0,
        };
        augmented = augment_mesh(mesh, &opts, rng).0;
        &augmented
    } else {
        mesh
    };
    tokens_of(mesh, &cfg.model, rng.next_u64())
}

/// The batches of one epoch, as indices into the training meshes (given by their vertex
/// counts): a shuffle seeded by (seed, epoch), grouped by vertex-slot bucket
/// ([`VaeConfig::slots_for`]; one bucket without length buckets), cut into batches of
/// `batch_size` (a bucket's remainder makes one smaller batch), and the batches shuffled. A
/// function of (seed, epoch) alone, so a resumed run needs only its position in the list.
pub fn epoch_batches(
    vertex_counts: &[usize],
    cfg: &VaeTrainConfig,
    epoch: usize,
) -> Vec<Vec<usize>> {
    let mut rng = Rng::new(cfg.seed ^ (epoch as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15));
    let mut order: Vec<usize> = (0..vertex_counts.len()).collect();
    rng.shuffle(&mut order);
    let mut buckets: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
    for i in order {
        buckets
            .entry(cfg.model.slots_for(vertex_counts[i]))
            .or_default()
            .push(i);
    }
    let mut batches: Vec<Vec<usize>> = buckets
        .values()
        .flat_map(|b| b.chunks(cfg.batch_size.max(1)).map(<[usize]>::to_vec))
        .collect();
    rng.shuffle(&mut batches);
    batches
}

/// One optimiser step on a batch of token sets (on the autodiff `device`): losses, backward,
/// clipped AdamW at `lr`.
/// Returns the updated model, the loss terms and the gradient norm before clipping.
///
/// With [`VaeTrainConfig::data_parallel`] above 1 the batch's gradient is summed from
/// sub-batches run at once ([`gradients_in_parallel`]): every loss term is a mean over the
/// batch's meshes. The reparameterisation noise is drawn for the whole batch and cut, so the
/// random stream is the same with or without the split.
#[allow(clippy::too_many_arguments)]
fn optimiser_step(
    vae: MeshVae,
    tokens: &[VertexTokens],
    cfg: &VaeTrainConfig,
    optim: &AdamW,
    optim_state: &mut AdamWState,
    lr: f64,
    rng: &mut Rng,
    device: &Device,
    laps: &mut Laps,
) -> (MeshVae, VaeLosses, f64) {
    let latents = tokens[0].mask.len() / cfg.model.merge_ratio();
    let shape = [tokens.len(), latents, cfg.model.latent_dim];
    let noise = normal_noise(rng, shape, device);
    // Drawn only when asked for, so runs without it keep their random stream.
    let jitter = (cfg.latent_noise > 0.0)
        .then(|| normal_noise(rng, shape, device) * cfg.latent_noise as f64);
    let parts = sub_batches(tokens.len(), cfg.data_parallel);
    let (losses, grads) = if parts.len() == 1 {
        let batch = make_batch(tokens, cfg.non_edge_weights(), device);
        laps.lap("batch: dense tensors to the device");
        let losses = vae_losses_timed(&vae, &batch, noise, jitter, cfg, laps);
        let grads = losses.total.backward();
        laps.lap("backward");
        (losses, GradientsParams::from_grads(grads, &vae))
    } else {
        let meshes = tokens.len() as f64;
        let work: Vec<_> = parts
            .into_iter()
            .map(|r| {
                let noise = noise.clone().narrow(0, r.start, r.len());
                let jitter = jitter.clone().map(|j| j.narrow(0, r.start, r.len()));
                (r.len() as f64 / meshes, (r, noise, jitter))
            })
            .collect();
        let (parts, grads) = gradients_in_parallel(&vae, work, |copy, (r, noise, jitter)| {
            let batch = make_batch(&tokens[r], cfg.non_edge_weights(), device);
            let losses = vae_losses_timed(copy, &batch, noise, jitter, cfg, &mut Laps::off());
            (losses.total.clone(), losses)
        });
        laps.lap("sub-batches at once: batch, forward, backward");
        let losses = parts
            .into_iter()
            .map(|(share, losses)| losses.scaled(share))
            .reduce(VaeLosses::add)
            .expect("at least two sub-batches");
        (losses, grads)
    };
    let (updated, grad_norm) = optim.step(optim_state, vae, grads, lr);
    laps.lap("optimizer (clip + AdamW)");
    (updated, losses, grad_norm)
}

/// Where a training step's time goes: [`profile_vae_step`]'s result.
pub struct StepProfile {
    /// `(part, mean seconds per step)`, in step order.
    pub parts: Vec<(&'static str, f64)>,
    /// Mean meshes per step (a length bucket's last batch may be smaller).
    pub meshes_per_step: f64,
    /// Mean matrix-product FLOPs per step: forward and backward, 3x
    /// [`VaeConfig::forward_flops`] at each batch's slot count.
    pub flops_per_step: f64,
}

/// Mean wall time of each part of a training step of `cfg` on `meshes` (model frame), over
/// `steps` steps after one warm-up step, on `device` (its autodiff twin runs the step), with
/// the training loop's batching (length buckets when configured). Parts: token building with
/// augmentation, dense batch tensors, encoder, decoder, the loss terms, the pairwise adjacency
/// term, backward, the optimiser, the EMA and the loss read-back of the training loop.
pub fn profile_vae_step(
    cfg: &VaeTrainConfig,
    meshes: &[Mesh],
    device: &Device,
    steps: usize,
) -> Result<StepProfile, TrainError> {
    let meshes: Vec<&Mesh> = meshes
        .iter()
        .filter(|m| !m.positions.is_empty() && m.positions.len() <= cfg.model.num_vertices)
        .collect();
    if meshes.is_empty() {
        return Err(TrainError::NoData(cfg.model.num_vertices));
    }
    let ad_device = device.clone().autodiff();
    let mut vae = seeded_init(MeshVae::new(&cfg.model, &ad_device), cfg.seed);
    let optim = AdamW::new(cfg.weight_decay, cfg.grad_clip);
    let mut optim_state = AdamWState::default();
    let mut ema = cfg.ema_decay.map(|decay| DeviceEma::new(&vae, decay));
    let mut rng = Rng::new(cfg.seed);
    let mut totals: Vec<(&'static str, f64)> = Vec::new();
    let vertex_counts: Vec<usize> = meshes.iter().map(|m| m.positions.len()).collect();
    let batches = epoch_batches(&vertex_counts, cfg, 0);
    let (mut meshes_total, mut flops_total) = (0.0, 0.0);
    for step in 0..=steps {
        let mut laps = Laps::on();
        let tokens: Vec<VertexTokens> = batches[step % batches.len()]
            .iter()
            .filter_map(|&i| training_tokens(meshes[i], cfg, &mut rng))
            .collect();
        laps.lap("data: augment + tokens");
        let lr = cfg.lr_at(step);
        let (updated, losses, _) = optimiser_step(
            vae,
            &tokens,
            cfg,
            &optim,
            &mut optim_state,
            lr,
            &mut rng,
            &ad_device,
            &mut laps,
        );
        vae = updated;
        if let Some(ema) = ema.as_mut() {
            ema.update(&vae);
        }
        laps.lap("EMA (on the device)");
        for t in [losses.total, losses.mask, losses.position, losses.normal] {
            scalar(t);
        }
        laps.lap("loss read-back");
        if step == 0 {
            continue;
        }
        meshes_total += tokens.len() as f64;
        flops_total += 3.0 * tokens.len() as f64 * cfg.model.forward_flops(tokens[0].mask.len());
        for (part, s) in laps.parts {
            match totals.iter_mut().find(|(p, _)| *p == part) {
                Some((_, t)) => *t += s,
                None => totals.push((part, s)),
            }
        }
    }
    let steps = steps.max(1) as f64;
    for (_, t) in totals.iter_mut() {
        *t /= steps;
    }
    Ok(StepProfile {
        parts: totals,
        meshes_per_step: meshes_total / steps,
        flops_per_step: flops_total / steps,
    })
}

/// Validation on up to `limit` meshes, batch by batch, with the posterior mean.
pub fn validate(
    vae: &MeshVae,
    meshes: &[Mesh],
    cfg: &VaeTrainConfig,
    device: &Device,
    step: usize,
) -> Option<ValLog> {
    let mut tokens: Vec<VertexTokens> = meshes
        .iter()
        .enumerate()
        .filter_map(|(i, m)| tokens_of(m, &cfg.model, i as u64))
        .collect();
    if tokens.is_empty() {
        return None;
    }
    // Batches hold one length each (length buckets); the figures are pooled, so order is free.
    tokens.sort_by_key(|t| t.mask.len());
    let (mut loss, mut position, mut normal, mut adjacency, mut batches) =
        (0.0, 0.0, 0.0, 0.0, 0.0);
    let (mut tp, mut fp, mut edges_total, mut mask_ok, mut mask_total) =
        (0usize, 0usize, 0usize, 0usize, 0usize);
    // Pairs by how many grid thresholds their score exceeds, edges and non-edges apart.
    let (mut edges_above, mut non_edges_above) = ([0usize; 26], [0usize; 26]);
    let tau = cfg.trained_model().tau;
    let chunks = tokens
        .chunk_by(|a, b| a.mask.len() == b.mask.len())
        .flat_map(|same| same.chunks(cfg.batch_size.max(1)));
    for chunk in chunks {
        let n = chunk[0].mask.len();
        let latents = n / cfg.model.merge_ratio();
        // The plain non-edge weight, so validation losses compare across near weights.
        let batch = make_batch(
            chunk,
            NonEdgeWeights::uniform(cfg.lambda_neg as f32),
            device,
        );
        let zeros = Tensor::zeros([chunk.len(), latents, cfg.model.latent_dim], device);
        let l = vae_losses(vae, &batch, zeros, cfg);
        loss += scalar(l.total);
        position += scalar(l.position);
        normal += scalar(l.normal);
        adjacency += scalar(l.adjacency);
        batches += 1.0;
        let posterior = vae.encode(batch.features, &mut Trace::default());
        let out = vae.decode(posterior.mean, &mut Trace::default());
        let d = vae
            .edge_distances(out.edge_embeddings, out.features, &batch.real_slots)
            .ok()?;
        let logits = out
            .mask_logits
            .try_into_data()
            .ok()?
            .convert::<f32>()
            .try_into_vec::<f32>()
            .ok()?;
        for (k, t) in chunk.iter().enumerate() {
            // One pass over the real pairs: the scores at the extraction tau and the histogram
            // over the grid (`t.edges` are real, i < j and distinct).
            let real = t.num_real;
            let mut is_edge = vec![false; real * real];
            for &[i, j] in &t.edges {
                is_edge[i as usize * real + j as usize] = true;
            }
            for i in 0..real {
                for j in i + 1..real {
                    let score = d[k * n * n + i * n + j];
                    let above = TAU_GRID.partition_point(|&tau| score > tau);
                    let edge = is_edge[i * real + j];
                    if edge {
                        edges_above[above] += 1;
                    } else {
                        non_edges_above[above] += 1;
                    }
                    if score > tau {
                        if edge {
                            tp += 1;
                        } else {
                            fp += 1;
                        }
                    }
                }
            }
            edges_total += t.edges.len();
            for i in 0..n {
                mask_ok += ((logits[k * n + i] > 0.0) == t.mask[i]) as usize;
            }
            mask_total += n;
        }
    }
    let fn_ = edges_total - tp;
    let precision = tp as f64 / (tp + fp).max(1) as f64;
    let recall = tp as f64 / (tp + fn_).max(1) as f64;
    let f1 = if precision + recall > 0.0 {
        2.0 * precision * recall / (precision + recall)
    } else {
        0.0
    };
    let (best_f1, best_tau) = best_grid_f1(&edges_above, &non_edges_above, f1, tau);
    Some(ValLog {
        step,
        val_loss: loss / batches,
        val_position: position / batches,
        val_normal: normal / batches,
        val_adjacency: adjacency / batches,
        edge_precision: precision,
        edge_recall: recall,
        edge_f1: f1,
        edge_f1_best_tau: best_f1,
        best_tau,
        mask_accuracy: mask_ok as f64 / mask_total.max(1) as f64,
    })
}

/// The best pooled F1 over [`TAU_GRID`] and its tau, from the pairs counted by how many grid
/// thresholds their score exceeds (`edges_above[k]`: edges above exactly k of them), or
/// `(f1, tau)`, the model's own, when no grid threshold beats it.
pub fn best_grid_f1(
    edges_above: &[usize; 26],
    non_edges_above: &[usize; 26],
    f1: f64,
    tau: f32,
) -> (f64, f32) {
    let all_edges: usize = edges_above.iter().sum();
    let mut best = (f1, tau);
    for (g, &grid_tau) in TAU_GRID.iter().enumerate() {
        // At threshold g the predicted pairs are those above more than g thresholds.
        let tp: usize = edges_above[g + 1..].iter().sum();
        let fp: usize = non_edges_above[g + 1..].iter().sum();
        let f1 = 2.0 * tp as f64 / (tp + fp + all_edges).max(1) as f64;
        if f1 > best.0 {
            best = (f1, grid_tau);
        }
    }
    best
}

/// Where a VAE run stands in its data: the epoch and the next batch of its list.
#[derive(Default, Serialize, Deserialize)]
pub struct EpochPosition {
    cursor: usize,
    epoch: usize,
}

/// The MeshVAE's part of [`run_training`]: batches from [`epoch_batches`], the paper's losses.
struct VaeTask<'a> {
    cfg: &'a VaeTrainConfig,
    train: Vec<&'a Mesh>,
    val: &'a [Mesh],
    vertex_counts: Vec<usize>,
    /// The batch list of `batches_epoch`.
    batches: Vec<Vec<usize>>,
    batches_epoch: Option<usize>,
    ad_device: Device,
    device: Device,
}

impl VaeTask<'_> {
    fn batches_of(&mut self, epoch: usize) {
        if self.batches_epoch != Some(epoch) {
            self.batches = epoch_batches(&self.vertex_counts, self.cfg, epoch);
            self.batches_epoch = Some(epoch);
        }
    }
}

impl Task for VaeTask<'_> {
    type Model = MeshVae;
    type Position = EpochPosition;
    type Validation = ValLog;
    const THROUGHPUT: &'static str = "meshes_per_s";

    fn step(
        &mut self,
        model: MeshVae,
        position: &mut EpochPosition,
        rng: &mut Rng,
        (optim, optim_state): (&AdamW, &mut AdamWState),
        lr: f64,
    ) -> (MeshVae, Option<StepOutcome>) {
        self.batches_of(position.epoch);
        if position.cursor == self.batches.len() {
            position.epoch += 1;
            position.cursor = 0;
            self.batches_of(position.epoch);
        }
        let tokens: Vec<VertexTokens> = self.batches[position.cursor]
            .iter()
            .filter_map(|&i| training_tokens(self.train[i], self.cfg, rng))
            .collect();
        position.cursor += 1;
        if tokens.is_empty() {
            return (model, None);
        }
        let (model, losses, grad_norm) = optimiser_step(
            model,
            &tokens,
            self.cfg,
            optim,
            optim_state,
            lr,
            rng,
            &self.ad_device,
            &mut Laps::off(),
        );
        let loss = scalar(losses.total);
        let mut terms = vec![
            ("mask", scalar(losses.mask)),
            ("position", scalar(losses.position)),
            ("normal", scalar(losses.normal)),
            ("adjacency", scalar(losses.adjacency)),
            ("kl", scalar(losses.kl)),
        ];
        if let Some(pair) = losses.pair_adjacency {
            terms.push(("pair_adjacency", scalar(pair)));
        }
        let summary = format!(
            "loss {loss:.4} (adj {:.4}, pos {:.2e})",
            terms[3].1, terms[1].1
        );
        let outcome = StepOutcome {
            loss,
            grad_norm,
            examples: tokens.len(),
            terms,
            summary,
        };
        (model, Some(outcome))
    }

    fn validate(&self, model: &MeshVae, step: usize) -> Option<ValLog> {
        validate(model, self.val, self.cfg, &self.device, step)
    }

    fn describe(v: &ValLog) -> String {
        format!(
            "step {}: val loss {:.4}, edge P/R/F1 {:.3}/{:.3}/{:.3} (best F1 {:.3} at tau {}), \
             mask acc {:.4}",
            v.step,
            v.val_loss,
            v.edge_precision,
            v.edge_recall,
            v.edge_f1,
            v.edge_f1_best_tau,
            v.best_tau,
            v.mask_accuracy
        )
    }
}

/// Trains a VAE on `train` (model-frame meshes), validating on `val`, writing checkpoints and
/// `metrics.jsonl` under `out_dir` ([`run_training`]). A checkpoint already in
/// `out_dir/checkpoint` with the same configuration is resumed: the run continues exactly as if
/// it had not stopped.
pub fn train_vae(
    cfg: &VaeTrainConfig,
    train: &[Mesh],
    val: &[Mesh],
    out_dir: &Path,
    device: &Device,
    observer: &mut dyn TrainObserver,
) -> Result<Trained<ValLog>, TrainError> {
    train_vae_from(cfg, None, train, val, out_dir, device, observer)
}

/// [`train_vae`] starting from `init` (trained weights of the same configuration) instead of
/// a seeded initialisation; a `decoder_only` configuration needs it. With `decoder_only` the
/// returned weights' encoder side is `init`'s, bit for bit (the EMA of a constant could
/// otherwise drift by rounding), and `init` may hold the encoder side alone: the decoder then
/// starts from the seeded initialisation (a decoder of another size on the same latents).
pub fn train_vae_from(
    cfg: &VaeTrainConfig,
    init: Option<&TensorMap>,
    train: &[Mesh],
    val: &[Mesh],
    out_dir: &Path,
    device: &Device,
    observer: &mut dyn TrainObserver,
) -> Result<Trained<ValLog>, TrainError> {
    cfg.validate()
        .map_err(|e| TrainError::Weights(WeightsError::Config(e)))?;
    if cfg.decoder_only && init.is_none() {
        return Err(TrainError::Weights(WeightsError::Config(
            "decoder_only: training the decoder alone needs trained weights to start from".into(),
        )));
    }
    let train: Vec<&Mesh> = train
        .iter()
        .filter(|m| !m.positions.is_empty() && m.positions.len() <= cfg.model.num_vertices)
        .collect();
    if train.is_empty() {
        return Err(TrainError::NoData(cfg.model.num_vertices));
    }
    let ad_device = device.clone().autodiff();
    let mut vae = seeded_init(MeshVae::new(&cfg.model, &ad_device), cfg.seed);
    if let Some(init) = init {
        // A decoder-only run may start a decoder of another size: `init` then holds the
        // encoder side alone, and the decoder starts from the seeded initialisation.
        let fresh_decoder = |name: &str| cfg.decoder_only && !is_encoder_side(name);
        vae = load_module_keeping(vae, init, &|_| false, &fresh_decoder)
            .map_err(TrainError::Weights)?;
    }
    let mut task = VaeTask {
        cfg,
        vertex_counts: train.iter().map(|m| m.positions.len()).collect(),
        train,
        val,
        batches: Vec::new(),
        batches_epoch: None,
        ad_device,
        device: device.clone(),
    };
    let mut trained = run_training(
        &mut task,
        cfg,
        &cfg.schedule(),
        vae,
        out_dir,
        device,
        observer,
    )?;
    if let (true, Some(init)) = (cfg.decoder_only, init) {
        for (name, tensor) in &init.tensors {
            if is_encoder_side(name) {
                trained.weights.tensors.insert(name.clone(), tensor.clone());
            }
        }
    }
    Ok(trained)
}

/// Per-channel mean and standard deviation of the posterior means over `meshes` (the
/// statistics a DiT normalises the latents by; written into the VAE's manifest).
pub fn latent_statistics(
    vae: &MeshVae,
    cfg: &VaeConfig,
    meshes: &[Mesh],
    device: &Device,
) -> (Vec<f32>, Vec<f32>) {
    let d = cfg.latent_dim;
    let (mut sum, mut sq, mut count) = (vec![0f64; d], vec![0f64; d], 0f64);
    let mut tokens: Vec<_> = meshes
        .iter()
        .enumerate()
        .filter_map(|(i, m)| build_tokens(m, &cfg.tokens_for(m.positions.len()), i as u64).ok())
        .collect();
    // One length per forward pass (length buckets).
    tokens.sort_by_key(|t| t.mask.len());
    let chunks = tokens
        .chunk_by(|a, b| a.mask.len() == b.mask.len())
        .flat_map(|same| same.chunks(16));
    for chunk in chunks {
        let batch = make_batch(chunk, NonEdgeWeights::uniform(1.0), device);
        let mean = vae.encode(batch.features, &mut Trace::default()).mean;
        let values = mean
            .try_into_data()
            .expect("readback")
            .convert::<f32>()
            .try_into_vec::<f32>()
            .expect("f32");
        for row in values.chunks_exact(d) {
            for (c, &v) in row.iter().enumerate() {
                sum[c] += v as f64;
                sq[c] += (v as f64) * (v as f64);
            }
            count += 1.0;
        }
    }
    let mean: Vec<f32> = sum.iter().map(|s| (s / count.max(1.0)) as f32).collect();
    let std = sq
        .iter()
        .zip(&mean)
        .map(|(q, &m)| ((q / count.max(1.0) - (m as f64).powi(2)).max(1e-12).sqrt()) as f32)
        .collect();
    (mean, std)
}
