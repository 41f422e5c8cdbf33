//! Training loops (feature `train`: Burn's autodiff) and what they share: the optimiser,
//! checkpoint files, the learning-rate schedule, EMA, noise and the observer interface.

pub mod adamw;
pub mod dit;
pub mod vae;

use std::fs;
use std::path::{Path, PathBuf};

use burn::tensor::{Device, Tensor};

use crate::model::weights::{TensorMap, WeightsError};

/// Why training stopped early.
#[derive(Debug, thiserror::Error)]
pub enum TrainError {
    #[error("no training example fits the model (N = {0} vertices)")]
    NoData(usize),
    #[error("checkpoint in {dir}: {reason}")]
    Checkpoint { dir: String, reason: String },
    #[error("the checkpoint was made with a different configuration; use a new output folder")]
    ConfigChanged,
    #[error(transparent)]
    Weights(#[from] WeightsError),
    #[error("{0}")]
    Io(#[from] std::io::Error),
    #[error("loss became {0} at step {1}")]
    Diverged(f64, usize),
}

/// Callbacks for the caller's progress display; `stop` is polled between steps (a run that
/// stops writes a checkpoint first, so it can be resumed).
pub trait TrainObserver {
    /// After each optimiser step: the step count and a one-line summary.
    fn step(&mut self, step: usize, summary: &str);
    /// A line worth keeping on screen (validation results).
    fn note(&mut self, line: &str);
    fn stop(&self) -> bool {
        false
    }
}

/// Linear warm-up over `warmup` steps, then cosine decay to `lr * final_ratio` at `steps`
/// (`step` is 0-based).
pub fn warmup_cosine(step: usize, lr: f64, warmup: usize, steps: usize, final_ratio: f64) -> f64 {
    if step < warmup {
        return lr * (step + 1) as f64 / warmup as f64;
    }
    let span = steps.saturating_sub(warmup).max(1) as f64;
    let t = ((step - warmup) as f64 / span).min(1.0);
    let min = lr * final_ratio;
    min + 0.5 * (lr - min) * (1.0 + (std::f64::consts::PI * t).cos())
}

/// The files of a checkpoint folder.
pub(crate) struct CheckpointPaths {
    pub model: PathBuf,
    pub optim: PathBuf,
    pub ema: PathBuf,
    pub state: PathBuf,
}

impl CheckpointPaths {
    pub fn new(dir: &Path) -> Self {
        Self {
            model: dir.join("model.safetensors"),
            optim: dir.join("optimizer.safetensors"),
            ema: dir.join("ema.safetensors"),
            state: dir.join("state.json"),
        }
    }
}

/// What a checkpoint folder restores: the run's state, weights, optimiser moments and EMA.
pub(crate) struct Restored<S> {
    pub state: S,
    pub model: TensorMap,
    pub optim: adamw::AdamWState,
    pub ema: Option<TensorMap>,
}

impl CheckpointPaths {
    /// Reads the checkpoint when there is one. `same_config` must accept the saved state (else
    /// [`TrainError::ConfigChanged`]); `steps` gives the optimiser steps it had taken; moments
    /// are placed on `device` (the model's inner device).
    pub fn restore<S: serde::de::DeserializeOwned>(
        &self,
        same_config: impl Fn(&S) -> bool,
        steps: impl Fn(&S) -> usize,
        with_ema: bool,
        device: &Device,
    ) -> Result<Option<Restored<S>>, TrainError> {
        if !self.state.is_file() {
            return Ok(None);
        }
        let bad = |reason: String| TrainError::Checkpoint {
            dir: self
                .state
                .parent()
                .unwrap_or(&self.state)
                .display()
                .to_string(),
            reason,
        };
        let state: S =
            serde_json::from_slice(&fs::read(&self.state)?).map_err(|e| bad(e.to_string()))?;
        if !same_config(&state) {
            return Err(TrainError::ConfigChanged);
        }
        let model = TensorMap::from_safetensors(&fs::read(&self.model)?, "")?;
        let moments = TensorMap::from_safetensors(&fs::read(&self.optim)?, "")?;
        let optim =
            adamw::AdamWState::from_tensors(&moments, steps(&state) as u64, device).map_err(bad)?;
        let ema = if with_ema {
            Some(TensorMap::from_safetensors(&fs::read(&self.ema)?, "")?)
        } else {
            None
        };
        Ok(Some(Restored {
            state,
            model,
            optim,
            ema,
        }))
    }

    /// Writes a checkpoint, each file atomically, the state last (so a state file always
    /// describes complete weights).
    pub fn save<S: serde::Serialize>(
        &self,
        model: &TensorMap,
        optim: &adamw::AdamWState,
        ema: Option<&TensorMap>,
        state: &S,
    ) -> Result<(), TrainError> {
        write_atomic(&self.model, &model.to_safetensors(None))?;
        write_atomic(&self.optim, &optim.to_tensors().to_safetensors(None))?;
        if let Some(ema) = ema {
            write_atomic(&self.ema, &ema.to_safetensors(None))?;
        }
        let json = serde_json::to_vec_pretty(state).expect("a training state serialises");
        write_atomic(&self.state, &json)?;
        Ok(())
    }
}

/// Creates `out_dir/checkpoint` and opens `out_dir/metrics.jsonl` for appending (a resumed run
/// continues the same log).
pub(crate) fn open_run(out_dir: &Path) -> Result<(CheckpointPaths, fs::File), TrainError> {
    let ckpt_dir = out_dir.join("checkpoint");
    fs::create_dir_all(&ckpt_dir)?;
    let log = fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(out_dir.join("metrics.jsonl"))?;
    Ok((CheckpointPaths::new(&ckpt_dir), log))
}

/// A `[1]` tensor's value (NaN when it cannot be read back).
pub(crate) fn scalar(t: Tensor<1>) -> f64 {
    t.try_into_data()
        .ok()
        .and_then(|d| d.convert::<f64>().try_into_vec::<f64>().ok())
        .and_then(|v| v.first().copied())
        .unwrap_or(f64::NAN)
}

/// Standard-normal noise from the run's RNG (so a resumed run draws the same numbers).
/// `ema = decay ema + (1 - decay) current`, tensor by tensor.
pub(crate) fn ema_update(ema: &mut TensorMap, current: &TensorMap, decay: f32) {
    for (name, (_, values)) in ema.tensors.iter_mut() {
        let (_, cur) = &current.tensors[name];
        for (e, c) in values.iter_mut().zip(cur) {
            *e = decay * *e + (1.0 - decay) * c;
        }
    }
}

/// Writes through a temporary file and a rename, so a killed run never leaves a torn file.
pub(crate) fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let tmp = path.with_extension("tmp");
    fs::write(&tmp, bytes)?;
    fs::rename(tmp, path)
}
