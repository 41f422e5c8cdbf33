//! Candidates drawn in parts (the browser's workers each draw a run of them) are the
//! candidates drawn in one batch: candidate `j` is seeded by `seed + j` whatever batch it is
//! drawn in, and a row of a batch does not depend on the other rows.

mod common;

use meshflow::pipeline::generate::GenerateOptions;

#[test]
fn candidates_drawn_in_parts_are_the_candidates_drawn_at_once() {
    let (models, device) = common::shipped_on_cpu();
    let generator = models.generator(&device);
    let points = common::lantern_points();
    let mut one = GenerateOptions {
        samples: 1,
        ..GenerateOptions::default()
    };
    one.sharpen.enabled = false;
    let all = generator
        .generate(&vec![points.clone(); 12], &one, &mut |_, _| true)
        .unwrap();
    let later = generator
        .generate(
            &vec![points.clone(); 5],
            &GenerateOptions {
                seed: 7,
                ..one.clone()
            },
            &mut |_, _| true,
        )
        .unwrap();
    for (j, g) in later.iter().enumerate() {
        let whole = &all[7 + j];
        assert_eq!(g.mesh.faces, whole.mesh.faces, "candidate {}", 7 + j);
        let worst = g
            .mesh
            .positions
            .iter()
            .zip(&whole.mesh.positions)
            .map(|(a, b)| (*a - *b).abs().max_element())
            .fold(0.0f32, f32::max);
        eprintln!("candidate {}: max |dv| {worst:e}", 7 + j);
        assert_eq!(
            g.mesh.positions,
            whole.mesh.positions,
            "candidate {}",
            7 + j
        );
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
