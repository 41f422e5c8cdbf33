//! The Burn DiT against the reference (`shared/golden/dit_small`): the forward pass and its
//! recorded intermediates within 1e-4, on the CPU backend (flex) and, with the `wgpu` feature,
//! on burn-wgpu over Vulkan.

mod common;

use burn::tensor::{Device, Tensor};
use common::{Golden, max_abs_diff};
use meshflow::model::dit::{Condition, Dit, DitConfig, is_image_path, time_features};
use meshflow::model::golden::{TOLERANCE, verify_dit};
use meshflow::model::{TensorMap, load_module};

fn values<const D: usize>(t: Tensor<D>) -> Vec<f32> {
    t.into_data()
        .convert::<f32>()
        .try_into_vec::<f32>()
        .unwrap()
}

fn load(device: &Device) -> (Golden, Dit) {
    let g = Golden::load("dit_small");
    let bytes = std::fs::read(common::golden_dir().join("dit_small.safetensors")).unwrap();
    let map = TensorMap::from_safetensors(&bytes, "param.").unwrap();
    let dit = load_module(
        Dit::new(&DitConfig::dit_small(), device),
        &map,
        &is_image_path,
    )
    .unwrap();
    (g, dit)
}

/// The time features, then the library's comparison ([`verify_dit`], as `meshflow verify`
/// runs it: the forward pass with its intermediates and the 10-step sampling trace), every
/// tensor within [`TOLERANCE`].
fn run_golden(device: &Device) {
    let g = Golden::load("dit_small");
    let t = g.f32("input.timestep").data;
    let want = g.f32("output.t_freq").data;
    let err = max_abs_diff(&values(time_features(&t, 96, device)), &want);
    eprintln!("t_freq: max abs diff {err:.3e}");
    assert!(err < TOLERANCE, "t_freq: max abs diff {err}");
    let diffs = verify_dit(&common::golden_dir(), device).unwrap();
    common::assert_within_tolerance(&diffs);
    let names: Vec<&str> = diffs.iter().map(|d| d.name.as_str()).collect();
    let inter = g.json["tensors"]
        .as_object()
        .unwrap()
        .keys()
        .filter_map(|k| k.strip_prefix("inter."));
    for name in ["sample", "sample_trace", "sampled"]
        .into_iter()
        .chain(inter)
    {
        assert!(names.contains(&name), "{name} compared");
    }
}

#[test]
fn dit_small_matches_reference_on_cpu() {
    run_golden(&Device::flex());
}

#[cfg(feature = "wgpu")]
#[test]
fn dit_small_matches_reference_on_wgpu_vulkan() {
    run_golden(&meshflow::device::vulkan().expect("a Vulkan device (lavapipe in CI)"));
}

#[test]
fn schedules_match_reference() {
    use meshflow::model::schedule::{ScheduleMode, step_times, timesteps};
    let text = std::fs::read_to_string(common::golden_dir().join("sched.json")).unwrap();
    let sched: serde_json::Value = serde_json::from_str(&text).unwrap();
    for n in [10usize, 11, 28, 29] {
        let entry = &sched[format!("set_timesteps_{n}")];
        let want: Vec<f32> = entry["timesteps"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap() as f32)
            .collect();
        let got = timesteps(n);
        assert_eq!(got.len(), want.len());
        let err = max_abs_diff(&got, &want);
        eprintln!("timesteps({n}): max abs diff {err:e}");
        assert!(err <= 1e-4, "timesteps({n}) differ by {err}");
    }
    let (g, _) = load(&Device::flex());
    let trace_t = g.f32("output.trace_timesteps").data;
    let times = step_times(10, ScheduleMode::Reference);
    let model_times: Vec<f32> = trace_t.iter().map(|t| t / 1000.0).collect();
    assert!(max_abs_diff(&times[..10], &model_times) < 1e-7);
    assert!(
        (times[10] - 0.008928572).abs() < 1e-7,
        "ends at ~0.0089: {}",
        times[10]
    );
    let to_zero = step_times(10, ScheduleMode::ToZero);
    assert_eq!(to_zero.len(), 11);
    assert_eq!(to_zero[10], 0.0);
}

#[test]
fn sampling_can_be_cancelled_between_steps() {
    use meshflow::model::sampler::{SampleError, Solver, sample};
    use meshflow::model::schedule::ScheduleMode;
    let device = Device::flex();
    let (_, dit) = load(&device);
    let condition = Condition::new(&DitConfig::dit_small(), &[[0.0; 3]; 16], &[], 1, &device);
    let noise = Tensor::<3>::zeros([1, 16, 8], &device);
    let cond = Tensor::<2>::ones([1, 1], &device);
    let mut seen = 0;
    let r = sample(
        &dit,
        noise,
        cond,
        &condition,
        28,
        ScheduleMode::ToZero,
        Solver::Heun,
        &mut |i, n, _| {
            assert_eq!(n, 28);
            seen = i;
            i < 3
        },
    );
    assert_eq!(r.unwrap_err(), SampleError::Cancelled(3, 28));
    assert_eq!(seen, 3);
}
