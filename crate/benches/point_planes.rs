//! Timing of sharpening's input planes (`PointPlanes::new`: each point's plane from its 12
//! nearest points, then the planar regions grown over them) on three bundled inputs: a
//! curved scan, a flat-sided one, and a box with 1% noise.

use std::hint::black_box;
use std::path::Path;

use criterion::{Criterion, criterion_group, criterion_main};
use meshflow::io::{Limits, read_path};
use meshflow::surface::sharpen::PointPlanes;

fn bench(c: &mut Criterion) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    for file in [
        "web/examples/panda_4096.ply",
        "web/examples/milk_truck_4096.ply",
        "tests/fixtures/hard_surface/points/box_noise1.ply",
    ] {
        let points = read_path(&root.join(file), &Limits::default())
            .unwrap()
            .positions;
        c.bench_function(&format!("PointPlanes::new {file}"), |b| {
            b.iter(|| PointPlanes::new(black_box(&points), 12))
        });
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
