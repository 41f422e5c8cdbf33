//! The one training loop both models use: learning-rate schedule, clipped AdamW, EMA on the
//! device, checkpoints that resume exactly (a killed run's log is trimmed back to its last
//! checkpoint), a JSON-lines metrics file, validation cadence and progress. A model plugs in
//! its step and its validation through [`Task`].

use std::io::Write;
use std::path::Path;
use std::time::Instant;

use burn::module::Module;
use burn::tensor::Device;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use super::adamw::{AdamW, AdamWState};
use super::{DeviceEma, TrainError, TrainObserver, open_run, resume_metrics, warmup_cosine};
use crate::model::weights::{TensorMap, load_module, module_tensors};
use crate::rng::Rng;

/// The schedule and bookkeeping settings of a run (both training configurations carry them).
#[derive(Clone, Debug)]
pub struct Schedule {
    pub steps: usize,
    pub learning_rate: f64,
    pub warmup_steps: usize,
    /// The cosine decays to `learning_rate * final_lr_ratio`.
    pub final_lr_ratio: f64,
    pub weight_decay: f64,
    /// Global gradient-norm clip.
    pub grad_clip: f64,
    /// EMA of the weights; `None` ships the raw weights.
    pub ema_decay: Option<f32>,
    pub seed: u64,
    pub checkpoint_every: usize,
    pub eval_every: usize,
}

/// What one optimiser step reports to the loop.
pub struct StepOutcome {
    /// The total loss (a non-finite one stops the run).
    pub loss: f64,
    /// Gradient norm before clipping.
    pub grad_norm: f64,
    /// Examples in the batch (for the throughput figure).
    pub examples: usize,
    /// Model-specific loss terms for the metrics line.
    pub terms: Vec<(&'static str, f64)>,
    /// A short progress summary.
    pub summary: String,
}

/// One model's part of a training run.
pub trait Task {
    type Model: Module;
    /// Where the run stands in its data, saved in checkpoints (e.g. epoch and position).
    type Position: Serialize + DeserializeOwned + Default;
    /// A validation result, written to the metrics file.
    type Validation: Serialize;
    /// The throughput field's name in the metrics file (e.g. `meshes_per_s`).
    const THROUGHPUT: &'static str;

    /// Draws a batch (advancing `position`, drawing from `rng`) and takes one optimiser step at
    /// `lr`. `None` when the batch came out empty (nothing was done; the loop draws again).
    fn step(
        &mut self,
        model: Self::Model,
        position: &mut Self::Position,
        rng: &mut Rng,
        optim: (&AdamW, &mut AdamWState),
        lr: f64,
    ) -> (Self::Model, Option<StepOutcome>);

    /// Validates the model (in validation mode); `None` when there is nothing to validate on.
    fn validate(&self, model: &Self::Model, step: usize) -> Option<Self::Validation>;

    /// A line for the progress display.
    fn describe(validation: &Self::Validation) -> String;
}

/// What a run produced.
pub struct Trained<V> {
    /// The weights to ship (the EMA when enabled).
    pub weights: TensorMap,
    pub steps: usize,
    pub last_validation: Option<V>,
    /// Seconds of training that earlier processes spent on this run before it resumed (0 for
    /// a fresh run), so a manifest's wall time covers the whole run.
    pub earlier_s: f64,
}

/// A checkpoint's state file: the configuration (a run resumes only with the same one), the
/// step, the RNG state to continue from, the training time so far and the data position.
#[derive(Serialize, Deserialize)]
struct RunState<C, P> {
    config: C,
    step: usize,
    rng: u64,
    /// Seconds of training up to this checkpoint, over every process that ran it: a resumed
    /// run's `elapsed_s` goes on from here, as an unbroken run's would (checkpoints written
    /// before this field existed read 0).
    #[serde(default)]
    elapsed_s: f64,
    #[serde(flatten)]
    position: P,
}

/// Trains `model` (on the autodiff device) with `task` under `schedule`, writing checkpoints
/// and `metrics.jsonl` under `out_dir`. A checkpoint already there with the same `config` is
/// resumed: the run continues exactly as if it had not stopped. `device` is the plain device
/// the optimiser state and EMA live on.
pub fn run_training<T: Task, C>(
    task: &mut T,
    config: &C,
    schedule: &Schedule,
    model: T::Model,
    out_dir: &Path,
    device: &Device,
    observer: &mut dyn TrainObserver,
) -> Result<Trained<T::Validation>, TrainError>
where
    C: Serialize + DeserializeOwned + PartialEq + Clone,
{
    let (paths, mut log) = open_run(out_dir)?;
    let optim = AdamW::new(schedule.weight_decay, schedule.grad_clip);
    let mut optim_state = AdamWState::default();
    let mut model = model;
    let mut state = RunState {
        config: config.clone(),
        step: 0,
        rng: schedule.seed,
        elapsed_s: 0.0,
        position: T::Position::default(),
    };
    let mut ema_map: Option<TensorMap> = None;
    if let Some(r) = paths.restore(
        |saved: &RunState<C, T::Position>| saved.config == *config,
        |saved| saved.step,
        schedule.ema_decay.is_some(),
        device,
    )? {
        model = load_module(model, &r.model, &|_| false)?;
        optim_state = r.optim;
        ema_map = r.ema;
        state = r.state;
        log = resume_metrics(out_dir, state.step)?;
    }
    let mut ema = match (schedule.ema_decay, ema_map) {
        (Some(decay), Some(map)) => Some(DeviceEma::from_map(&model, &map, decay)?),
        (Some(decay), None) => Some(DeviceEma::new(&model, decay)),
        (None, _) => None,
    };

    let mut rng = Rng::new(state.rng);
    let earlier_s = state.elapsed_s;
    let started = Instant::now();
    let elapsed_s = || earlier_s + started.elapsed().as_secs_f64();
    // Throughput over a window of up to 10 steps of this process (not inflated by a resume).
    let mut window = (Instant::now(), 0usize);
    let mut last_validation = None;
    while state.step < schedule.steps && !observer.stop() {
        let lr = warmup_cosine(
            state.step,
            schedule.learning_rate,
            schedule.warmup_steps,
            schedule.steps,
            schedule.final_lr_ratio,
        );
        let (updated, outcome) = task.step(
            model,
            &mut state.position,
            &mut rng,
            (&optim, &mut optim_state),
            lr,
        );
        model = updated;
        let Some(out) = outcome else { continue };
        state.step += 1;
        if !out.loss.is_finite() {
            return Err(TrainError::Diverged(out.loss, state.step));
        }
        if let Some(ema) = ema.as_mut() {
            ema.update(&model);
        }
        window.1 += out.examples;
        let rate = window.1 as f64 / window.0.elapsed().as_secs_f64().max(1e-9);
        if state.step.is_multiple_of(10) {
            window = (Instant::now(), 0);
        }
        let mut line = serde_json::Map::new();
        line.insert("step".into(), state.step.into());
        line.insert("lr".into(), lr.into());
        line.insert("loss".into(), out.loss.into());
        for (name, value) in &out.terms {
            line.insert((*name).into(), (*value).into());
        }
        line.insert("grad_norm".into(), out.grad_norm.into());
        line.insert(T::THROUGHPUT.into(), rate.into());
        line.insert("elapsed_s".into(), elapsed_s().into());
        writeln!(log, "{}", serde_json::Value::Object(line))?;
        observer.step(
            state.step,
            &format!("{} {rate:.1} {}", out.summary, T::THROUGHPUT),
        );

        let last = state.step == schedule.steps || observer.stop();
        let due = state.step.is_multiple_of(schedule.eval_every.max(1)) || last;
        if let Some(v) = due
            .then(|| task.validate(&model.valid(), state.step))
            .flatten()
        {
            writeln!(log, "{}", serde_json::to_string(&v).expect("serialisable"))?;
            observer.note(&T::describe(&v));
            last_validation = Some(v);
        }
        if state.step.is_multiple_of(schedule.checkpoint_every.max(1)) || last {
            // The generator's whole state, so a run resumed from any checkpoint (a scheduled
            // one or a stop) draws the same numbers as an unbroken run.
            state.rng = rng.state();
            state.elapsed_s = elapsed_s();
            let ema_map = ema.as_ref().map(|e| e.to_map(&model));
            paths.save(
                &module_tensors(&model),
                &optim_state,
                ema_map.as_ref(),
                &state,
            )?;
        }
    }
    let weights = match &ema {
        Some(e) => e.to_map(&model),
        None => module_tensors(&model),
    };
    Ok(Trained {
        weights,
        steps: state.step,
        last_validation,
        earlier_s,
    })
}
