//! The WGSL spacetime threshold (`shaders/spacetime_threshold.wgsl`, `meshflow::extract::threshold_gpu`)
//! on burn-wgpu over Vulkan (lavapipe in CI) against the CPU kernel and the reference's edges.
#![cfg(feature = "wgpu")]

mod common;

use burn::tensor::{Device, Tensor, TensorData};
use common::Golden;
use meshflow::extract::threshold_gpu::{GpuThresholdError, spacetime_edge_bits, words_per_row};
use meshflow::extract::{
    DecodedEdges, DecodedVertices, ExtractOptions, edges_from_bits, extract_from_decoded,
    spacetime_distance, spacetime_edges,
};
use meshflow::model::dit::{Dit, DitConfig};
use meshflow::model::{MeshVae, TensorMap, VaeConfig, load_module, seeded_init};
use meshflow::pipeline::generate::{DeviceEdges, Generator, read_bits};
use meshflow::rng::Rng;

const TAU: f32 = 0.6;

fn vulkan() -> Device {
    meshflow::device::vulkan().expect("a Vulkan device (lavapipe in CI)")
}

/// Runs the kernel on `[b, n, dim]` embeddings and `[b, n]` logits; returns the bit rows.
fn gpu_bits(emb: &[f32], logits: &[f32], b: usize, n: usize, dim: usize) -> Vec<u32> {
    let device = vulkan();
    let emb = Tensor::<3>::from_data(TensorData::new(emb.to_vec(), [b, n, dim]), &device);
    let logits = Tensor::<3>::from_data(TensorData::new(logits.to_vec(), [b, n, 1]), &device);
    let bits = spacetime_edge_bits(emb, logits, TAU).unwrap();
    assert_eq!(bits.dims(), [b, n, words_per_row(n)]);
    read_bits(bits.try_into_data()).unwrap()
}

#[test]
fn the_kernel_finds_the_reference_edges() {
    let g = Golden::load("vae_small");
    let emb = g.f32("input.synthetic_adjacency_emb");
    assert_eq!(emb.shape, vec![64, 32]);
    let bits = gpu_bits(&emb.data, &[1.0; 64], 1, 64, 32);
    let edges = edges_from_bits(&bits, 2, 64).unwrap();
    assert_eq!(edges.len(), 583);
    assert_eq!(edges, g.pairs("output.synthetic_spacetime_edges"));
}

#[test]
fn the_kernel_agrees_with_the_cpu_threshold_on_masked_batches() {
    // Three meshes of 77 vertices (three words per row, the last one partly past n), a third of
    // them masked out, with embeddings scaled so that many pairs fall near tau.
    let (b, n, dim) = (3, 77, 32);
    let mut rng = Rng::new(11);
    let emb: Vec<f32> = (0..b * n * dim)
        .map(|_| rng.normal() as f32 * 0.18)
        .collect();
    let logits: Vec<f32> = (0..b * n).map(|_| rng.next_f32() * 3.0 - 1.0).collect();
    let bits = gpu_bits(&emb, &logits, b, n, dim);
    let words = words_per_row(n);

    let mut total = 0;
    for k in 0..b {
        let rows = &bits[k * n * words..(k + 1) * n * words];
        let gpu = edges_from_bits(rows, words, n).unwrap();
        let kept: Vec<usize> = (0..n).filter(|&i| logits[k * n + i] > 0.0).collect();
        let h = |i: usize| &emb[(k * n + i) * dim..(k * n + i + 1) * dim];
        let kept_emb: Vec<f32> = kept.iter().flat_map(|&i| h(i).iter().copied()).collect();
        let cpu: Vec<[u32; 2]> = spacetime_edges(&kept_emb, dim, TAU)
            .unwrap()
            .into_iter()
            .map(|[a, c]| [kept[a as usize] as u32, kept[c as usize] as u32])
            .collect();
        // Masked rows and columns carry no bits.
        for &[i, j] in &gpu {
            assert!(logits[k * n + i as usize] > 0.0 && logits[k * n + j as usize] > 0.0);
        }
        // Any disagreement must be a pair within rounding of tau.
        let differing: Vec<_> = gpu
            .iter()
            .filter(|e| !cpu.contains(e))
            .chain(cpu.iter().filter(|e| !gpu.contains(e)))
            .collect();
        for &&[i, j] in &differing {
            let d = spacetime_distance(h(i as usize), h(j as usize));
            assert!((d - TAU).abs() < 1e-5, "mesh {k}: ({i}, {j}) at d = {d}");
        }
        assert!(differing.len() <= 1, "mesh {k}: {differing:?}");
        total += gpu.len();
    }
    // Enough edges that the comparison means something, far from all pairs.
    assert!(total > 200 && total < b * n * n / 4, "{total} edges");
}

#[test]
fn the_kernel_refuses_flex_tensors_and_bad_shapes() {
    let flex = Device::flex();
    let emb = Tensor::<3>::zeros([1, 4, 32], &flex);
    let logits = Tensor::<3>::zeros([1, 4, 1], &flex);
    assert_eq!(
        spacetime_edge_bits(emb, logits, TAU).unwrap_err(),
        GpuThresholdError::NotOnWgpu
    );
    let device = vulkan();
    let emb = Tensor::<3>::zeros([1, 4, 31], &device);
    let logits = Tensor::<3>::zeros([1, 4, 1], &device);
    assert!(matches!(
        spacetime_edge_bits(emb, logits, TAU),
        Err(GpuThresholdError::Shapes(..))
    ));
}

/// The shipped VAE decodes seeded latents on lavapipe through [`Generator::decode`], which
/// thresholds on the device; the bits and the host's threshold of the read-back embeddings
/// disagree at most on pairs within rounding of tau, and where they agree, extraction gives
/// the same meshes.
#[test]
fn decoded_meshes_are_the_same_through_the_gpu_and_cpu_threshold() {
    let device = vulkan();
    let weights = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../weights"));
    let manifest: serde_json::Value =
        serde_json::from_slice(&std::fs::read(weights.join("vae.manifest.json")).unwrap()).unwrap();
    let floats = |key: &str| -> Vec<f32> { serde_json::from_value(manifest[key].clone()).unwrap() };
    let (mean, std) = (floats("latent_mean"), floats("latent_std"));
    // The device threshold serves decoders without a pair head (a pair head's candidates are
    // chosen on the host): the shipped decoder without its pair head, if it has one.
    let cfg = VaeConfig {
        pair_head: 0,
        ..serde_json::from_value(manifest["model"].clone()).unwrap()
    };
    let map =
        TensorMap::from_safetensors(&std::fs::read(weights.join("vae.safetensors")).unwrap(), "")
            .unwrap();
    let vae = load_module(MeshVae::new(&cfg, &device), &map, &|name| {
        name.contains("pair_head")
    })
    .unwrap();
    // decode() does not use the DiT; any one of the right latent shape will do.
    let dit_cfg = DitConfig {
        num_latents: cfg.num_latents,
        latent_dim: cfg.latent_dim,
        width: 24,
        depth: 2,
        num_heads: 2,
        point_tokens: 0,
        count_divisor: 0,
    };
    let dit = seeded_init(Dit::new(&dit_cfg, &device), 1);
    let generator = Generator::new(&vae, &cfg, &mean, &std, &dit, &dit_cfg, &device);

    let (b, l, d, n) = (2, cfg.num_latents, cfg.latent_dim, cfg.num_vertices);
    let mut rng = Rng::new(5);
    let z: Vec<f32> = (0..b * l * d).map(|_| rng.normal() as f32).collect();
    let z = Tensor::<3>::from_data(TensorData::new(z, [b, l, d]), &device);
    // The device thresholds at the VAE's tau; the host extraction compared with it must too.
    let opts = ExtractOptions::paper().at_tau_of(&cfg);
    let on_gpu = generator.decode(z.clone(), &opts);
    let bits = match on_gpu.edges {
        DeviceEdges::Bits(t) => read_bits(t.try_into_data()).unwrap(),
        DeviceEdges::Embeddings(_) | DeviceEdges::PairHead { .. } => {
            panic!("on Vulkan the threshold runs on the device")
        }
    };
    // The non-manifold filter needs the margins, so it keeps the embeddings.
    let filtered = ExtractOptions {
        drop_non_manifold: true,
        ..opts.clone()
    };
    let on_host = generator.decode(z, &filtered);
    let DeviceEdges::Embeddings(embeddings) = on_host.edges else {
        panic!("the non-manifold filter reads the embeddings back");
    };
    let read = |t: Tensor<3>| -> Vec<f32> { t.into_data().convert::<f32>().try_to_vec().unwrap() };
    let embeddings = read(embeddings);
    let logits = read(on_gpu.mask_logits);
    let positions = read(on_gpu.positions);
    let normals = read(on_gpu.normals);
    let vec3s =
        |f: &[f32]| -> Vec<glam::Vec3> { f.chunks_exact(3).map(glam::Vec3::from_slice).collect() };
    let (e, w) = (cfg.edge_dim, words_per_row(n));
    let mut faces = 0;
    let mut compared = 0;
    for k in 0..b {
        // The device and the host compute each pair's distance in their own order of
        // operations: a pair within rounding of tau may fall on either side (then the meshes
        // may differ, rightly); any other pair must agree.
        let h = |i: usize| &embeddings[(k * n + i) * e..(k * n + i + 1) * e];
        let kept: Vec<usize> = (0..n).filter(|&i| logits[k * n + i] > 0.0).collect();
        let kept_emb: Vec<f32> = kept.iter().flat_map(|&i| h(i).iter().copied()).collect();
        let on_host: Vec<[u32; 2]> = spacetime_edges(&kept_emb, e, opts.tau)
            .unwrap()
            .into_iter()
            .map(|[a, c]| [kept[a as usize] as u32, kept[c as usize] as u32])
            .collect();
        let on_device = edges_from_bits(&bits[k * n * w..(k + 1) * n * w], w, n).unwrap();
        let differing: Vec<_> = on_device
            .iter()
            .filter(|p| !on_host.contains(p))
            .chain(on_host.iter().filter(|p| !on_device.contains(p)))
            .collect();
        for &&[i, j] in &differing {
            let d = spacetime_distance(h(i as usize), h(j as usize));
            // f32 rounding of a sum over the embedding's channels near |tau| = 2.5.
            assert!(
                (d - opts.tau).abs() < 5e-5,
                "mesh {k}: ({i}, {j}) at d = {d}"
            );
        }
        let near_ties = differing.len();
        if near_ties > 0 {
            continue;
        }
        compared += 1;
        let pos = vec3s(&positions[k * n * 3..(k + 1) * n * 3]);
        let nrm = vec3s(&normals[k * n * 3..(k + 1) * n * 3]);
        let decoded = |edges| DecodedVertices {
            mask_logits: &logits[k * n..(k + 1) * n],
            positions: &pos,
            normals: &nrm,
            edges,
        };
        let (gpu, gpu_report) = extract_from_decoded(
            &decoded(DecodedEdges::Bits {
                words: &bits[k * n * w..(k + 1) * n * w],
                words_per_row: w,
            }),
            &opts,
        )
        .unwrap();
        let (cpu, cpu_report) = extract_from_decoded(
            &decoded(DecodedEdges::Embeddings {
                values: &embeddings[k * n * e..(k + 1) * n * e],
                dim: e,
            }),
            &opts,
        )
        .unwrap();
        assert_eq!(gpu_report, cpu_report, "mesh {k}");
        assert_eq!(gpu, cpu, "mesh {k}");
        assert_eq!(gpu_report, cpu_report, "mesh {k}");
        faces += gpu.faces.len();
    }
    assert!(
        compared > 0 && faces > 0,
        "{compared} meshes compared, {faces} faces: the comparison is empty"
    );
}
