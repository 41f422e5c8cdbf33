//! Candidates drawn in parts (the browser's workers each draw a run of them) are the
//! candidates drawn in one batch: candidate `j` is seeded by `seed + j` whatever batch it is
//! drawn in, and a row of a batch does not depend on the other rows.

mod common;

use meshflow::pipeline::generate::GenerateOptions;

/// One candidate, unsharpened: a candidate as the default path draws it.
fn one_candidate() -> GenerateOptions {
    let mut one = GenerateOptions {
        samples: 1,
        ..GenerateOptions::default()
    };
    one.sharpen.enabled = false;
    one
}

#[test]
fn candidates_drawn_in_parts_are_the_candidates_drawn_at_once() {
    let (models, device) = common::shipped_on_cpu();
    let generator = models.generator(&device);
    let points = common::lantern_points();
    let one = one_candidate();
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

/// The browser's threaded module prepares its runs of candidates together (the input
/// conditioned once) and decodes them side by side ([`Generator::prepare_runs`],
/// [`Generator::decode_and_extract`]): the candidates are the ones drawn in one batch.
///
/// [`Generator::prepare_runs`]: meshflow::pipeline::generate::Generator::prepare_runs
/// [`Generator::decode_and_extract`]: meshflow::pipeline::generate::Generator::decode_and_extract
#[test]
fn runs_prepared_together_are_the_candidates_drawn_at_once() {
    let (models, device) = common::shipped_on_cpu();
    let generator = models.generator(&device);
    let points = common::lantern_points();
    let all = generator
        .generate(&vec![points.clone(); 12], &one_candidate(), &mut |_, _| {
            true
        })
        .unwrap();
    let opts = GenerateOptions {
        samples: 12,
        ..one_candidate()
    };
    let runs = [(0, 5), (5, 7)];
    let prepared = generator.prepare_runs(&points, &opts, &runs).unwrap();
    assert_eq!(prepared.len(), runs.len());
    let mut drawn = Vec::new();
    for p in prepared {
        let x = generator.sample(&p, &opts, &mut |_, _| true).unwrap();
        drawn.extend(generator.decode_and_extract(p, x, &opts).unwrap());
    }
    assert_eq!(drawn.len(), all.len());
    for (j, (g, whole)) in drawn.iter().zip(&all).enumerate() {
        assert_eq!(g.mesh.faces, whole.mesh.faces, "candidate {j}");
        assert_eq!(g.mesh.positions, whole.mesh.positions, "candidate {j}");
    }
}
