//! Euler sampling of the rectified flow: from noise at t = 1 to latents, one DiT evaluation per
//! step, with a progress callback and cancellation between steps.

use burn::tensor::{Device, Tensor, TensorData};

use super::dit::{Dit, Rope};
use super::schedule::{ScheduleMode, step_times};
use super::vae::Trace;
use crate::rng::Rng;

/// Why sampling stopped without a result.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum SampleError {
    #[error("sampling was cancelled after {0} of {1} steps")]
    Cancelled(usize, usize),
    #[error("at least one sampling step is needed")]
    NoSteps,
}

/// Integrates `dx/dt = v(x, t)` from `noise` (`[B, L, D]`, t = 1) down the schedule:
/// `x -= (t_i - t_{i+1}) v(x, t_i)`. `on_step(i, steps)` runs after each step and returns
/// false to cancel.
pub fn sample(
    dit: &Dit,
    noise: Tensor<3>,
    cond: Tensor<2>,
    rope: &Rope,
    steps: usize,
    mode: ScheduleMode,
    on_step: &mut dyn FnMut(usize, usize, &Tensor<3>) -> bool,
) -> Result<Tensor<3>, SampleError> {
    if steps == 0 {
        return Err(SampleError::NoSteps);
    }
    let times = step_times(steps, mode);
    let mut x = noise;
    for i in 0..steps {
        x = euler_step(dit, x, times[i], times[i + 1], cond.clone(), rope);
        if !on_step(i + 1, steps, &x) {
            return Err(SampleError::Cancelled(i + 1, steps));
        }
    }
    Ok(x)
}

/// One Euler step from model time `t` to `t_next` (`t > t_next`): `x - (t - t_next) v(x, t)`.
/// Drivers that must wait between steps (the browser) loop over [`step_times`] with it.
pub fn euler_step(
    dit: &Dit,
    x: Tensor<3>,
    t: f32,
    t_next: f32,
    cond: Tensor<2>,
    rope: &Rope,
) -> Tensor<3> {
    let batch = x.dims()[0];
    let v = dit.forward(
        x.clone(),
        &vec![t; batch],
        cond,
        rope,
        &mut Trace::default(),
    );
    x - v * (t - t_next) as f64
}

/// Standard normal noise of `shape`, drawn from `rng` in row-major order (the same values on
/// every backend and platform).
pub fn normal_noise(rng: &mut Rng, shape: [usize; 3], device: &Device) -> Tensor<3> {
    let values: Vec<f32> = (0..shape.iter().product::<usize>())
        .map(|_| rng.normal() as f32)
        .collect();
    Tensor::from_data(TensorData::new(values, shape), device)
}
