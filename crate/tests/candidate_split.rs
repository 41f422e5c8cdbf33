//! Candidates drawn in parts (the browser's workers and threads each draw a run of them) are
//! the candidates that one generation draws: candidate `j` is seeded by `candidate_seed(seed,
//! j)` whatever run it is drawn in, and a row of a batch does not depend on the other rows.

mod common;

use glam::Vec3;
use meshflow::pipeline::generate::{GenerateOptions, Generated, Generator, keep_sharpened};

/// One candidate, unsharpened: a candidate as the default path draws it.
fn one_candidate() -> GenerateOptions {
    let mut one = GenerateOptions {
        samples: 1,
        ..GenerateOptions::default()
    };
    one.sharpen.enabled = false;
    one
}

/// The candidates of `runs` (`(first, count)` each), drawn as the browser draws them
/// ([`Generator::prepare_runs`], then each run sampled, decoded and extracted).
fn draw(
    generator: &Generator<'_>,
    points: &[Vec3],
    opts: &GenerateOptions,
    runs: &[(usize, usize)],
) -> Vec<Generated> {
    let prepared = generator.prepare_runs(points, opts, runs).unwrap();
    assert_eq!(prepared.len(), runs.len());
    let mut drawn = Vec::new();
    for p in prepared {
        let x = generator.sample(&p, opts, &mut |_, _| true).unwrap();
        drawn.extend(generator.decode_and_extract(p, x, opts).unwrap());
    }
    drawn
}

/// The same faces, and positions no more than `tolerance` apart.
fn assert_near(a: &Generated, b: &Generated, tolerance: f32, what: &str) {
    assert_eq!(a.mesh.faces, b.mesh.faces, "{what}");
    let worst = (a.mesh.positions.iter().zip(&b.mesh.positions))
        .map(|(p, q)| (*p - *q).abs().max_element())
        .fold(0.0f32, f32::max);
    assert!(worst <= tolerance, "{what}: max |dv| {worst:e}");
}

fn assert_same(a: &Generated, b: &Generated, what: &str) {
    assert_near(a, b, 0.0, what);
}

/// The runs of the threaded module (`(0, 5), (5, 7)`) and of a worker (`(7, 5)`) draw the
/// candidates of one run of 12; the first is the one-sample mesh and the mesh kept from the
/// twelve is the one [`Generator::generate`] keeps.
#[test]
fn candidates_drawn_in_parts_are_the_candidates_drawn_at_once() {
    let (models, device) = common::shipped_on_cpu();
    let generator = models.generator(&device);
    let points = common::lantern_points();
    let opts = GenerateOptions {
        samples: 12,
        ..one_candidate()
    };
    let all = draw(&generator, &points, &opts, &[(0, 12)]);
    assert_eq!(all.len(), 12);
    let parts = draw(&generator, &points, &opts, &[(0, 5), (5, 7)]);
    for (j, (g, whole)) in parts.iter().zip(&all).enumerate() {
        assert_same(g, whole, &format!("candidate {j} in runs of 5 and 7"));
    }
    let later = draw(&generator, &points, &opts, &[(7, 5)]);
    for (j, g) in later.iter().enumerate() {
        assert_same(
            g,
            &all[7 + j],
            &format!("candidate {} in a run from 7", 7 + j),
        );
    }
    let one = generator
        .generate(
            std::slice::from_ref(&points),
            &one_candidate(),
            &mut |_, _| true,
        )
        .unwrap();
    // A batch of one multiplies in another order than a batch of several.
    assert_near(&one[0], &all[0], 1e-4, "candidate 0 against one sample");
    let kept = generator
        .generate(std::slice::from_ref(&points), &opts, &mut |_, _| true)
        .unwrap();
    assert_same(
        &kept[0],
        &keep_sharpened(all, &points, &opts),
        "the kept candidate",
    );
}

/// The next seed draws other candidates: until 2026-12-07 candidate `j` took `seed + j`, and
/// seeds 2 to 9 gave the clean box the same mesh, byte for byte.
#[test]
fn neighbouring_seeds_draw_other_candidates() {
    let (models, device) = common::shipped_on_cpu();
    let generator = models.generator(&device);
    let points = common::lantern_points();
    let at = |seed| {
        let opts = GenerateOptions {
            samples: 3,
            seed,
            ..one_candidate()
        };
        draw(&generator, &points, &opts, &[(0, 3)])
    };
    let (a, b) = (at(4), at(5));
    for (j, g) in a.iter().enumerate() {
        for (i, h) in b.iter().enumerate() {
            assert_ne!(
                g.mesh.positions, h.mesh.positions,
                "candidate {j} of seed 4 is candidate {i} of seed 5"
            );
        }
    }
}

/// On the CPU the generator draws a batch in one run per thread at once; the meshes are the
/// ones a single thread draws in one batch (the default path: 12 candidates, sharpening on).
#[test]
fn runs_on_threads_give_the_single_threaded_mesh() {
    let (models, device) = common::shipped_on_cpu();
    let generator = models.generator(&device);
    let points = vec![common::lantern_points()];
    let opts = GenerateOptions::default();
    let generate = || {
        generator
            .generate(&points, &opts, &mut |_, _| true)
            .unwrap()
            .remove(0)
    };
    let threads = rayon::ThreadPoolBuilder::new()
        .num_threads(3)
        .build()
        .unwrap()
        .install(generate);
    let single = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(generate);
    assert_eq!(threads.mesh.faces, single.mesh.faces);
    assert_eq!(threads.mesh.positions, single.mesh.positions);
    assert_eq!(threads.input_score, single.input_score);
}
