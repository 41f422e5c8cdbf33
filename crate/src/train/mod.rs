//! Training (feature `train`: Burn's autodiff): one loop for both models ([`run`]) with the
//! model-specific steps in [`vae`] and [`dit`], and what the loop is made of: the optimiser,
//! checkpoint files, the learning-rate schedule, the device-side EMA, the observer interface,
//! and a batch's gradient from sub-batches run at once ([`sub_batches`]).

pub mod adamw;
pub mod dit;
pub mod presets;
pub mod profile;
pub mod run;
pub mod ship;
pub mod sub_batches;
pub mod vae;

use std::fs;
use std::path::{Path, PathBuf};

use std::collections::BTreeMap;

use burn::module::{Module, ModuleMapper, ModuleVisitor, Param};
use burn::tensor::{Device, Tensor};

use crate::io::write_atomic;
use crate::model::weights::{TensorMap, WeightsError, load_module, module_tensors, reference_name};

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

/// Checks what both training configurations share: the counts in `counts` are at least 1, the
/// learning rate is positive and finite, the EMA decay (when set) is in [0, 1). The message names
/// the offending field.
pub(crate) fn check_schedule(
    counts: &[(&str, usize)],
    learning_rate: f64,
    ema_decay: Option<f32>,
) -> Result<(), String> {
    if let Some((name, _)) = counts.iter().find(|(_, v)| *v == 0) {
        return Err(format!("{name} must be at least 1"));
    }
    if !(learning_rate.is_finite() && learning_rate > 0.0) {
        return Err(format!(
            "learning_rate must be positive (got {learning_rate})"
        ));
    }
    if let Some(d) = ema_decay.filter(|d| !(0.0..1.0).contains(d)) {
        return Err(format!("ema_decay must be in [0, 1) (got {d})"));
    }
    Ok(())
}

/// A short identity of a shard build for a training manifest: the sha256 of its
/// `manifest.jsonl` ("unknown" when it cannot be read).
pub fn data_version(shards: &Path) -> String {
    match fs::read(shards.join("manifest.jsonl")) {
        Ok(bytes) => format!(
            "manifest.jsonl sha256 {}",
            crate::pipeline::shipped::sha256_hex(&bytes)
        ),
        Err(_) => "unknown".into(),
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

/// Drops the lines of `out_dir/metrics.jsonl` written after step `step` (by a run that was
/// killed after its last checkpoint), so a resumed run's log reads like an unbroken one, and
/// opens it again for appending.
pub(crate) fn resume_metrics(out_dir: &Path, step: usize) -> Result<fs::File, TrainError> {
    let path = out_dir.join("metrics.jsonl");
    let text = fs::read_to_string(&path).unwrap_or_default();
    let kept: String = text
        .lines()
        .filter(|line| {
            serde_json::from_str::<serde_json::Value>(line)
                .ok()
                .and_then(|v| v.get("step").and_then(|s| s.as_u64()))
                .is_none_or(|s| s as usize <= step)
        })
        .flat_map(|line| [line, "\n"])
        .collect();
    if kept.len() != text.len() {
        write_atomic(&path, kept.as_bytes())?;
    }
    Ok(fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(path)?)
}

/// A `[1]` tensor's value (NaN when it cannot be read back).
pub(crate) fn scalar(t: Tensor<1>) -> f64 {
    t.try_into_data()
        .ok()
        .and_then(|d| d.convert::<f64>().try_into_vec::<f64>().ok())
        .and_then(|v| v.first().copied())
        .unwrap_or(f64::NAN)
}

/// An exponential moving average of a module's parameters, kept on the device (flattened, by
/// reference name), so a training step reads nothing back to the host; converted to a
/// [`TensorMap`] only for checkpoints and the final weights.
pub(crate) struct DeviceEma {
    decay: f32,
    values: BTreeMap<String, Tensor<1>>,
}

/// Visits a module's parameters by reference name.
struct EmaVisitor<'a> {
    path: Vec<String>,
    decay: Option<f32>,
    values: &'a mut BTreeMap<String, Tensor<1>>,
}

impl ModuleVisitor for EmaVisitor<'_> {
    fn enter_module(&mut self, name: &str, _container: &str) {
        self.path.push(name.to_string());
    }

    fn exit_module(&mut self, _name: &str, _container: &str) {
        self.path.pop();
    }

    fn visit_float<const D: usize>(&mut self, param: &Param<Tensor<D>>) {
        let value = param.val().inner();
        let numel = value.dims().iter().product::<usize>();
        let value = value.reshape([numel]);
        let name = reference_name(&self.path);
        let next = match (self.values.remove(&name), self.decay) {
            (Some(ema), Some(decay)) => ema * decay + value * (1.0 - decay),
            _ => value,
        };
        self.values.insert(name, next);
    }
}

/// Puts EMA values into a module's parameters.
struct EmaSetter<'a> {
    path: Vec<String>,
    values: &'a BTreeMap<String, Tensor<1>>,
}

impl ModuleMapper for EmaSetter<'_> {
    fn enter_module(&mut self, name: &str, _container: &str) {
        self.path.push(name.to_string());
    }

    fn exit_module(&mut self, _name: &str, _container: &str) {
        self.path.pop();
    }

    fn map_float<const D: usize>(&mut self, param: Param<Tensor<D>>) -> Param<Tensor<D>> {
        let Some(ema) = self.values.get(&reference_name(&self.path)) else {
            return param;
        };
        param.map(|value| Tensor::from_inner(ema.clone().reshape(value.dims())).require_grad())
    }
}

impl DeviceEma {
    /// An EMA that starts at `module`'s current parameters (an autodiff module).
    pub fn new<M: Module>(module: &M, decay: f32) -> Self {
        let mut values = BTreeMap::new();
        module.visit(&mut EmaVisitor {
            path: Vec::new(),
            decay: None,
            values: &mut values,
        });
        Self { decay, values }
    }

    /// `ema = decay ema + (1 - decay) current`, parameter by parameter, on the device.
    pub fn update<M: Module>(&mut self, module: &M) {
        module.visit(&mut EmaVisitor {
            path: Vec::new(),
            decay: Some(self.decay),
            values: &mut self.values,
        });
    }

    /// The averaged parameters under their reference names, laid out like `module`'s.
    pub fn to_map<M: Module>(&self, module: &M) -> TensorMap {
        let averaged = module.clone().map(&mut EmaSetter {
            path: Vec::new(),
            values: &self.values,
        });
        module_tensors(&averaged)
    }

    /// An EMA restored from a checkpoint's map, laid out like `module`.
    pub fn from_map<M: Module>(
        module: &M,
        map: &TensorMap,
        decay: f32,
    ) -> Result<Self, TrainError> {
        let loaded = load_module(module.clone(), map, &|_| false)?;
        Ok(Self::new(&loaded, decay))
    }
}
