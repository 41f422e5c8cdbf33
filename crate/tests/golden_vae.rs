//! The Burn MeshVAE against the reference (`shared/golden/vae_small`): every output and every
//! recorded intermediate within 1e-4, on the CPU backend (flex) and, with the `wgpu` feature,
//! on burn-wgpu over Vulkan (lavapipe without a GPU).

mod common;

use burn::tensor::{Device, Tensor, TensorData};
use common::{Golden, max_abs_diff};
use glam::Vec3;
use meshflow::model::tokens::assemble_features;
use meshflow::model::{MeshVae, TensorMap, Trace, VaeConfig, WeightsError, load_module};
use meshflow::model::{module_tensors, spacetime_distances};

const TOLERANCE: f32 = 1e-4;

fn tensor3(t: &common::Tensor<f32>, device: &Device) -> Tensor<3> {
    Tensor::from_data(TensorData::new(t.data.clone(), t.shape.clone()), device)
}

fn values<const D: usize>(t: Tensor<D>) -> Vec<f32> {
    t.into_data()
        .convert::<f32>()
        .try_into_vec::<f32>()
        .unwrap()
}

fn golden_params(g: &Golden) -> TensorMap {
    let bytes = std::fs::read(common::golden_dir().join("vae_small.safetensors")).unwrap();
    let map = TensorMap::from_safetensors(&bytes, "param.").unwrap();
    assert_eq!(map.tensors.len(), 120, "{:?}", g.json["constructor_args"]);
    map
}

/// Encoder input `x` built from the golden inputs by the crate's token code.
fn encoder_input(g: &Golden) -> common::Tensor<f32> {
    let cfg = VaeConfig::vae_small().tokens();
    let verts = g.f32("input.padded_verts").data;
    let normals = g.f32("input.verts_normal").data;
    let neighbours = g.f32("input.neighbor_points").data;
    let mut x = Vec::new();
    for i in 0..verts.len() / 3 {
        let nb: Vec<Vec3> = neighbours[i * 24..(i + 1) * 24]
            .chunks_exact(3)
            .map(Vec3::from_slice)
            .collect();
        // All-zero neighbour rows are padding; the reference keeps them as zeros.
        assemble_features(
            Vec3::from_slice(&verts[i * 3..i * 3 + 3]),
            Vec3::from_slice(&normals[i * 3..i * 3 + 3]),
            &nb,
            &cfg,
            &mut x,
        );
    }
    common::Tensor {
        shape: vec![2, 64, 222],
        data: x,
    }
}

fn check(name: &str, got: Vec<f32>, g: &Golden, key: &str, worst: &mut f32) {
    let want = g.f32(key);
    assert_eq!(got.len(), want.data.len(), "{name}: size");
    let err = max_abs_diff(&got, &want.data);
    eprintln!("{name}: max abs diff {err:.3e}");
    assert!(err < TOLERANCE, "{name}: max abs diff {err}");
    *worst = worst.max(err);
}

fn run_golden(device: &Device) {
    let g = Golden::load("vae_small");
    let cfg = VaeConfig::vae_small();
    let vae = load_module(MeshVae::new(&cfg, device), &golden_params(&g), &|_| false).unwrap();
    let x = encoder_input(&g);
    let mut worst = 0f32;
    check("x", x.data.clone(), &g, "output.x", &mut worst);

    let mut trace = Trace::recording();
    let posterior = vae.encode(tensor3(&x, device), &mut trace);
    check(
        "posterior_mean",
        values(posterior.mean.clone()),
        &g,
        "output.posterior_mean",
        &mut worst,
    );
    check(
        "posterior_logvar",
        values(posterior.logvar.clone()),
        &g,
        "output.posterior_logvar",
        &mut worst,
    );
    // Eval mode: z is the mean.
    check(
        "z",
        values(posterior.mean.clone()),
        &g,
        "output.z",
        &mut worst,
    );
    let decoded = vae.decode(posterior.mean, &mut trace);
    let recorded: Vec<String> = trace.tensors.iter().map(|(n, _)| n.clone()).collect();
    for (name, t) in trace.tensors {
        check(&name, values(t), &g, &format!("inter.{name}"), &mut worst);
    }
    let inter_keys = g.json["tensors"]
        .as_object()
        .unwrap()
        .keys()
        .filter_map(|k| k.strip_prefix("inter."))
        .count();
    assert_eq!(
        recorded.len(),
        inter_keys,
        "every recorded intermediate compared"
    );
    check(
        "mask",
        values(decoded.mask_logits),
        &g,
        "output.mask",
        &mut worst,
    );
    check(
        "verts",
        values(decoded.positions),
        &g,
        "output.verts",
        &mut worst,
    );
    check(
        "verts_normal",
        values(decoded.normals),
        &g,
        "output.verts_normal",
        &mut worst,
    );
    check(
        "adjacency_emb",
        values(decoded.edge_embeddings.clone()),
        &g,
        "output.adjacency_emb",
        &mut worst,
    );
    let st = spacetime_distances(decoded.edge_embeddings.narrow(0, 0, 1));
    check("spacetime", values(st), &g, "output.spacetime", &mut worst);
    let synthetic = g.f32("input.synthetic_adjacency_emb");
    let synthetic =
        Tensor::<2>::from_data(TensorData::new(synthetic.data, synthetic.shape), device)
            .unsqueeze::<3>();
    check(
        "synthetic_spacetime",
        values(spacetime_distances(synthetic)),
        &g,
        "output.synthetic_spacetime",
        &mut worst,
    );
    eprintln!("worst max abs diff {worst:.3e}");
}

#[test]
fn vae_small_matches_reference_on_cpu() {
    run_golden(&Device::flex());
}

#[cfg(feature = "wgpu")]
#[test]
fn vae_small_matches_reference_on_wgpu_vulkan() {
    run_golden(&meshflow::device::vulkan().expect("a Vulkan device (lavapipe in CI)"));
}

#[test]
fn weights_round_trip_under_reference_names() {
    let g = Golden::load("vae_small");
    let device = Device::flex();
    let params = golden_params(&g);
    let vae = load_module(
        MeshVae::new(&VaeConfig::vae_small(), &device),
        &params,
        &|_| false,
    )
    .unwrap();
    let saved = module_tensors(&vae);
    assert_eq!(
        saved, params,
        "saving gives back exactly the loaded tensors and names"
    );
    let bytes = saved.to_safetensors(None);
    assert_eq!(TensorMap::from_safetensors(&bytes, "").unwrap(), params);
}

#[test]
fn mismatched_weights_are_refused_with_a_reason() {
    let g = Golden::load("vae_small");
    let device = Device::flex();
    let params = golden_params(&g);
    let fresh = || MeshVae::new(&VaeConfig::vae_small(), &device);

    let mut missing = params.clone();
    missing.tensors.remove("decoder.mask_head.2.bias");
    match load_module(fresh(), &missing, &|_| false) {
        Err(WeightsError::Missing(names)) => assert_eq!(names, ["decoder.mask_head.2.bias"]),
        other => panic!("expected Missing, got {other:?}"),
    }

    let mut extra = params.clone();
    extra
        .tensors
        .insert("decoder.extra.weight".into(), (vec![1], vec![0.0]));
    assert!(matches!(
        load_module(fresh(), &extra, &|_| false),
        Err(WeightsError::Unexpected(n)) if n == ["decoder.extra.weight"]
    ));
    assert!(load_module(fresh(), &extra, &|n| n.starts_with("decoder.extra")).is_ok());

    let mut wider = VaeConfig::vae_small();
    wider.width_encoder = 128;
    let err = load_module(MeshVae::new(&wider, &device), &params, &|_| false).unwrap_err();
    assert!(matches!(err, WeightsError::Shape { .. }), "{err}");
    assert!(err.to_string().contains("encoder.proj_in.weight"), "{err}");
}
