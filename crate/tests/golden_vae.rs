//! The Burn MeshVAE against the reference (`shared/golden/vae_small`): every output and every
//! recorded intermediate within 1e-4, on the CPU backend (flex) and, with the `wgpu` feature,
//! on burn-wgpu over Vulkan (lavapipe without a GPU).

mod common;

use burn::tensor::Device;
use common::Golden;
use meshflow::model::golden::verify_vae;
use meshflow::model::{MeshVae, TensorMap, VaeConfig, WeightsError, load_module, module_tensors};

fn golden_params(g: &Golden) -> TensorMap {
    let bytes = std::fs::read(common::golden_dir().join("vae_small.safetensors")).unwrap();
    let map = TensorMap::from_safetensors(&bytes, "param.").unwrap();
    assert_eq!(map.tensors.len(), 120, "{:?}", g.json["constructor_args"]);
    map
}

/// The library's comparison ([`verify_vae`], as `meshflow verify` runs it), every tensor
/// within [`meshflow::model::golden::TOLERANCE`], and nothing the reference recorded left out.
fn run_golden(device: &Device) {
    let g = Golden::load("vae_small");
    // Eval mode: z is the posterior mean. The reference's z is its mean bit for bit, so the
    // `posterior_mean` row below is the comparison of z too.
    assert_eq!(
        g.f32("output.z").data,
        g.f32("output.posterior_mean").data,
        "z is the mean"
    );
    let diffs = verify_vae(&common::golden_dir(), device).unwrap();
    let worst = common::assert_within_tolerance(&diffs);
    let names: Vec<&str> = diffs.iter().map(|d| d.name.as_str()).collect();
    let outputs = [
        "x",
        "posterior_mean",
        "posterior_logvar",
        "mask",
        "verts",
        "verts_normal",
        "adjacency_emb",
        "spacetime",
        "synthetic_spacetime",
    ];
    let inter: Vec<&str> = g.json["tensors"]
        .as_object()
        .unwrap()
        .keys()
        .filter_map(|k| k.strip_prefix("inter."))
        .collect();
    for name in outputs.iter().chain(&inter) {
        assert!(names.contains(name), "{name} compared");
    }
    assert_eq!(
        names.len(),
        outputs.len() + inter.len(),
        "every recorded intermediate compared, and only those"
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
