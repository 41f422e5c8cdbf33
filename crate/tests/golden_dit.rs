//! The Burn DiT against the reference (`shared/golden/dit_small`): the forward pass and its
//! recorded intermediates within 1e-4, on the CPU backend (flex) and, with the `wgpu` feature,
//! on burn-wgpu over Vulkan.

mod common;

use burn::tensor::{Device, Tensor, TensorData};
use common::{Golden, max_abs_diff};
use meshflow::model::dit::{Dit, DitConfig, Rope, is_image_path, time_features};
use meshflow::model::{TensorMap, Trace, load_module};

const TOLERANCE: f32 = 1e-4;

fn values<const D: usize>(t: Tensor<D>) -> Vec<f32> {
    t.into_data()
        .convert::<f32>()
        .try_into_vec::<f32>()
        .unwrap()
}

fn check(name: &str, got: Vec<f32>, g: &Golden, key: &str) {
    let want = g.f32(key);
    assert_eq!(got.len(), want.data.len(), "{name}: size");
    let err = max_abs_diff(&got, &want.data);
    eprintln!("{name}: max abs diff {err:.3e}");
    assert!(err < TOLERANCE, "{name}: max abs diff {err}");
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

fn run_forward(device: &Device) {
    let (g, dit) = load(device);
    let x = g.f32("input.x");
    let t = g.f32("input.timestep").data;
    let rope_input: Vec<f32> = g
        .i64("input.rope_input")
        .data
        .iter()
        .map(|&v| v as f32)
        .collect();
    let positions: Vec<[f32; 3]> = rope_input
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    let rope = Rope::new(&positions, 2, 24, device);
    let cond = g.f32("input.proj_cond_on_temb");
    let cond = Tensor::<2>::from_data(TensorData::new(cond.data, cond.shape), device);
    check(
        "t_freq",
        values(time_features(&t, 96, device)),
        &g,
        "output.t_freq",
    );
    check(
        "temb",
        values(dit.time_embedding(&t, cond.clone())),
        &g,
        "inter.temb",
    );
    let x = Tensor::<3>::from_data(TensorData::new(x.data, x.shape), device);
    let mut trace = Trace::recording();
    let out = dit.forward(x, &t, cond, &rope, &mut trace);
    for (name, tensor) in trace.tensors {
        check(&name, values(tensor), &g, &format!("inter.{name}"));
    }
    check("sample", values(out), &g, "output.sample");
}

#[test]
fn dit_small_forward_matches_reference_on_cpu() {
    run_forward(&Device::flex());
}

#[cfg(feature = "wgpu")]
#[test]
fn dit_small_forward_matches_reference_on_wgpu_vulkan() {
    run_forward(&meshflow::device::vulkan().expect("a Vulkan device (lavapipe in CI)"));
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

fn run_sampling(device: &Device) {
    use meshflow::model::sampler::sample;
    use meshflow::model::schedule::ScheduleMode;
    let (g, dit) = load(device);
    let rope_input: Vec<f32> = g
        .i64("input.rope_input")
        .data
        .iter()
        .map(|&v| v as f32)
        .collect();
    let positions: Vec<[f32; 3]> = rope_input
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    let rope = Rope::new(&positions, 2, 24, device);
    let cond = g.f32("input.proj_cond_on_temb");
    let cond = Tensor::<2>::from_data(TensorData::new(cond.data, cond.shape), device);
    let noise = g.f32("input.noise");
    let noise = Tensor::<3>::from_data(TensorData::new(noise.data, noise.shape), device);
    let mut trace = Vec::new();
    let out = sample(
        &dit,
        noise,
        cond,
        &rope,
        10,
        ScheduleMode::Reference,
        &mut |_, _, x| {
            trace.extend(values(x.clone()));
            true
        },
    )
    .unwrap();
    check("sample_trace", trace, &g, "output.sample_trace");
    check("sampled", values(out), &g, "output.sampled");
}

#[test]
fn dit_small_sampling_trace_matches_reference_on_cpu() {
    run_sampling(&Device::flex());
}

#[cfg(feature = "wgpu")]
#[test]
fn dit_small_sampling_trace_matches_reference_on_wgpu_vulkan() {
    run_sampling(&meshflow::device::vulkan().expect("a Vulkan device (lavapipe in CI)"));
}

#[test]
fn sampling_can_be_cancelled_between_steps() {
    use meshflow::model::sampler::{SampleError, sample};
    use meshflow::model::schedule::ScheduleMode;
    let device = Device::flex();
    let (_, dit) = load(&device);
    let rope = Rope::new(&[[0.0; 3]; 16], 1, 24, &device);
    let noise = Tensor::<3>::zeros([1, 16, 8], &device);
    let cond = Tensor::<2>::ones([1, 1], &device);
    let mut seen = 0;
    let r = sample(
        &dit,
        noise,
        cond,
        &rope,
        28,
        ScheduleMode::ToZero,
        &mut |i, n, _| {
            assert_eq!(n, 28);
            seen = i;
            i < 3
        },
    );
    assert_eq!(r.unwrap_err(), SampleError::Cancelled(3, 28));
    assert_eq!(seen, 3);
}
