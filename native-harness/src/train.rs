//! `meshflow train vae`: trains the MeshVAE on built shards and writes shippable weights
//! (safetensors + config + manifest with sha256, the command, data version, wall time, machine
//! and the latent statistics the DiT normalises by).

use std::fs;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use clap::{Args, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use meshflow::Mesh;
use meshflow::data::dataset::Split;
use meshflow::device::{BackendKind, device};
use meshflow::model::tokens::build_tokens;
use meshflow::model::{MeshVae, TensorMap, Trace, VaeConfig, load_module};
use meshflow::pipeline::shipped::{Provenance, VaeManifest, sha256_hex};
use meshflow::train::TrainObserver;
use meshflow::train::vae::{VaeTrainConfig, make_batch, train_vae_from};
use serde::Serialize;

use crate::BadInput;
use meshflow::data::shards::load_split;

#[derive(Subcommand)]
pub enum TrainCommand {
    /// Trains the MeshVAE on the train split of a shard build; resumes from OUT/checkpoint.
    Vae(TrainVaeArgs),
    /// Trains the DiT on latents of a trained VAE; resumes from OUT/checkpoint.
    Dit(crate::train_dit::TrainDitArgs),
}

#[derive(Args)]
pub struct TrainVaeArgs {
    /// The build's output folder [default: ~/.cache/meshflow/data/shards].
    #[arg(long)]
    data: Option<PathBuf>,
    /// Run folder: checkpoint/, metrics.jsonl and the final weights.
    #[arg(short, long)]
    out: PathBuf,
    /// A size preset (`ship`, `tiny`) or a JSON file with a full training configuration.
    #[arg(long, default_value = "ship")]
    config: String,
    /// Override the number of optimiser steps.
    #[arg(long)]
    steps: Option<usize>,
    #[arg(long)]
    batch_size: Option<usize>,
    #[arg(long)]
    seed: Option<u64>,
    #[arg(long, default_value = "cpu", value_parser = crate::train::backend_parser())]
    backend: BackendKind,
    /// Use at most this many training meshes (0 = all).
    #[arg(long, default_value_t = 0)]
    limit: usize,
    /// Validation meshes evaluated at each evaluation step.
    #[arg(long, default_value_t = 64)]
    val_meshes: usize,
    /// Stop after this many seconds of wall time (checkpointed and validated, weights
    /// written), e.g. for sweep arms with equal budgets.
    #[arg(long)]
    time_budget_s: Option<f64>,
    /// Stop at this step (checkpointed and validated, weights written) with the schedule
    /// unchanged, so the same command without it resumes: snapshots along one run.
    #[arg(long)]
    stop_at_step: Option<usize>,
    /// Start from this weights folder's VAE (same model configuration) instead of a seeded
    /// initialisation; required by a `decoder_only` configuration, whose result keeps this
    /// VAE's encoder and latent statistics, so a DiT trained on them still fits.
    #[arg(long)]
    init: Option<PathBuf>,
}

/// The `--backend` values (the library's [`BackendKind`]: cpu = Burn's flex backend, wgpu =
/// burn-wgpu over Vulkan, ndarray = Burn's ndarray backend in a build with `--features
/// ndarray`, for comparison with flex), listed in `--help`.
pub fn backend_parser() -> impl clap::builder::TypedValueParser<Value = BackendKind> {
    use clap::builder::TypedValueParser;
    clap::builder::PossibleValuesParser::new(BackendKind::ALL.map(BackendKind::name))
        .try_map(|name| name.parse::<BackendKind>())
}

/// `meshflow bench train-vae`.
#[derive(Args)]
pub struct BenchTrainVaeArgs {
    /// The build's output folder [default: ~/.cache/meshflow/data/shards].
    #[arg(long)]
    data: Option<PathBuf>,
    /// A size preset (`ship`, `tiny`) or a JSON file with a full training configuration.
    #[arg(long, default_value = "ship")]
    config: String,
    /// Steps timed after one warm-up step.
    #[arg(long, default_value_t = 10)]
    steps: usize,
    /// Training meshes cycled through (the first of the train split that fit).
    #[arg(long, default_value_t = 256)]
    limit: usize,
    /// Where to write the JSON.
    #[arg(short, long, default_value = "bench/train_vae_step.json")]
    output: PathBuf,
}

#[derive(Serialize)]
struct StepPart {
    part: String,
    ms: f64,
    share: f64,
}

#[derive(Serialize)]
struct StepReport {
    method: &'static str,
    cpu: String,
    threads: usize,
    config: String,
    batch_size: usize,
    num_vertices: usize,
    length_buckets: bool,
    step_ms: f64,
    meshes_per_s: f64,
    parts: Vec<StepPart>,
    /// Mean matrix-product FLOPs of a step: 3x the forward's (forward + two backward
    /// products).
    step_gflop: f64,
    achieved_gflop_per_s: f64,
    /// A 4096x256 @ 256x256 f32 matmul on the same backend, best of 5.
    matmul_peak_gflop_per_s: f64,
}

/// The CPU backend's matmul throughput on docs/design.md's reference shape, best of 5 runs.
fn matmul_peak(device: &meshflow::burn::tensor::Device) -> f64 {
    use meshflow::burn::tensor::{Distribution, Tensor};
    let a = Tensor::<2>::random([4096, 256], Distribution::Default, device);
    let b = Tensor::<2>::random([256, 256], Distribution::Default, device);
    let mut best = f64::INFINITY;
    for _ in 0..6 {
        let t = Instant::now();
        let _ = a.clone().matmul(b.clone()).into_data();
        best = best.min(t.elapsed().as_secs_f64());
    }
    2.0 * 4096.0 * 256.0 * 256.0 / best / 1e9
}

pub fn bench_train_vae(args: BenchTrainVaeArgs) -> Result<()> {
    let cfg = resolve_config(&args.config)?;
    cfg.validate()
        .map_err(|e| BadInput(format!("configuration: {e}")))?;
    let data = crate::data::shards_dir(args.data);
    let mut meshes: Vec<Mesh> = load_split(&data, Split::Train)?
        .into_iter()
        .filter(|m| m.positions.len() <= cfg.model.num_vertices)
        .collect();
    meshes.truncate(args.limit.max(1));
    let device = device(BackendKind::Cpu).map_err(|e| anyhow::anyhow!(e))?;
    let peak = matmul_peak(&device);
    let profile =
        meshflow::train::vae::profile_vae_step(&cfg, &meshes, &device, args.steps.max(1))?;
    let parts = &profile.parts;
    let step_s: f64 = parts.iter().map(|(_, s)| s).sum();
    let step_gflop = profile.flops_per_step / 1e9;
    let report = StepReport {
        method: "mean wall time per part over `steps` training steps after one warm-up step \
                 (profile_vae_step: the training loop's step and batching with laps; Burn's CPU \
                 backend runs eagerly); FLOPs are the matrix products only \
                 (VaeConfig::forward_flops at each batch's slot count, x 3)",
        cpu: crate::bench::cpu_name(),
        threads: std::thread::available_parallelism().map_or(1, |n| n.get()),
        config: args.config.clone(),
        batch_size: cfg.batch_size,
        num_vertices: cfg.model.num_vertices,
        length_buckets: cfg.model.length_buckets,
        step_ms: step_s * 1e3,
        meshes_per_s: profile.meshes_per_step / step_s,
        parts: parts
            .iter()
            .map(|(p, s)| StepPart {
                part: p.to_string(),
                ms: s * 1e3,
                share: s / step_s,
            })
            .collect(),
        step_gflop,
        achieved_gflop_per_s: step_gflop / step_s,
        matmul_peak_gflop_per_s: peak,
    };
    for p in &report.parts {
        println!("{:>42}: {:8.1} ms ({:4.1}%)", p.part, p.ms, p.share * 100.0);
    }
    println!(
        "step {:.0} ms = {:.2} meshes/s; {:.1} GFLOP per step = {:.1} GFLOP/s (matmul peak {:.1})",
        report.step_ms,
        report.meshes_per_s,
        report.step_gflop,
        report.achieved_gflop_per_s,
        report.matmul_peak_gflop_per_s
    );
    if let Some(dir) = args.output.parent().filter(|d| !d.as_os_str().is_empty()) {
        fs::create_dir_all(dir)?;
    }
    meshflow::io::write_atomic(
        &args.output,
        (serde_json::to_string_pretty(&report)? + "\n").as_bytes(),
    )?;
    println!("-> {}", args.output.display());
    Ok(())
}

/// The shipped configuration (`weights/vae.train.json`; a unit test keeps the two equal),
/// chosen by the fixed-budget capacity sweep in BENCHMARKS.md.
pub fn ship_config() -> VaeTrainConfig {
    let model = VaeConfig {
        num_vertices: 512,
        num_latents: 128,
        // 32 floats per latent token of 4 vertices: 8 (2 floats per vertex) was a bottleneck
        // that more steps did not make up for; 64 was no better at the same wall time.
        latent_dim: 32,
        width_encoder: 128,
        width_decoder: 128,
        num_heads: 4,
        num_layers_encoder: 3,
        num_layers_decoder: 3,
        max_degree: 16,
        // 16 frequencies (the paper's) were no better than 8 at the same wall time and 9%
        // slower per step.
        num_freqs: 8,
        edge_dim: 32,
        tau: 0.6,
        // Pad each mesh to its length bucket, not to 512: 2.4x the meshes per second.
        length_buckets: true,
    };
    let mut cfg = VaeTrainConfig::new(model);
    cfg.batch_size = 8;
    // About 55 minutes alone on the 2-core CPU (0.33 s per step with length buckets).
    cfg.steps = 10_000;
    // Positions in the [-1, 1] frame have squared errors ~1e-4 when good; weight them up so
    // they are not drowned by the adjacency term.
    cfg.position_weight = 10.0;
    // The paper's lambda_neg = 0.01 weighs each non-edge pair 1/100 of an edge, so the loss
    // is minimised by predicting an edge at p > 0.01: a 233M model trained for days separates
    // the pairs anyway, but at our size and budget it left edge precision at 0.05 (recall
    // 0.79) after 500 steps. 0.25 puts the decision near F1's optimum (BENCHMARKS.md).
    cfg.lambda_neg = 0.25;
    cfg.warmup_steps = 300;
    cfg.eval_every = 250;
    cfg.checkpoint_every = 250;
    cfg.ema_decay = Some(0.999);
    cfg
}

/// A seconds-scale configuration for tests and smoke runs.
pub fn tiny_config() -> VaeTrainConfig {
    let model = VaeConfig {
        num_vertices: 64,
        num_latents: 16,
        latent_dim: 8,
        width_encoder: 64,
        width_decoder: 64,
        num_heads: 4,
        num_layers_encoder: 1,
        num_layers_decoder: 1,
        max_degree: 8,
        num_freqs: 6,
        edge_dim: 32,
        tau: 0.6,
        length_buckets: false,
    };
    let mut cfg = VaeTrainConfig::new(model);
    cfg.batch_size = 4;
    cfg.steps = 300;
    cfg.warmup_steps = 20;
    cfg.learning_rate = 2e-3;
    cfg.eval_every = 100;
    cfg.checkpoint_every = 100;
    cfg.augment = false;
    cfg
}

fn resolve_config(name: &str) -> Result<VaeTrainConfig> {
    match name {
        "ship" => Ok(ship_config()),
        "tiny" => Ok(tiny_config()),
        path => {
            let text = fs::read_to_string(path)
                .map_err(|e| BadInput(format!("--config {path}: not a preset or file ({e})")))?;
            Ok(serde_json::from_str(&text)
                .map_err(|e| BadInput(format!("--config {path}: {e}")))?)
        }
    }
}

/// A progress bar for a training run, with an optional wall-clock budget after which the run
/// stops (checkpointed, so it can be resumed) and writes its weights.
pub struct BarObserver {
    pub bar: ProgressBar,
    pub deadline: Option<Instant>,
    /// Stop once the run has reached this step (the schedule keeps its full length).
    pub stop_at_step: Option<usize>,
    step: usize,
}

impl BarObserver {
    /// A bar of `steps` steps that stops the run after `budget_s` seconds or at step
    /// `stop_at_step` (when given).
    pub fn new(steps: usize, budget_s: Option<f64>, stop_at_step: Option<usize>) -> Self {
        let bar = ProgressBar::new(steps as u64);
        bar.set_style(
            ProgressStyle::with_template(
                "{elapsed_precise} [{bar:30}] {pos}/{len} ETA {eta} {msg}",
            )
            .expect("template"),
        );
        let deadline = budget_s.map(|s| Instant::now() + std::time::Duration::from_secs_f64(s));
        Self {
            bar,
            deadline,
            stop_at_step,
            step: 0,
        }
    }
}

impl TrainObserver for BarObserver {
    fn stop(&self) -> bool {
        self.deadline.is_some_and(|d| Instant::now() >= d)
            || self.stop_at_step.is_some_and(|s| self.step >= s)
    }

    fn step(&mut self, step: usize, summary: &str) {
        self.step = step;
        self.bar.set_position(step as u64);
        self.bar.set_message(summary.to_string());
    }

    fn note(&mut self, line: &str) {
        self.bar.println(line);
    }
}

pub fn machine_description() -> String {
    let cpu = fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|s| s.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    format!("{cpu}, {cores} threads")
}

/// Per-channel mean and standard deviation of the posterior means over `meshes`.
pub fn latent_statistics(
    vae: &MeshVae,
    cfg: &VaeConfig,
    meshes: &[Mesh],
    device: &meshflow::burn::tensor::Device,
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
        let batch = make_batch(chunk, device);
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

pub fn run(which: TrainCommand) -> Result<()> {
    match which {
        TrainCommand::Vae(args) => train_vae_command(args),
        TrainCommand::Dit(args) => crate::train_dit::run(args),
    }
}

fn train_vae_command(args: TrainVaeArgs) -> Result<()> {
    let mut cfg = resolve_config(&args.config)?;
    if let Some(s) = args.steps {
        cfg.steps = s;
    }
    if let Some(b) = args.batch_size {
        if b == 0 {
            bail!(BadInput("--batch-size must be at least 1".into()));
        }
        cfg.batch_size = b;
    }
    if let Some(s) = args.seed {
        cfg.seed = s;
    }
    cfg.validate()
        .map_err(|e| BadInput(format!("configuration: {e}")))?;
    let data = crate::data::shards_dir(args.data);
    let fits = |m: &Mesh| m.positions.len() <= cfg.model.num_vertices;
    let mut train: Vec<Mesh> = load_split(&data, Split::Train)?
        .into_iter()
        .filter(fits)
        .collect();
    if args.limit > 0 {
        train.truncate(args.limit);
    }
    let val: Vec<Mesh> = load_split(&data, Split::Val)?
        .into_iter()
        .filter(fits)
        .take(args.val_meshes)
        .collect();
    if train.is_empty() {
        bail!(BadInput(format!(
            "no training mesh in {} has at most {} vertices",
            data.display(),
            cfg.model.num_vertices
        )));
    }
    let device = device(args.backend).map_err(|e| anyhow::anyhow!(e))?;
    let init = match &args.init {
        Some(dir) => {
            // One read: the checked load (sha256, shapes) and the tensors come from the same bytes.
            let (manifest_bytes, bytes) = read_shipped(dir, "vae")?;
            let (_, manifest) =
                meshflow::pipeline::shipped::load_vae(&manifest_bytes, &bytes, &device)
                    .map_err(|e| BadInput(format!("--init {}: {e}", dir.display())))?;
            if manifest.model != cfg.model {
                bail!(BadInput(format!(
                    "--init {}: its VAE configuration differs from the training configuration's",
                    dir.display()
                )));
            }
            let map = TensorMap::from_safetensors(&bytes, "")?;
            Some((map, manifest))
        }
        None if cfg.decoder_only => bail!(BadInput(
            "configuration: decoder_only needs --init WEIGHTS (the VAE whose encoder it keeps)"
                .into()
        )),
        None => None,
    };
    fs::create_dir_all(&args.out)?;
    eprintln!(
        "training MeshVAE on {} meshes (<= {} vertices), validating on {}, {} steps of {} on {}",
        train.len(),
        cfg.model.num_vertices,
        val.len(),
        cfg.steps,
        cfg.batch_size,
        args.backend.name()
    );
    let started = Instant::now();
    let mut observer = BarObserver::new(cfg.steps, args.time_budget_s, args.stop_at_step);
    let trained = train_vae_from(
        &cfg,
        init.as_ref().map(|(map, _)| map),
        &train,
        &val,
        &args.out,
        &device,
        &mut observer,
    )?;
    observer.bar.finish();
    let wall = started.elapsed().as_secs_f64();

    let vae = load_module(MeshVae::new(&cfg.model, &device), &trained.weights, &|_| {
        false
    })?;
    // A decoder-only run keeps the encoder, so the statistics the DiT normalises by stay the
    // initial VAE's exactly (recomputing could differ in the last bit).
    let (latent_mean, latent_std) = match &init {
        Some((_, m)) if cfg.decoder_only => (m.latent_mean.clone(), m.latent_std.clone()),
        _ => latent_statistics(&vae, &cfg.model, &train, &device),
    };
    let bytes = trained.weights.to_safetensors(None);
    write_weights(
        &args.out,
        "vae",
        &bytes,
        &cfg.model,
        &VaeManifest {
            model: cfg.model.clone(),
            sha256: sha256_hex(&bytes),
            latent_mean,
            latent_std,
            latent_space_sha256: String::new(),
            provenance: Provenance {
                parameters: trained.weights.tensors.values().map(|(_, v)| v.len()).sum(),
                command: std::env::args().collect::<Vec<_>>().join(" "),
                training: serde_json::to_value(&cfg)?,
                init_sha256: init.as_ref().map(|(_, m)| m.sha256.clone()),
                data: data_version(&data),
                train_examples: train.len(),
                final_validation: serde_json::to_value(&trained.last_val)?,
                wall_time_s: wall,
                machine: machine_description(),
                backend: args.backend.name().into(),
            },
        },
    )?;
    println!(
        "{} steps in {:.0} s -> {}",
        trained.steps,
        wall,
        args.out.join("vae.safetensors").display()
    );
    Ok(())
}

/// A short identity of the shard build: the sha256 of its manifest.
pub fn data_version(dir: &Path) -> String {
    match fs::read(dir.join("manifest.jsonl")) {
        Ok(bytes) => format!("manifest.jsonl sha256 {}", sha256_hex(&bytes)),
        Err(_) => "unknown".into(),
    }
}

/// Writes `dir/NAME.safetensors`, `NAME.json` (the model configuration) and
/// `NAME.manifest.json`, each file whole or not at all; the manifest last, so a manifest never
/// names weights that are not there yet.
pub fn write_weights(
    dir: &Path,
    name: &str,
    bytes: &[u8],
    model: &impl Serialize,
    manifest: &impl Serialize,
) -> Result<()> {
    use meshflow::io::write_atomic;
    write_atomic(&dir.join(format!("{name}.safetensors")), bytes)?;
    write_atomic(
        &dir.join(format!("{name}.json")),
        serde_json::to_string_pretty(model)?.as_bytes(),
    )?;
    write_atomic(
        &dir.join(format!("{name}.manifest.json")),
        serde_json::to_string_pretty(manifest)?.as_bytes(),
    )?;
    Ok(())
}

/// Reads `dir/NAME.manifest.json` and `dir/NAME.safetensors`.
pub fn read_shipped(dir: &Path, name: &str) -> Result<(Vec<u8>, Vec<u8>)> {
    let read = |file: String| {
        let path = dir.join(file);
        fs::read(&path).with_context(|| format!("cannot read {}", path.display()))
    };
    Ok((
        read(format!("{name}.manifest.json"))?,
        read(format!("{name}.safetensors"))?,
    ))
}

/// Loads the VAE of a weights folder (sha256, configuration and shapes checked).
pub fn load_weights(
    dir: &Path,
    device: &meshflow::burn::tensor::Device,
) -> Result<(MeshVae, VaeManifest)> {
    let (manifest, weights) = read_shipped(dir, "vae")?;
    meshflow::pipeline::shipped::load_vae(&manifest, &weights, device)
        .map_err(|e| BadInput(format!("{}: {e}", dir.display())).into())
}

#[cfg(test)]
mod tests {
    /// `weights/vae.train.json` is what the `ship` preset trains, so the documented command
    /// and the preset cannot drift apart.
    #[test]
    fn the_ship_preset_is_the_shipped_training_config() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../weights/vae.train.json");
        let shipped: meshflow::train::vae::VaeTrainConfig =
            serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap();
        assert_eq!(shipped, super::ship_config());
    }
}
