//! DiT training by conditional flow matching on cached VAE latents.
//!
//! Each training mesh is encoded once with the shipped VAE (posterior mean), normalised by the
//! latent mean/std of the VAE's manifest, and stored with its latent tokens' RoPE positions
//! ([`crate::condition::latent_positions`]) and its vertex count. A step draws `t` from a
//! logit-normal (`sigmoid(N(0, 1))`), forms `x_t = (1 - t) x_0 + t eps` and regresses the
//! velocity `eps - x_0` with mean squared error (DESIGN.md section 2).

use std::io::Write;
use std::path::Path;
use std::time::Instant;

use burn::module::Module;
use burn::optim::GradientsParams;
use burn::tensor::{Device, Tensor, TensorData};
use serde::{Deserialize, Serialize};

use super::adamw::{AdamW, AdamWState};
use super::{TrainError, TrainObserver, ema_update, open_run, scalar, warmup_cosine};
use crate::Mesh;
use crate::condition::{latent_positions, vertex_condition};
use crate::model::dit::{Dit, DitConfig, Rope};
use crate::model::sampler::normal_noise;
use crate::model::weights::{TensorMap, WeightsError, load_module};
use crate::model::{MeshVae, Trace, VaeConfig, module_tensors, seeded_init};
use crate::rng::Rng;
use crate::tokens::build_tokens;
use crate::train::vae::make_batch;

/// One cached training example.
#[derive(Clone, Debug, PartialEq)]
pub struct LatentExample {
    /// `num_latents x latent_dim`, normalised.
    pub latents: Vec<f32>,
    /// RoPE voxel position of each latent token.
    pub positions: Vec<[f32; 3]>,
    pub vertex_count: usize,
}

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
    let tokens: Vec<_> = meshes
        .iter()
        .enumerate()
        .filter_map(|(i, m)| build_tokens(m, &cfg.tokens(), i as u64).ok())
        .collect();
    let (l, d) = (cfg.num_latents, cfg.latent_dim);
    let mut out = Vec::with_capacity(tokens.len());
    for chunk in tokens.chunks(16) {
        let batch = make_batch(chunk, device);
        let z = vae.encode(batch.features, &mut Trace::default()).mean;
        let values = z
            .into_data()
            .convert::<f32>()
            .try_into_vec::<f32>()
            .expect("f32 latents");
        for (k, t) in chunk.iter().enumerate() {
            let latents = values[k * l * d..(k + 1) * l * d]
                .iter()
                .enumerate()
                .map(|(i, &v)| (v - mean[i % d]) / std[i % d].max(1e-6))
                .collect();
            out.push(LatentExample {
                latents,
                positions: latent_positions(t, cfg.merge_ratio()),
                vertex_count: t.num_real,
            });
        }
    }
    out
}

/// Everything that defines a DiT training run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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
        }
    }
}

/// A batch of flow-matching inputs and targets.
struct FlowBatch {
    x_t: Tensor<3>,
    target: Tensor<3>,
    t: Vec<f32>,
    cond: Tensor<2>,
    rope: Rope,
}

fn flow_batch(
    examples: &[&LatentExample],
    cfg: &DitConfig,
    rng: &mut Rng,
    device: &Device,
) -> FlowBatch {
    let (b, l, d) = (examples.len(), cfg.num_latents, cfg.latent_dim);
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
    let tt = Tensor::<1>::from_data(TensorData::new(t.clone(), [b]), device).reshape([b, 1, 1]);
    let x_t = x0.clone() * (tt.clone().neg() + 1.0) + eps.clone() * tt;
    let cond: Vec<f32> = examples
        .iter()
        .map(|e| vertex_condition(e.vertex_count, l))
        .collect();
    let positions: Vec<[f32; 3]> = examples
        .iter()
        .flat_map(|e| e.positions.iter().copied())
        .collect();
    FlowBatch {
        x_t,
        target: eps - x0,
        t,
        cond: Tensor::from_data(TensorData::new(cond, [b, 1]), device),
        rope: Rope::new(&positions, b, cfg.width / cfg.num_heads, device),
    }
}

/// Mean squared error of the predicted velocity.
fn flow_loss(dit: &Dit, batch: &FlowBatch) -> Tensor<1> {
    let v = dit.forward(
        batch.x_t.clone(),
        &batch.t,
        batch.cond.clone(),
        &batch.rope,
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
    for chunk in val.chunks(cfg.batch_size.max(1)) {
        let refs: Vec<&LatentExample> = chunk.iter().collect();
        let batch = flow_batch(&refs, &cfg.model, &mut rng, device);
        sum += scalar(flow_loss(dit, &batch)) * chunk.len() as f64;
        n += chunk.len() as f64;
    }
    sum / n.max(1.0)
}

#[derive(Serialize, Deserialize)]
struct DitState {
    config: DitTrainConfig,
    step: usize,
    rng: u64,
}

#[derive(Serialize)]
struct DitStepLog {
    step: usize,
    lr: f64,
    loss: f64,
    grad_norm: f64,
    examples_per_s: f64,
    elapsed_s: f64,
}

/// Trains the DiT on cached latents, with checkpoints and `metrics.jsonl` under `out_dir`;
/// resumes from `out_dir/checkpoint` when its configuration matches. Returns the weights to
/// ship (the EMA when enabled) and the last validation loss.
pub fn train_dit(
    cfg: &DitTrainConfig,
    train: &[LatentExample],
    val: &[LatentExample],
    out_dir: &Path,
    device: &Device,
    observer: &mut dyn TrainObserver,
) -> Result<(TensorMap, usize, Option<f64>), TrainError> {
    cfg.model
        .validate()
        .map_err(|e| TrainError::Weights(WeightsError::Config(e)))?;
    let shape = cfg.model.num_latents * cfg.model.latent_dim;
    let train: Vec<&LatentExample> = train.iter().filter(|e| e.latents.len() == shape).collect();
    if train.is_empty() {
        return Err(TrainError::NoData(cfg.model.num_latents));
    }
    let (paths, mut log) = open_run(out_dir)?;
    let ad_device = device.clone().autodiff();
    let mut dit = seeded_init(Dit::new(&cfg.model, &ad_device), cfg.seed);
    let optim = AdamW::new(cfg.weight_decay, cfg.grad_clip);
    let mut optim_state = AdamWState::default();
    let mut state = DitState {
        config: cfg.clone(),
        step: 0,
        rng: cfg.seed,
    };
    let mut ema = None;
    if let Some(r) = paths.restore(
        |saved: &DitState| saved.config == *cfg,
        |saved| saved.step,
        cfg.ema_decay.is_some(),
        device,
    )? {
        dit = load_module(dit, &r.model, &|_| false)?;
        optim_state = r.optim;
        ema = r.ema;
        state = r.state;
    }
    if cfg.ema_decay.is_some() && ema.is_none() {
        ema = Some(module_tensors(&dit));
    }
    let mut rng = Rng::new(state.rng);
    let started = Instant::now();
    let mut last_val = None;
    while state.step < cfg.steps && !observer.stop() {
        let batch: Vec<&LatentExample> = (0..cfg.batch_size)
            .map(|_| train[rng.below(train.len())])
            .collect();
        let fb = flow_batch(&batch, &cfg.model, &mut rng, &ad_device);
        let loss = flow_loss(&dit, &fb);
        let grads = GradientsParams::from_grads(loss.backward(), &dit);
        let lr = warmup_cosine(
            state.step,
            cfg.learning_rate,
            cfg.warmup_steps,
            cfg.steps,
            cfg.final_lr_ratio,
        );
        let (updated, grad_norm) = optim.step(&mut optim_state, dit, grads, lr);
        dit = updated;
        state.step += 1;
        let loss = scalar(loss);
        if !loss.is_finite() {
            return Err(TrainError::Diverged(loss, state.step));
        }
        if let (Some(ema), Some(decay)) = (ema.as_mut(), cfg.ema_decay) {
            ema_update(ema, &module_tensors(&dit), decay);
        }
        let elapsed = started.elapsed().as_secs_f64();
        let line = DitStepLog {
            step: state.step,
            lr,
            loss,
            grad_norm,
            examples_per_s: (state.step * cfg.batch_size) as f64 / elapsed.max(1e-9),
            elapsed_s: elapsed,
        };
        writeln!(
            log,
            "{}",
            serde_json::to_string(&line).expect("serialisable")
        )?;
        observer.step(
            state.step,
            &format!("loss {loss:.4}, grad norm {grad_norm:.2}"),
        );
        let last = state.step == cfg.steps;
        if (state.step.is_multiple_of(cfg.eval_every.max(1)) || last) && !val.is_empty() {
            let v = validate_dit(&dit.valid(), cfg, val, device);
            writeln!(
                log,
                "{}",
                serde_json::json!({"step": state.step, "val_loss": v})
            )?;
            observer.note(&format!("step {}: validation flow loss {v:.4}", state.step));
            last_val = Some(v);
        }
        if state.step.is_multiple_of(cfg.checkpoint_every.max(1)) || last || observer.stop() {
            state.rng = rng.next_u64();
            rng = Rng::new(state.rng);
            paths.save(&module_tensors(&dit), &optim_state, ema.as_ref(), &state)?;
        }
    }
    let weights = ema.unwrap_or_else(|| module_tensors(&dit));
    Ok((weights, state.step, last_val))
}
