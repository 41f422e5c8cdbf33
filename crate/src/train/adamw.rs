//! AdamW with global gradient-norm clipping, its state keyed by the parameters' reference names
//! so a checkpoint is a plain safetensors file and resumes exactly on any device.
//!
//! (Burn's own optimiser keys its state by random parameter ids and restores it on
//! `Device::default()`, which with the wgpu feature is a GPU; this one stays on the model's
//! device.)

use std::collections::BTreeMap;

use burn::module::{Module, ModuleMapper, ModuleVisitor, Param};
use burn::optim::GradientsParams;
use burn::tensor::{Device, Tensor};

use crate::model::weights::{TensorMap, reference_name};

/// Hyper-parameters (PyTorch's AdamW defaults apart from the weight decay).
#[derive(Clone, Debug)]
pub struct AdamW {
    pub beta1: f64,
    pub beta2: f64,
    pub eps: f64,
    pub weight_decay: f64,
    /// Gradients are scaled so their global L2 norm is at most this (0 = no clipping).
    pub max_grad_norm: f64,
}

/// First and second moments per parameter (flattened), and the number of steps taken.
#[derive(Default)]
pub struct AdamWState {
    pub step: u64,
    moments: BTreeMap<String, (Tensor<1>, Tensor<1>)>,
}

struct NormVisitor<'a> {
    grads: &'a GradientsParams,
    sum: Option<Tensor<1>>,
}

impl ModuleVisitor for NormVisitor<'_> {
    fn visit_float<const D: usize>(&mut self, param: &Param<Tensor<D>>) {
        if let Some(g) = self.grads.get::<D>(param.id) {
            let s = g.square().sum();
            self.sum = Some(match self.sum.take() {
                Some(acc) => acc + s,
                None => s,
            });
        }
    }
}

struct StepMapper<'a> {
    opt: &'a AdamW,
    state: &'a mut AdamWState,
    grads: GradientsParams,
    lr: f64,
    grad_scale: f64,
    path: Vec<String>,
}

impl ModuleMapper for StepMapper<'_> {
    fn enter_module(&mut self, name: &str, _container: &str) {
        self.path.push(name.to_string());
    }

    fn exit_module(&mut self, _name: &str, _container: &str) {
        self.path.pop();
    }

    fn map_float<const D: usize>(&mut self, param: Param<Tensor<D>>) -> Param<Tensor<D>> {
        let Some(grad) = self.grads.remove::<D>(param.id) else {
            return param;
        };
        let name = reference_name(&self.path);
        let o = self.opt;
        let t = self.state.step as i32;
        param.map(|value| {
            let shape = value.dims();
            let numel = shape.iter().product::<usize>();
            let w = value.inner().reshape([numel]);
            let g = grad.reshape([numel]) * self.grad_scale;
            let (m, v) = match self.state.moments.remove(&name) {
                Some((m, v)) => (
                    m * o.beta1 + g.clone() * (1.0 - o.beta1),
                    v * o.beta2 + g.square() * (1.0 - o.beta2),
                ),
                None => (g.clone() * (1.0 - o.beta1), g.square() * (1.0 - o.beta2)),
            };
            let m_hat = m.clone() / (1.0 - o.beta1.powi(t));
            let v_hat = v.clone() / (1.0 - o.beta2.powi(t));
            let w = w * (1.0 - self.lr * o.weight_decay) - m_hat / (v_hat.sqrt() + o.eps) * self.lr;
            self.state.moments.insert(name.clone(), (m, v));
            Tensor::from_inner(w.reshape(shape)).require_grad()
        })
    }
}

impl AdamW {
    /// PyTorch's betas (0.9, 0.999) and eps (1e-8) with the given decay and clip.
    pub fn new(weight_decay: f64, max_grad_norm: f64) -> Self {
        Self {
            beta1: 0.9,
            beta2: 0.999,
            eps: 1e-8,
            weight_decay,
            max_grad_norm,
        }
    }

    /// One update of `module` from `grads` at learning rate `lr`. Returns the module and the
    /// global gradient norm before clipping.
    pub fn step<M: Module>(
        &self,
        state: &mut AdamWState,
        module: M,
        grads: GradientsParams,
        lr: f64,
    ) -> (M, f64) {
        let mut norm = NormVisitor {
            grads: &grads,
            sum: None,
        };
        module.visit(&mut norm);
        let grad_norm = norm
            .sum
            .and_then(|s| s.try_into_data().ok())
            .and_then(|d| d.convert::<f64>().try_into_vec::<f64>().ok())
            .and_then(|v| v.first().copied())
            .unwrap_or(0.0f64)
            .sqrt();
        let grad_scale = if self.max_grad_norm > 0.0 && grad_norm > self.max_grad_norm {
            self.max_grad_norm / (grad_norm + 1e-6)
        } else {
            1.0
        };
        state.step += 1;
        let mut mapper = StepMapper {
            opt: self,
            state,
            grads,
            lr,
            grad_scale,
            path: Vec::new(),
        };
        (module.map(&mut mapper), grad_norm)
    }
}

impl AdamWState {
    /// The moments as named tensors (`m.NAME`, `v.NAME`) for a checkpoint.
    pub fn to_tensors(&self) -> TensorMap {
        let mut map = TensorMap::default();
        for (name, (m, v)) in &self.moments {
            for (prefix, t) in [("m", m), ("v", v)] {
                let values = t
                    .clone()
                    .try_into_data()
                    .expect("reading back optimiser state")
                    .convert::<f32>()
                    .try_into_vec::<f32>()
                    .expect("f32");
                map.tensors
                    .insert(format!("{prefix}.{name}"), (vec![values.len()], values));
            }
        }
        map
    }

    /// Restores the moments saved by [`Self::to_tensors`] onto `device` (the inner, non-autodiff
    /// device of the model).
    pub fn from_tensors(map: &TensorMap, step: u64, device: &Device) -> Result<Self, String> {
        let mut moments = BTreeMap::new();
        for name in map.tensors.keys().filter_map(|k| k.strip_prefix("m.")) {
            let m = map.tensor::<1>(&format!("m.{name}"), device);
            let v = map.tensor::<1>(&format!("v.{name}"), device);
            match (m, v) {
                (Some(m), Some(v)) => {
                    moments.insert(name.to_string(), (m, v));
                }
                _ => return Err(format!("optimiser state for {name} is incomplete")),
            }
        }
        Ok(Self { step, moments })
    }
}
