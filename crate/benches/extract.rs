//! Extraction (Algorithm 1 and the manifold method) from ground-truth edges on icospheres and
//! from over-connected sphere graphs, and the spacetime threshold on N x 32 embeddings.
//! Run: `cargo bench -p meshflow --bench extract` (add `--features wgpu` for the WGSL kernel on
//! Vulkan). The CPU kernels are single-threaded by construction.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use meshflow::extract::{ExtractMethod, TAU, spacetime_edges};
use meshflow::workloads::{icosphere_edges, over_connected_sphere, random_embeddings};

fn extraction(c: &mut Criterion) {
    for (name, method) in [
        ("paper", ExtractMethod::Paper),
        ("manifold", ExtractMethod::Manifold),
    ] {
        let mut group = c.benchmark_group(format!("extract_from_edges_{name}"));
        for subdivisions in 2..=5 {
            let w = icosphere_edges(subdivisions);
            let id = BenchmarkId::from_parameter(w.positions.len());
            group.bench_with_input(id, &w, |b, w| b.iter(|| w.extract(method)));
        }
        group.finish();
        // What the manifold method is for: a graph whose cliques overlap everywhere.
        let mut group = c.benchmark_group(format!("extract_over_connected_{name}"));
        for n in [512, 2048] {
            let w = over_connected_sphere(n, 8);
            let id = BenchmarkId::from_parameter(n);
            group.bench_with_input(id, &w, |b, w| b.iter(|| w.extract(method)));
        }
        group.finish();
    }
}

fn threshold(c: &mut Criterion) {
    let mut group = c.benchmark_group("spacetime_threshold");
    group.sample_size(20);
    for n in [512, 1024, 2048, 4096, 8192] {
        let emb = random_embeddings(n, 32, 1);
        group.bench_with_input(BenchmarkId::from_parameter(n), &emb, |b, emb| {
            b.iter(|| spacetime_edges(emb, 32, TAU).unwrap())
        });
    }
    group.finish();
}

/// The WGSL threshold (`threshold_gpu`) on burn-wgpu's Vulkan device, read back: what
/// generation pays on a wgpu device instead of reading the embeddings back for the CPU
/// kernel. On lavapipe this is a CPU too, so compare it with the GPU figures with care.
#[cfg(feature = "wgpu")]
fn threshold_gpu(c: &mut Criterion) {
    use burn::tensor::{Tensor, TensorData};
    use meshflow::extract::threshold_gpu::spacetime_edge_bits;
    let Ok(device) = meshflow::device::vulkan() else {
        eprintln!("no Vulkan device: skipping the GPU threshold");
        return;
    };
    let mut group = c.benchmark_group("spacetime_threshold_wgpu");
    group.sample_size(10);
    for n in [512, 1024, 2048, 4096] {
        let emb = random_embeddings(n, 32, 1);
        let emb = Tensor::<3>::from_data(TensorData::new(emb, [1, n, 32]), &device);
        let mask = Tensor::<3>::ones([1, n, 1], &device);
        group.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, _| {
            b.iter(|| {
                spacetime_edge_bits(emb.clone(), mask.clone(), TAU)
                    .unwrap()
                    .into_data()
            })
        });
    }
    group.finish();
}

#[cfg(not(feature = "wgpu"))]
fn threshold_gpu(_: &mut Criterion) {}

criterion_group!(benches, extraction, threshold, threshold_gpu);
criterion_main!(benches);
