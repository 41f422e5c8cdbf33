//! Sharpening gives the same mesh from fitted positions that differ by a few units in the
//! last place: what the CPU kernels natively and inside WebAssembly hand it (they round the
//! model's outputs differently, and the fitted positions differ by up to about 5 ulps; see
//! the browser test "the CPU path inside wasm and `meshflow generate` make the same mesh at
//! the defaults"). Its collapses are greedy and ordered by float costs, so without a common
//! start two near-equal costs change places and the meshes part.

mod common;

use glam::Vec3;
use meshflow::io::{Limits, read_path};
use meshflow::pipeline::generate::{GenerateOptions, Generated, input_points, keep_sharpened};

/// `x` moved by `ulps` units in the last place (toward +inf for positive `ulps` on a
/// positive `x`).
fn nudged(x: f32, ulps: i32) -> f32 {
    if x == 0.0 {
        return x;
    }
    f32::from_bits((x.to_bits() as i64 + i64::from(ulps)) as u32)
}

/// `g` with each coordinate moved by -3..=3 ulps, a fixed pattern per coordinate.
fn perturbed(g: &Generated) -> Generated {
    let mut p = g.clone();
    let mut state = 0x9e37_79b9_u32;
    for v in &mut p.mesh.positions {
        *v = Vec3::from_array(v.to_array().map(|x| {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            nudged(x, (state >> 29) as i32 - 3)
        }));
    }
    p.input_score = None;
    p
}

#[test]
fn sharpening_is_the_same_from_positions_a_few_ulps_apart() {
    let root = common::repo_root();
    let (models, device) = common::shipped_on_cpu();
    let generator = models.generator(&device);
    let mut unsharpened = GenerateOptions {
        samples: 1,
        ..GenerateOptions::default()
    };
    unsharpened.sharpen.enabled = false;
    let sharpened = GenerateOptions {
        samples: 1,
        ..GenerateOptions::default()
    };
    let mut differ = Vec::new();
    for file in [
        "tests/fixtures/points/stone_lantern_2048.ply",
        "web/examples/milk_truck_4096.ply",
        "web/examples/panda_walk_noisy_4096.ply",
        "web/examples/engine_normals_3072.ply",
    ] {
        let input = read_path(&root.join(file), &Limits::default()).unwrap();
        let points = input_points(&input, 0).unwrap();
        let fitted = generator
            .generate(std::slice::from_ref(&points), &unsharpened, &mut |_, _| {
                true
            })
            .unwrap()
            .remove(0);
        let a = keep_sharpened(vec![fitted.clone()], &points, &sharpened);
        let b = keep_sharpened(vec![perturbed(&fitted)], &points, &sharpened);
        assert!(a.sharpen.ran(), "{file}: sharpening did not run");
        eprintln!(
            "{file}: {} faces fitted, {} and {} sharpened",
            fitted.mesh.faces.len(),
            a.mesh.faces.len(),
            b.mesh.faces.len()
        );
        if a.mesh.faces != b.mesh.faces || a.mesh.positions != b.mesh.positions {
            differ.push(file);
        }
    }
    assert!(differ.is_empty(), "sharpened meshes differ: {differ:?}");
}
