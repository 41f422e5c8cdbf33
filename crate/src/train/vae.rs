//! MeshVAE training: batches of vertex tokens, the paper's losses, AdamW with warm-up and
//! cosine decay, optional EMA, checkpoints that resume exactly, and a JSON-lines metrics log.
//!
//! Losses (DESIGN.md section 2), each averaged per mesh and then over the batch:
//! - mask: binary cross-entropy of the mask logits against real/padding, over all N tokens;
//! - position and normal: squared error over real vertices (mean over vertices and the 3 axes);
//! - adjacency: `(sum_E softplus(tau - d) + lambda_neg sum_notE softplus(d - tau)) / |E|`,
//!   which is `L_pos + lambda_neg (|notE| / |E|) L_neg` with both means written out; pairs are
//!   real i < j;
//! - KL: `0.5 mean(mu^2 + exp(logvar) - 1 - logvar)` over latent channels, weight 1e-3.

use std::io::Write;
use std::path::Path;
use std::time::Instant;

use burn::module::Module;
use burn::optim::GradientsParams;
use burn::tensor::activation::softplus;
use burn::tensor::{Device, Tensor, TensorData};
use serde::{Deserialize, Serialize};

use super::adamw::{AdamW, AdamWState};
use super::{TrainError, TrainObserver, ema_update, open_run, scalar, warmup_cosine};
use crate::Mesh;
use crate::augment::{AugmentOptions, augment_mesh};
use crate::metrics::edge_scores;
use crate::model::sampler::normal_noise;
use crate::model::weights::{TensorMap, WeightsError, load_module};
use crate::model::{MeshVae, Trace, VaeConfig, module_tensors, seeded_init, spacetime_distances};
use crate::rng::Rng;
use crate::tokens::{VertexTokens, build_tokens};

/// Everything that defines a training run; saved in the checkpoint and the weights manifest.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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
    /// `[B, N, N]`: 1 for real pairs i < j that are not edges.
    pub non_edges: Tensor<3>,
}

/// Stacks token sets (all with the same N) into a batch.
pub fn make_batch(tokens: &[VertexTokens], device: &Device) -> VaeBatch {
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
        let plane = &mut non_edges[k * n * n..(k + 1) * n * n];
        for i in 0..t.num_real {
            plane[i * n + i + 1..i * n + t.num_real].fill(1.0);
        }
        for &[i, j] in &t.edges {
            let at = k * n * n + i as usize * n + j as usize;
            edges[at] = 1.0;
            non_edges[at] = 0.0;
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
    }
}

/// The loss terms of one batch, as scalars (`[1]` tensors).
pub struct VaeLosses {
    pub total: Tensor<1>,
    pub mask: Tensor<1>,
    pub position: Tensor<1>,
    pub normal: Tensor<1>,
    pub adjacency: Tensor<1>,
    pub kl: Tensor<1>,
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
    let posterior = vae.encode(batch.features.clone(), &mut Trace::default());
    let std = (posterior.logvar.clone() * 0.5).exp();
    let z = posterior.mean.clone() + std * noise;
    let out = vae.decode(z, &mut Trace::default());

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

    let tau = cfg.model.tau as f64;
    let d = spacetime_distances(out.edge_embeddings);
    let pos = per_mesh(softplus(d.clone().neg() + tau, 1.0) * batch.edges.clone());
    let neg = per_mesh(softplus(d - tau, 1.0) * batch.non_edges.clone());
    let num_edges = per_mesh(batch.edges.clone()).clamp_min(1.0);
    let adjacency = ((pos + neg * cfg.lambda_neg) / num_edges).mean();

    let kl = ((posterior.mean.square() + posterior.logvar.clone().exp() - 1.0 - posterior.logvar)
        * 0.5)
        .mean();
    let total = mask.clone()
        + position.clone() * cfg.position_weight
        + normal.clone() * cfg.normal_weight
        + adjacency.clone()
        + kl.clone() * cfg.kl_weight;
    VaeLosses {
        total,
        mask,
        position,
        normal,
        adjacency,
        kl,
    }
}

/// Progress of one step, for a progress bar and the metrics log.
#[derive(Clone, Debug, Serialize)]
pub struct StepLog {
    pub step: usize,
    pub lr: f64,
    pub loss: f64,
    pub mask: f64,
    pub position: f64,
    pub normal: f64,
    pub adjacency: f64,
    pub kl: f64,
    pub grad_norm: f64,
    pub meshes_per_s: f64,
    pub elapsed_s: f64,
}

/// Validation figures: losses with the posterior mean, and edge precision/recall/F1 of the
/// thresholded spacetime distances among the real vertices.
#[derive(Clone, Debug, Serialize)]
pub struct ValLog {
    pub step: usize,
    pub val_loss: f64,
    pub val_position: f64,
    pub val_adjacency: f64,
    pub edge_precision: f64,
    pub edge_recall: f64,
    pub edge_f1: f64,
    pub mask_accuracy: f64,
}

#[derive(Serialize, Deserialize)]
struct TrainState {
    config: VaeTrainConfig,
    /// Steps done.
    step: usize,
    rng: u64,
    /// Position in the shuffled epoch order.
    cursor: usize,
    epoch: usize,
}

/// What training produced.
pub struct TrainedVae {
    /// The weights to ship (the EMA when enabled).
    pub weights: TensorMap,
    pub steps: usize,
    pub last_val: Option<ValLog>,
}

/// Tokens of `mesh` for the model (None when it has too many vertices or is invalid).
fn tokens_of(mesh: &Mesh, cfg: &VaeConfig, seed: u64) -> Option<VertexTokens> {
    build_tokens(mesh, &cfg.tokens(), seed).ok()
}

/// Validation on up to `limit` meshes, batch by batch, with the posterior mean.
pub fn validate(
    vae: &MeshVae,
    meshes: &[Mesh],
    cfg: &VaeTrainConfig,
    device: &Device,
    step: usize,
) -> Option<ValLog> {
    let tokens: Vec<VertexTokens> = meshes
        .iter()
        .enumerate()
        .filter_map(|(i, m)| tokens_of(m, &cfg.model, i as u64))
        .collect();
    if tokens.is_empty() {
        return None;
    }
    let (mut loss, mut position, mut adjacency, mut batches) = (0.0, 0.0, 0.0, 0.0);
    let (mut tp, mut fp, mut fn_, mut mask_ok, mut mask_total) =
        (0usize, 0usize, 0usize, 0usize, 0usize);
    let latents = cfg.model.num_latents;
    for chunk in tokens.chunks(cfg.batch_size.max(1)) {
        let batch = make_batch(chunk, device);
        let zeros = Tensor::zeros([chunk.len(), latents, cfg.model.latent_dim], device);
        let l = vae_losses(vae, &batch, zeros, cfg);
        loss += scalar(l.total);
        position += scalar(l.position);
        adjacency += scalar(l.adjacency);
        batches += 1.0;
        let posterior = vae.encode(batch.features, &mut Trace::default());
        let out = vae.decode(posterior.mean, &mut Trace::default());
        let d = spacetime_distances(out.edge_embeddings)
            .try_into_data()
            .ok()?
            .convert::<f32>()
            .try_into_vec::<f32>()
            .ok()?;
        let logits = out
            .mask_logits
            .try_into_data()
            .ok()?
            .convert::<f32>()
            .try_into_vec::<f32>()
            .ok()?;
        let n = cfg.model.num_vertices;
        for (k, t) in chunk.iter().enumerate() {
            let mut predicted = Vec::new();
            for i in 0..t.num_real {
                for j in i + 1..t.num_real {
                    if d[k * n * n + i * n + j] > cfg.model.tau {
                        predicted.push([i as u32, j as u32]);
                    }
                }
            }
            let s = edge_scores(&predicted, &t.edges);
            tp += s.true_positives;
            fp += s.predicted - s.true_positives;
            fn_ += s.actual - s.true_positives;
            for i in 0..n {
                mask_ok += ((logits[k * n + i] > 0.0) == t.mask[i]) as usize;
            }
            mask_total += n;
        }
    }
    let precision = tp as f64 / (tp + fp).max(1) as f64;
    let recall = tp as f64 / (tp + fn_).max(1) as f64;
    let f1 = if precision + recall > 0.0 {
        2.0 * precision * recall / (precision + recall)
    } else {
        0.0
    };
    Some(ValLog {
        step,
        val_loss: loss / batches,
        val_position: position / batches,
        val_adjacency: adjacency / batches,
        edge_precision: precision,
        edge_recall: recall,
        edge_f1: f1,
        mask_accuracy: mask_ok as f64 / mask_total.max(1) as f64,
    })
}

/// Trains a VAE on `train` (model-frame meshes), validating on `val`, writing checkpoints and
/// `metrics.jsonl` under `out_dir`. A checkpoint already in `out_dir/checkpoint` with the same
/// configuration is resumed: the run continues exactly as if it had not stopped.
pub fn train_vae(
    cfg: &VaeTrainConfig,
    train: &[Mesh],
    val: &[Mesh],
    out_dir: &Path,
    device: &Device,
    observer: &mut dyn TrainObserver,
) -> Result<TrainedVae, TrainError> {
    cfg.model
        .validate()
        .map_err(|e| TrainError::Weights(WeightsError::Config(e)))?;
    let train: Vec<&Mesh> = train
        .iter()
        .filter(|m| !m.positions.is_empty() && m.positions.len() <= cfg.model.num_vertices)
        .collect();
    if train.is_empty() {
        return Err(TrainError::NoData(cfg.model.num_vertices));
    }
    let (paths, mut log) = open_run(out_dir)?;
    let ad_device = device.clone().autodiff();

    let mut vae = seeded_init(MeshVae::new(&cfg.model, &ad_device), cfg.seed);
    let optim = AdamW::new(cfg.weight_decay, cfg.grad_clip);
    let mut optim_state = AdamWState::default();
    let mut state = TrainState {
        config: cfg.clone(),
        step: 0,
        rng: cfg.seed,
        cursor: 0,
        epoch: 0,
    };
    let mut ema: Option<TensorMap> = None;
    if let Some(r) = paths.restore(
        |saved: &TrainState| saved.config == *cfg,
        |saved| saved.step,
        cfg.ema_decay.is_some(),
        device,
    )? {
        vae = load_module(vae, &r.model, &|_| false)?;
        optim_state = r.optim;
        ema = r.ema;
        state = r.state;
    }
    if cfg.ema_decay.is_some() && ema.is_none() {
        ema = Some(module_tensors(&vae));
    }

    let mut rng = Rng::new(state.rng);
    // The epoch order is a function of (seed, epoch), so resuming needs only the cursor.
    let order_for = |epoch: usize| {
        let mut order: Vec<usize> = (0..train.len()).collect();
        Rng::new(cfg.seed ^ (epoch as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15)).shuffle(&mut order);
        order
    };
    let mut order = order_for(state.epoch);
    let started = Instant::now();
    let mut last_val = None;
    let mut since_log = (Instant::now(), 0usize);
    while state.step < cfg.steps && !observer.stop() {
        let mut tokens = Vec::with_capacity(cfg.batch_size);
        while tokens.len() < cfg.batch_size {
            if state.cursor == order.len() {
                state.epoch += 1;
                state.cursor = 0;
                order = order_for(state.epoch);
            }
            let mesh = train[order[state.cursor]];
            state.cursor += 1;
            let mesh = if cfg.augment {
                let opts = AugmentOptions {
                    rotate: true,
                    scale_jitter: cfg.scale_jitter,
                    points: 0,
                };
                augment_mesh(mesh, &opts, &mut rng).0
            } else {
                mesh.clone()
            };
            if let Some(t) = tokens_of(&mesh, &cfg.model, rng.next_u64()) {
                tokens.push(t);
            }
        }
        let batch = make_batch(&tokens, &ad_device);
        let noise = normal_noise(
            &mut rng,
            [cfg.batch_size, cfg.model.num_latents, cfg.model.latent_dim],
            &ad_device,
        );
        let losses = vae_losses(&vae, &batch, noise, cfg);
        let grads = GradientsParams::from_grads(losses.total.backward(), &vae);
        let lr = cfg.lr_at(state.step);
        let (updated, grad_norm) = optim.step(&mut optim_state, vae, grads, lr);
        vae = updated;
        state.step += 1;
        let total = scalar(losses.total);
        if !total.is_finite() {
            return Err(TrainError::Diverged(total, state.step));
        }
        if let (Some(ema), Some(decay)) = (ema.as_mut(), cfg.ema_decay) {
            ema_update(ema, &module_tensors(&vae), decay);
        }
        since_log.1 += cfg.batch_size;
        let step_log = StepLog {
            step: state.step,
            lr,
            loss: total,
            mask: scalar(losses.mask),
            position: scalar(losses.position),
            normal: scalar(losses.normal),
            adjacency: scalar(losses.adjacency),
            kl: scalar(losses.kl),
            grad_norm,
            meshes_per_s: since_log.1 as f64 / since_log.0.elapsed().as_secs_f64().max(1e-9),
            elapsed_s: started.elapsed().as_secs_f64(),
        };
        if state.step.is_multiple_of(10) {
            since_log = (Instant::now(), 0);
        }
        writeln!(
            log,
            "{}",
            serde_json::to_string(&step_log).expect("serialisable")
        )?;
        observer.step(
            state.step,
            &format!(
                "loss {:.4} (adj {:.4}, pos {:.2e}) {:.1} meshes/s",
                step_log.loss, step_log.adjacency, step_log.position, step_log.meshes_per_s
            ),
        );
        let last = state.step == cfg.steps;
        if state.step.is_multiple_of(cfg.eval_every.max(1)) || last {
            let model = vae.valid();
            if let Some(v) = validate(&model, val, cfg, device, state.step) {
                writeln!(log, "{}", serde_json::to_string(&v).expect("serialisable"))?;
                observer.note(&format!(
                    "step {}: val loss {:.4}, edge P/R/F1 {:.3}/{:.3}/{:.3}, mask acc {:.4}",
                    v.step, v.val_loss, v.edge_precision, v.edge_recall, v.edge_f1, v.mask_accuracy
                ));
                last_val = Some(v);
            }
        }
        if state.step.is_multiple_of(cfg.checkpoint_every.max(1)) || last || observer.stop() {
            state.rng = rng.next_u64();
            rng = Rng::new(state.rng);
            paths.save(&module_tensors(&vae), &optim_state, ema.as_ref(), &state)?;
        }
    }
    let weights = ema.unwrap_or_else(|| module_tensors(&vae));
    Ok(TrainedVae {
        weights,
        steps: state.step,
        last_val,
    })
}
