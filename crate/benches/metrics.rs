//! Timing of the evaluation protocol: `compare_meshes` at 5,000 samples per side.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use meshflow::eval::metrics::{CompareOptions, chamfer_hausdorff, compare_meshes};
use meshflow::geometry::primitives::icosphere;
use meshflow::geometry::sample::sample_surface;

fn bench(c: &mut Criterion) {
    let opts = CompareOptions::default();
    let ico3 = icosphere(3);
    let ico4 = icosphere(4);
    c.bench_function("compare_meshes ico4 vs ico3, 5000 samples", |b| {
        b.iter(|| compare_meshes(black_box(&ico4), black_box(&ico3), &opts).unwrap())
    });
    c.bench_function("compare_meshes ico3 vs ico3, 5000 samples", |b| {
        b.iter(|| compare_meshes(black_box(&ico3), black_box(&ico3), &opts).unwrap())
    });
    c.bench_function("sample_surface ico4, 5000", |b| {
        b.iter(|| sample_surface(black_box(&ico4), 5000, 1).unwrap())
    });
    let a = sample_surface(&ico4, 5000, 1).unwrap().points;
    let bb = sample_surface(&ico3, 5000, 2).unwrap().points;
    c.bench_function("chamfer_hausdorff 5000 x 5000", |b| {
        b.iter(|| chamfer_hausdorff(black_box(&a), black_box(&bb)).unwrap())
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
