//! `meshflow train vae|dit` and `meshflow bench train-vae`: train the MeshVAE on built shards,
//! or the DiT on a trained VAE's latents, and write shippable weights (safetensors + config +
//! manifest with sha256, the command, data version, wall time, machine, and for the VAE the
//! latent statistics the DiT normalises by).

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Result, bail};
use clap::{Args, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use meshflow::Mesh;
use meshflow::data::dataset::Split;
use meshflow::data::shards::load_split;
use meshflow::device::{BackendKind, device};
use meshflow::train::TrainObserver;
use meshflow::train::presets;
use meshflow::train::profile::profile_report;
use meshflow::train::ship::{DitRun, RunError, RunSummary, RunTarget, VaeRun};

use crate::args::BackendArg;
use crate::files::write_json;
use crate::weights::weights_dir;
use crate::{BadInput, bad_input};

#[derive(Subcommand)]
pub enum TrainCommand {
    /// Trains the MeshVAE on the train split of a shard build; resumes from OUT/checkpoint.
    Vae(TrainVaeArgs),
    /// Trains the DiT on latents of a trained VAE; resumes from OUT/checkpoint.
    Dit(TrainDitArgs),
}

/// What every training run takes: its data, its folder, its backend and when it stops.
#[derive(Args)]
pub struct RunArgs {
    /// The build's output folder [default: ~/.cache/meshflow/data/shards].
    #[arg(long)]
    data: Option<PathBuf>,
    /// Run folder: checkpoint/, metrics.jsonl and the final weights.
    #[arg(short, long)]
    out: PathBuf,
    #[command(flatten)]
    backend: BackendArg,
    /// Stop after this many seconds of wall time (checkpointed and validated, weights
    /// written), e.g. for sweep arms with equal budgets.
    #[arg(long)]
    time_budget_s: Option<f64>,
    /// Stop at this step (checkpointed and validated, weights written) with the schedule
    /// unchanged, so the same command without it resumes: snapshots along one run.
    #[arg(long)]
    stop_at_step: Option<usize>,
    /// Compute each batch's gradient from N sub-batches run at once on the CPU's threads
    /// (overrides the configuration's `data_parallel`; 1 = the whole batch in one pass): the
    /// same gradient up to float rounding, about 1.6x the steps per second with 2 on two
    /// cores. Recorded in the checkpoint and the manifest like the rest of the configuration.
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
    data_parallel: Option<u64>,
}

impl RunArgs {
    /// Runs `train` into the run folder with a progress bar of `steps` steps that stops the
    /// run as asked (`--time-budget-s`, `--stop-at-step`).
    fn train_with_bar(
        &self,
        steps: usize,
        train: impl FnOnce(&RunTarget, &mut BarObserver) -> Result<RunSummary, RunError>,
    ) -> Result<RunSummary> {
        let target = RunTarget {
            out: &self.out,
            backend: self.backend.kind,
            command: std::env::args().collect::<Vec<_>>().join(" "),
        };
        let mut bar = BarObserver::new(steps, self.time_budget_s, self.stop_at_step);
        let done = train(&target, &mut bar).map_err(run_error)?;
        bar.bar.finish();
        Ok(done)
    }
}

#[derive(Args)]
pub struct TrainVaeArgs {
    #[command(flatten)]
    run: RunArgs,
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
    /// Use at most this many training meshes (0 = all).
    #[arg(long, default_value_t = 0)]
    limit: usize,
    /// Validation meshes evaluated at each evaluation step.
    #[arg(long, default_value_t = 64)]
    val_meshes: usize,
    /// Start from this weights folder's VAE (same model configuration) instead of a seeded
    /// initialisation; required by a `decoder_only` configuration, whose result keeps this
    /// VAE's encoder and latent statistics, so a DiT trained on them still fits.
    #[arg(long)]
    init: Option<PathBuf>,
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

pub fn bench_train_vae(args: BenchTrainVaeArgs) -> Result<()> {
    let cfg = presets::vae_config(&args.config).map_err(bad_input)?;
    cfg.validate()
        .map_err(|e| bad_input(format!("configuration: {e}")))?;
    let data = crate::data::shards_dir(args.data);
    let mut meshes: Vec<Mesh> = load_split(&data, Split::Train)?
        .into_iter()
        .filter(|m| m.positions.len() <= cfg.model.num_vertices)
        .collect();
    meshes.truncate(args.limit.max(1));
    let device = device(BackendKind::Cpu).map_err(|e| anyhow::anyhow!(e))?;
    let report = profile_report(&cfg, &args.config, &meshes, &device, args.steps)?;
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
    write_json(&args.output, &report)?;
    println!("-> {}", args.output.display());
    Ok(())
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

pub fn run(which: TrainCommand) -> Result<()> {
    match which {
        TrainCommand::Vae(args) => train_vae_command(args),
        TrainCommand::Dit(args) => train_dit_command(args),
    }
}

fn train_vae_command(args: TrainVaeArgs) -> Result<()> {
    let mut cfg = presets::vae_config(&args.config).map_err(bad_input)?;
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
    if let Some(n) = args.run.data_parallel {
        cfg.data_parallel = n as usize;
    }
    let data = crate::data::shards_dir(args.run.data.clone());
    let device = args.run.backend.device()?;
    let run = VaeRun::prepare(
        cfg,
        &data,
        args.limit,
        args.val_meshes,
        args.init.as_deref(),
        &device,
    )
    .map_err(run_error)?;
    let cfg = &run.config;
    eprintln!(
        "training MeshVAE on {} meshes (<= {} vertices), validating on {}, {} steps of {} on {}",
        run.train.len(),
        cfg.model.num_vertices,
        run.val.len(),
        cfg.steps,
        cfg.batch_size,
        args.run.backend.kind.name()
    );
    let done = args
        .run
        .train_with_bar(cfg.steps, |target, bar| run.train(target, &device, bar))?;
    println!(
        "{} steps in {:.0} s -> {}",
        done.steps,
        done.wall_s,
        done.weights.display()
    );
    Ok(())
}

/// A run error as the CLI reports it (exit status 2 for a request that cannot be met).
fn run_error(e: RunError) -> anyhow::Error {
    if e.is_bad_input() {
        bad_input(e)
    } else {
        anyhow::anyhow!(e)
    }
}

#[derive(Args)]
pub struct TrainDitArgs {
    #[command(flatten)]
    run: RunArgs,
    /// The trained VAE (vae.safetensors, vae.manifest.json) [default: the shipped weights,
    /// found from any folder: see README.md].
    #[arg(long)]
    vae: Option<PathBuf>,
    /// A JSON file with a full DiT training configuration [default: the shipped recipe,
    /// weights/dit.train.json, sized to the VAE's latents].
    #[arg(long)]
    config: Option<PathBuf>,
    #[arg(long)]
    steps: Option<usize>,
    /// Start from this folder's trained DiT (dit.safetensors, dit.manifest.json; same
    /// configuration, trained on this VAE's latents) instead of a seeded initialisation: a
    /// fine-tune.
    #[arg(long)]
    init: Option<PathBuf>,
}

fn train_dit_command(args: TrainDitArgs) -> Result<()> {
    let device = args.run.backend.device()?;
    let vae = weights_dir(args.vae.as_deref())?;
    let config = match &args.config {
        Some(path) => Some(presets::dit_config(path).map_err(bad_input)?),
        None => None,
    };
    let data = crate::data::shards_dir(args.run.data.clone());
    let mut run = DitRun::prepare(
        config,
        args.steps,
        &vae,
        &data,
        args.init.as_deref(),
        &device,
    )
    .map_err(run_error)?;
    if let Some(n) = args.run.data_parallel {
        run.config.data_parallel = n as usize;
    }
    eprintln!(
        "encoded {} train and {} validation meshes in {:.1} s; training the DiT for {} steps",
        run.train.len(),
        run.val.len(),
        run.encode_s,
        run.config.steps
    );
    let done = args.run.train_with_bar(run.config.steps, |target, bar| {
        run.train(target, &device, bar)
    })?;
    println!("{} steps -> {}", done.steps, done.weights.display());
    Ok(())
}
