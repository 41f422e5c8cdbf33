//! The flow-matching Euler schedule with time shift 3 (golden `sched.json`).
//!
//! The reference builds diffusers' `FlowMatchEulerDiscreteScheduler(1000, shift = 3)`: the
//! training grid `t / 1000, t = 1000..1` is shifted once (`s' = 3 s / (1 + 2 s)`), giving
//! `sigma_max = 1` and `sigma_min = 0.003 / 1.002`; `set_timesteps(n)` spaces `n` values
//! linearly from `1000 sigma_max` to `1000 sigma_min`, divides by 1000 and shifts again.
//! Sampling with S steps in the reference's way uses the schedule for S + 1 and stops at its
//! last value, `t ~ 0.0089` ([`ScheduleMode::Reference`]); [`ScheduleMode::ToZero`] uses the
//! schedule for S and ends at 0.

use serde::{Deserialize, Serialize};

/// The time shift.
pub const SHIFT: f64 = 3.0;
/// Training timesteps of the reference scheduler.
pub const TRAIN_TIMESTEPS: f64 = 1000.0;

fn shift(s: f64) -> f64 {
    SHIFT * s / (1.0 + (SHIFT - 1.0) * s)
}

/// `set_timesteps(n)`: the `n` timesteps (sigma x 1000, as f32) from 1000 down.
pub fn timesteps(n: usize) -> Vec<f32> {
    let sigma_max = shift(1.0);
    let sigma_min = shift(1.0 / TRAIN_TIMESTEPS);
    let (hi, lo) = (sigma_max * TRAIN_TIMESTEPS, sigma_min * TRAIN_TIMESTEPS);
    (0..n)
        .map(|i| {
            let t = if n == 1 {
                hi
            } else {
                hi + (lo - hi) * i as f64 / (n - 1) as f64
            };
            (shift(t / TRAIN_TIMESTEPS) * TRAIN_TIMESTEPS) as f32
        })
        .collect()
}

/// Where sampling ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ScheduleMode {
    /// As the reference: S steps over the first S + 1 timesteps of the schedule for S + 1,
    /// ending at t ~ 0.0089.
    Reference,
    /// S steps over the schedule for S, then to t = 0.
    ToZero,
}

/// The `S + 1` model times (in [0, 1], descending) that bound the `S` Euler steps: step `i`
/// evaluates the model at `times[i]` and moves by `times[i] - times[i + 1]`.
pub fn step_times(steps: usize, mode: ScheduleMode) -> Vec<f32> {
    match mode {
        ScheduleMode::Reference => timesteps(steps + 1)
            .into_iter()
            .map(|t| t / TRAIN_TIMESTEPS as f32)
            .collect(),
        ScheduleMode::ToZero => {
            let mut t: Vec<f32> = timesteps(steps)
                .into_iter()
                .map(|t| t / TRAIN_TIMESTEPS as f32)
                .collect();
            t.push(0.0);
            t
        }
    }
}
