//! Raising a model's capacity (issue 53: 512 to 2,048 vertices) changes no weight and no small
//! mesh: the shipped pair with its configuration raised gives the shipped pair's mesh where the
//! budget fits the old capacity, and makes meshes above it that the shipped pair refuses.

mod common;

use meshflow::pipeline::generate::{GenerateError, GenerateOptions};
use meshflow::pipeline::shipped::ShippedModels;
use serde_json::Value;

/// The shipped pair with `num_vertices` raised to `vertices` (and the latents with it, at the
/// same merge ratio): only the manifests change, as a decoder-only run at that capacity writes
/// them; the DiT's count condition keeps its trained divisor.
fn raised(vertices: usize, device: &burn::tensor::Device) -> ShippedModels {
    let dir = common::repo_root().join("weights");
    let read = |name: &str| std::fs::read(dir.join(name)).unwrap();
    let mut vae: Value = serde_json::from_slice(&read("vae.manifest.json")).unwrap();
    let mut dit: Value = serde_json::from_slice(&read("dit.manifest.json")).unwrap();
    let model = &mut vae["model"];
    let ratio = model["num_vertices"].as_u64().unwrap() / model["num_latents"].as_u64().unwrap();
    let latents = vertices as u64 / ratio;
    model["num_vertices"] = vertices.into();
    model["num_latents"] = latents.into();
    let trained = dit["model"]["num_latents"].clone();
    dit["model"]["count_divisor"] = trained;
    dit["model"]["num_latents"] = latents.into();
    ShippedModels::from_bytes(
        &serde_json::to_vec(&vae).unwrap(),
        &read("vae.safetensors"),
        &serde_json::to_vec(&dit).unwrap(),
        &read("dit.safetensors"),
        device,
    )
    .expect("the raised pair loads")
}

#[test]
fn a_raised_capacity_keeps_small_meshes_and_makes_larger_ones() {
    let (shipped, device) = common::shipped_on_cpu();
    let big = raised(2048, &device);
    let points = vec![common::lantern_points()];
    let opts = GenerateOptions {
        samples: 3,
        ..GenerateOptions::default()
    };
    let run = |models: &ShippedModels, opts: &GenerateOptions| {
        models
            .generator(&device)
            .generate(&points, opts, &mut |_, _| true)
    };
    let before = run(&shipped, &opts).unwrap().remove(0);
    let after = run(&big, &opts).unwrap().remove(0);
    assert!(before.vertex_budget <= 512);
    assert_eq!(after.vertex_budget, before.vertex_budget);
    assert_eq!(after.mesh.faces, before.mesh.faces);
    assert_eq!(after.mesh.positions, before.mesh.positions);

    // Unsharpened: sharpening merges flat regions, so its count says less about the model.
    let mut large = GenerateOptions {
        samples: 1,
        vertices: Some(1000),
        ..GenerateOptions::default()
    };
    large.sharpen.enabled = false;
    match run(&shipped, &large) {
        Err(GenerateError::Budget {
            asked: 1000,
            max: 512,
        }) => {}
        other => panic!(
            "the shipped pair must refuse 1,000 vertices: {:?}",
            other.err()
        ),
    }
    let made = run(&big, &large).unwrap().remove(0);
    assert_eq!(made.vertex_budget, 1000);
    assert!(
        made.mesh.positions.len() > 512,
        "{} vertices",
        made.mesh.positions.len()
    );
}
