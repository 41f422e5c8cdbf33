//! Sampling the rectified flow: from noise at t = 1 to latents along the schedule, with a
//! progress callback and cancellation between steps. Each step is one [`Solver`] step: Euler
//! (one DiT evaluation, as the paper) or a second-order one (two evaluations), which follows a
//! curved flow more closely for the same number of evaluations.

use burn::tensor::{Device, Tensor, TensorData};
use serde::{Deserialize, Serialize};

use super::dit::{Condition, Dit};
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

/// How one step moves `x` from model time `t` to `t_next` (`t > t_next`, `h = t - t_next`)
/// along `dx/dt = v(x, t)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Solver {
    /// `x - h v(x, t)`: one evaluation, as the paper and the reference.
    Euler,
    /// Heun's trapezoid: an Euler predictor `x' = x - h v(x, t)`, then
    /// `x - h (v(x, t) + v(x', t_next)) / 2`. Two evaluations, except on a step that ends at
    /// t = 0, which stays Euler as in Karras et al. 2022 (EDM): the DiT is trained on
    /// logit-normal times and has almost never seen t = 0.
    Heun,
    /// The explicit midpoint rule: `x - h v(x - h/2 v(x, t), t - h/2)`. Two evaluations, the
    /// second halfway through the step; on the long step down to the schedule's last time
    /// (t ~ 0.009, which training almost never drew) that is well inside the trained range,
    /// where Heun's corrector is not. The default of
    /// [`GenerateOptions`](crate::pipeline::generate::GenerateOptions).
    Midpoint,
}

impl Solver {
    /// One step of `dx/dt = velocity(x, t)` from `t` to `t_next` (`t > t_next`).
    pub fn step(
        self,
        x: Tensor<3>,
        t: f32,
        t_next: f32,
        velocity: &mut dyn FnMut(Tensor<3>, f32) -> Tensor<3>,
    ) -> Tensor<3> {
        let h = (t - t_next) as f64;
        let v = velocity(x.clone(), t);
        match self {
            Solver::Euler => x - v * h,
            Solver::Heun if t_next == 0.0 => x - v * h,
            Solver::Heun => {
                let v_next = velocity(x.clone() - v.clone() * h, t_next);
                x - (v + v_next) * (h / 2.0)
            }
            Solver::Midpoint => {
                let v_half = velocity(x.clone() - v * (h / 2.0), t - (t - t_next) / 2.0);
                x - v_half * h
            }
        }
    }
}

/// Integrates `dx/dt = v(x, t)` from `noise` (`[B, L, D]`, t = 1) down the schedule of
/// `steps` steps, each a `solver` step ([`step`]). `on_step(i, steps)` runs after each step
/// and returns false to cancel.
#[allow(clippy::too_many_arguments)]
pub fn sample(
    dit: &Dit,
    noise: Tensor<3>,
    cond: Tensor<2>,
    condition: &Condition,
    steps: usize,
    mode: ScheduleMode,
    solver: Solver,
    on_step: &mut dyn FnMut(usize, usize, &Tensor<3>) -> bool,
) -> Result<Tensor<3>, SampleError> {
    if steps == 0 {
        return Err(SampleError::NoSteps);
    }
    let times = step_times(steps, mode);
    let mut x = noise;
    for i in 0..steps {
        x = step(
            dit,
            solver,
            x,
            times[i],
            times[i + 1],
            cond.clone(),
            condition,
        );
        if !on_step(i + 1, steps, &x) {
            return Err(SampleError::Cancelled(i + 1, steps));
        }
    }
    Ok(x)
}

/// One `solver` step of the DiT's flow from model time `t` to `t_next` (`t > t_next`).
/// Drivers that must wait between steps (the browser) loop over [`step_times`] with it.
pub fn step(
    dit: &Dit,
    solver: Solver,
    x: Tensor<3>,
    t: f32,
    t_next: f32,
    cond: Tensor<2>,
    condition: &Condition,
) -> Tensor<3> {
    solver.step(x, t, t_next, &mut |x, t| {
        let batch = x.dims()[0];
        dit.forward(
            x,
            &vec![t; batch],
            cond.clone(),
            condition,
            &mut Trace::default(),
        )
    })
}

/// Standard normal noise of `shape`, drawn from `rng` in row-major order (the same values on
/// every backend and platform).
pub fn normal_noise(rng: &mut Rng, shape: [usize; 3], device: &Device) -> Tensor<3> {
    let values: Vec<f32> = (0..shape.iter().product::<usize>())
        .map(|_| rng.normal() as f32)
        .collect();
    Tensor::from_data(TensorData::new(values, shape), device)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `dx/dt = x cos(t)` from `x(1) = 1` has `x(t) = exp(sin t - sin 1)`: a curved flow with
    /// a closed form. Returns the error at `t_end` and how many times the velocity was
    /// evaluated.
    fn integrate(solver: Solver, steps: usize, t_end: f32) -> (f64, usize) {
        let device = Device::flex();
        let mut x = Tensor::<3>::ones([1, 1, 1], &device);
        let mut evaluations = 0;
        let mut velocity = |x: Tensor<3>, t: f32| {
            evaluations += 1;
            x * (t as f64).cos()
        };
        for i in 0..steps {
            let t = 1.0 - (1.0 - t_end) * i as f32 / steps as f32;
            let t_next = 1.0 - (1.0 - t_end) * (i + 1) as f32 / steps as f32;
            x = solver.step(
                x,
                t,
                if i + 1 == steps { t_end } else { t_next },
                &mut velocity,
            );
        }
        let got = x.into_data().try_into_vec::<f32>().unwrap()[0] as f64;
        let error = (got - ((t_end as f64).sin() - 1f64.sin()).exp()).abs();
        (error, evaluations)
    }

    fn error_at(solver: Solver, steps: usize, t_end: f32) -> f64 {
        integrate(solver, steps, t_end).0
    }

    #[test]
    fn second_order_solvers_converge_quadratically_and_euler_linearly() {
        // Halving the step divides the error by about 2 (first order) or 4 (second order).
        for (solver, lo, hi) in [
            (Solver::Euler, 1.7, 2.3),
            (Solver::Heun, 3.4, 4.6),
            (Solver::Midpoint, 3.4, 4.6),
        ] {
            let (coarse, fine) = (error_at(solver, 8, 0.1), error_at(solver, 16, 0.1));
            let ratio = coarse / fine;
            assert!((lo..hi).contains(&ratio), "{solver:?}: error ratio {ratio}");
        }
        // At the same number of evaluations the second-order steps are closer (here 2.4x and
        // 11x).
        let euler = error_at(Solver::Euler, 16, 0.1);
        assert!(error_at(Solver::Heun, 8, 0.1) < euler / 2.0);
        assert!(error_at(Solver::Midpoint, 8, 0.1) < euler / 5.0);
    }

    #[test]
    fn heun_ends_with_an_euler_step_at_t_zero() {
        // One Heun step to t = 0 evaluates once and equals Euler's step; otherwise the
        // second-order steps evaluate twice.
        assert_eq!(integrate(Solver::Heun, 1, 0.0).1, 1);
        assert_eq!(
            error_at(Solver::Heun, 1, 0.0),
            error_at(Solver::Euler, 1, 0.0)
        );
        assert_eq!(integrate(Solver::Heun, 7, 0.0).1, 13);
        assert_eq!(integrate(Solver::Heun, 7, 0.1).1, 14);
        assert_eq!(integrate(Solver::Midpoint, 7, 0.0).1, 14);
        assert_eq!(integrate(Solver::Euler, 7, 0.0).1, 7);
    }

    #[test]
    fn solvers_are_named_in_kebab_case_in_options() {
        for (solver, name) in [
            (Solver::Euler, "\"euler\""),
            (Solver::Heun, "\"heun\""),
            (Solver::Midpoint, "\"midpoint\""),
        ] {
            assert_eq!(serde_json::to_string(&solver).unwrap(), name);
            assert_eq!(serde_json::from_str::<Solver>(name).unwrap(), solver);
        }
        assert!(serde_json::from_str::<Solver>("\"rk4\"").is_err());
    }
}
