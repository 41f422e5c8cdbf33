//! `bench train-vae`: one VAE training step part by part ([`crate::train::vae::profile_vae_step`])
//! beside the backend's matrix-product peak, as a report.

use std::time::Instant;

use burn::tensor::{Device, Distribution, Tensor};
use serde::Serialize;

use crate::Mesh;
use crate::train::TrainError;
use crate::train::vae::{VaeTrainConfig, profile_vae_step};

/// One part of a step.
#[derive(Serialize)]
pub struct StepPart {
    pub part: String,
    pub ms: f64,
    pub share: f64,
}

/// What `bench train-vae` writes as JSON.
#[derive(Serialize)]
pub struct StepReport {
    pub method: &'static str,
    pub cpu: String,
    pub threads: usize,
    pub config: String,
    pub batch_size: usize,
    pub num_vertices: usize,
    pub length_buckets: bool,
    pub step_ms: f64,
    pub meshes_per_s: f64,
    pub parts: Vec<StepPart>,
    /// Mean matrix-product FLOPs of a step: 3x the forward's (forward + two backward
    /// products).
    pub step_gflop: f64,
    pub achieved_gflop_per_s: f64,
    /// A 4096x256 @ 256x256 f32 matmul on the same backend, best of 5.
    pub matmul_peak_gflop_per_s: f64,
}

/// The backend's matmul throughput on docs/design.md's reference shape (4096x256 @ 256x256),
/// in GFLOP/s, best of 5 runs after a warm-up.
pub fn matmul_peak(device: &Device) -> f64 {
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

/// Profiles `steps` training steps of `cfg` (named `config_name` in the report) over `meshes`
/// after one warm-up step, and relates the step's matrix-product FLOPs to [`matmul_peak`].
pub fn profile_report(
    cfg: &VaeTrainConfig,
    config_name: &str,
    meshes: &[Mesh],
    device: &Device,
    steps: usize,
) -> Result<StepReport, TrainError> {
    let peak = matmul_peak(device);
    let profile = profile_vae_step(cfg, meshes, device, steps.max(1))?;
    let parts = &profile.parts;
    let step_s: f64 = parts.iter().map(|(_, s)| s).sum();
    let step_gflop = profile.flops_per_step / 1e9;
    Ok(StepReport {
        method: "mean wall time per part over `steps` training steps after one warm-up step \
                 (profile_vae_step: the training loop's step and batching with laps; Burn's CPU \
                 backend runs eagerly); FLOPs are the matrix products only \
                 (VaeConfig::forward_flops at each batch's slot count, x 3)",
        cpu: crate::device::cpu_name(),
        threads: crate::device::threads(),
        config: config_name.into(),
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
    })
}
