//! Extraction from ground-truth edges on icospheres and the spacetime threshold on N x 32
//! embeddings: the two figures DESIGN.md section 4 compares with the reference.
//! Run: `cargo bench -p meshflow --bench extract`. Single-threaded by construction.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use meshflow::extract::{TAU, spacetime_edges};
use meshflow::workloads::{icosphere_edges, random_embeddings};

fn extraction(c: &mut Criterion) {
    let mut group = c.benchmark_group("extract_from_edges");
    for subdivisions in 2..=5 {
        let w = icosphere_edges(subdivisions);
        let id = BenchmarkId::from_parameter(w.positions.len());
        group.bench_with_input(id, &w, |b, w| b.iter(|| w.extract()));
    }
    group.finish();
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

criterion_group!(benches, extraction, threshold);
criterion_main!(benches);
