//! The inference path (`meshflow::pipeline::generate`) with the shipped VAE (`weights/`) and a small
//! seeded DiT, so the test does not depend on the shipped DiT's training: outputs are valid meshes in the
//! input's frame, seeding is reproducible and batch-independent, cancellation and bad input
//! give typed errors.

use burn::tensor::Device;
use glam::Vec3;
use meshflow::eval::metrics::chamfer_hausdorff;
use meshflow::geometry::primitives::icosphere;
use meshflow::geometry::sample::sample_surface;
use meshflow::model::dit::{Dit, DitConfig};
use meshflow::model::sampler::SampleError;
use meshflow::model::{MeshVae, TensorMap, VaeConfig, load_module, seeded_init};
use meshflow::pipeline::generate::{
    GenerateError, GenerateOptions, Generator, input_points, to_model_frame,
};

struct Models {
    vae: MeshVae,
    vae_cfg: VaeConfig,
    dit: Dit,
    dit_cfg: DitConfig,
    mean: Vec<f32>,
    std: Vec<f32>,
    device: Device,
}

fn models() -> Models {
    models_reading(0)
}

/// The shipped VAE and a seeded DiT that cross-attends to `point_tokens` input points.
fn models_reading(point_tokens: usize) -> Models {
    let device = Device::flex();
    let weights = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../weights"));
    let manifest: serde_json::Value =
        serde_json::from_slice(&std::fs::read(weights.join("vae.manifest.json")).unwrap()).unwrap();
    let floats = |key: &str| -> Vec<f32> { serde_json::from_value(manifest[key].clone()).unwrap() };
    let vae_cfg: VaeConfig = serde_json::from_value(manifest["model"].clone()).unwrap();
    let vae_map =
        TensorMap::from_safetensors(&std::fs::read(weights.join("vae.safetensors")).unwrap(), "")
            .unwrap();
    let dit_cfg = DitConfig {
        num_latents: vae_cfg.num_latents,
        latent_dim: vae_cfg.latent_dim,
        width: 48,
        depth: 2,
        num_heads: 2,
        point_tokens,
        count_divisor: 0,
    };
    Models {
        vae: load_module(MeshVae::new(&vae_cfg, &device), &vae_map, &|_| false).unwrap(),
        dit: seeded_init(Dit::new(&dit_cfg, &device), 3),
        mean: floats("latent_mean"),
        std: floats("latent_std"),
        vae_cfg,
        dit_cfg,
        device,
    }
}

impl Models {
    fn generator(&self) -> Generator<'_> {
        Generator::new(
            &self.vae,
            &self.vae_cfg,
            &self.mean,
            &self.std,
            &self.dit,
            &self.dit_cfg,
            &self.device,
        )
    }
}

fn sphere_points(scale: f32, offset: Vec3) -> Vec<Vec3> {
    let points = input_points(&icosphere(2), 0).unwrap();
    points.iter().map(|&p| p * scale + offset).collect()
}

/// One candidate (the default draws 12; one keeps these tests fast).
fn options(steps: usize) -> GenerateOptions {
    GenerateOptions {
        steps,
        vertices: Some(40),
        samples: 1,
        ..Default::default()
    }
}

#[test]
fn generated_meshes_are_valid_and_reported() {
    let m = models();
    let out = m
        .generator()
        .generate(
            &[sphere_points(1.0, Vec3::ZERO)],
            &options(4),
            &mut |_, _| true,
        )
        .unwrap();
    assert_eq!(out.len(), 1);
    let g = &out[0];
    g.mesh.validate().unwrap();
    assert!(!g.mesh.faces.is_empty(), "{:?}", g.extract);
    assert_eq!(g.vertex_budget, 40);
    assert_eq!(g.topology.faces, g.mesh.faces.len());
    assert_eq!(
        (
            g.topology.non_manifold_edges,
            g.topology.inconsistent_winding_edges
        ),
        (0, 0)
    );
    // Sharpening, when it keeps a round, says how many faces it left.
    if g.sharpen.rounds_kept > 0 {
        assert_eq!(g.sharpen.faces_out, g.mesh.faces.len());
    }
    assert!(g.times.sample_s > 0.0 && g.times.decode_s > 0.0);
    // The budget sets the tokens; the decoder's mask picks which of their vertex slots (the
    // budget's length bucket) are real, so the unsharpened mesh holds at most those, plus the
    // vertices completion seeded where the input goes on without them and one for each hole
    // closed by a fan (sharpening's splits and collapses rebuild the connectivity, so its
    // vertex count has no such bound).
    let unsharpened = GenerateOptions {
        sharpen: meshflow::surface::sharpen::SharpenOptions {
            enabled: false,
            ..Default::default()
        },
        ..options(4)
    };
    let u = &m
        .generator()
        .generate(
            &[sphere_points(1.0, Vec3::ZERO)],
            &unsharpened,
            &mut |_, _| true,
        )
        .unwrap()[0];
    assert!(u.extract.input_vertices >= u.vertex_budget);
    let added = u.complete.seeded + u.close.vertices_added;
    assert!(u.mesh.positions.len() <= u.extract.input_vertices + added);
}

#[test]
fn output_follows_the_input_frame() {
    // The model sees the same model-frame points, so moving and scaling the input moves and
    // scales the output by the same transform.
    let m = models();
    let generator = m.generator();
    let a = generator
        .generate(
            &[sphere_points(1.0, Vec3::ZERO)],
            &options(3),
            &mut |_, _| true,
        )
        .unwrap();
    let offset = Vec3::new(10.0, -4.0, 2.5);
    let b = generator
        .generate(&[sphere_points(3.0, offset)], &options(3), &mut |_, _| true)
        .unwrap();
    assert!(!a[0].mesh.faces.is_empty());
    assert_eq!(a[0].mesh.faces, b[0].mesh.faces);
    assert_eq!(a[0].mesh.positions.len(), b[0].mesh.positions.len());
    for (p, q) in a[0].mesh.positions.iter().zip(&b[0].mesh.positions) {
        assert!((*p * 3.0 + offset - *q).length() < 1e-3, "{p} vs {q}");
    }
}

#[test]
fn seeds_reproduce_and_batches_match_single_runs() {
    let m = models();
    let generator = m.generator();
    let inputs = [sphere_points(1.0, Vec3::ZERO), sphere_points(2.0, Vec3::X)];
    let single = generator
        .generate(&inputs[..1], &options(3), &mut |_, _| true)
        .unwrap();
    let again = generator
        .generate(&inputs[..1], &options(3), &mut |_, _| true)
        .unwrap();
    assert_eq!(single[0].mesh.positions, again[0].mesh.positions);
    assert_eq!(single[0].mesh.faces, again[0].mesh.faces);
    let batch = generator
        .generate(&inputs, &options(3), &mut |_, _| true)
        .unwrap();
    assert_eq!(batch.len(), 2);
    assert_eq!(batch[0].mesh.faces, single[0].mesh.faces);
    for (p, q) in batch[0]
        .mesh
        .positions
        .iter()
        .zip(&single[0].mesh.positions)
    {
        assert!((*p - *q).length() < 1e-4);
    }
    let other_seed = GenerateOptions {
        seed: 5,
        ..options(3)
    };
    let different = generator
        .generate(&inputs[..1], &other_seed, &mut |_, _| true)
        .unwrap();
    assert_ne!(different[0].mesh.positions, single[0].mesh.positions);
    // With several candidates too, input k of a batch is the input alone at seed + k: its
    // candidates do not depend on the batch's size (until 2026-12-07 they were seed + k + j n).
    let three = GenerateOptions {
        samples: 3,
        ..options(3)
    };
    let batch = generator
        .generate(&inputs, &three, &mut |_, _| true)
        .unwrap();
    let alone = generator
        .generate(
            &inputs[1..],
            &GenerateOptions { seed: 1, ..three },
            &mut |_, _| true,
        )
        .unwrap();
    assert_eq!(batch[1].mesh.faces, alone[0].mesh.faces);
    for (p, q) in batch[1].mesh.positions.iter().zip(&alone[0].mesh.positions) {
        assert!((*p - *q).length() < 1e-4);
    }
}

/// A pair head ([`VaeConfig::pair_head`]) takes generation through refined pair distances
/// (`DeviceEdges::PairHead`, extraction from a distance matrix) instead of the embeddings; a
/// silent one (output layer zero) must give exactly the mesh the decoder alone gives.
#[test]
fn a_silent_pair_head_generates_the_mesh_of_the_decoder_alone() {
    use meshflow::model::{load_module_keeping, module_tensors};
    let m = models();
    let mut map = module_tensors(&m.vae);
    map.tensors.retain(|name, _| !name.contains("pair_head"));
    let plain_cfg = VaeConfig {
        pair_head: 0,
        ..m.vae_cfg.clone()
    };
    let head_cfg = VaeConfig {
        pair_head: 8,
        ..m.vae_cfg.clone()
    };
    let plain = load_module(MeshVae::new(&plain_cfg, &m.device), &map, &|_| false).unwrap();
    let silent = load_module_keeping(
        seeded_init(MeshVae::new(&head_cfg, &m.device), 1),
        &map,
        &|_| false,
        &|name| name.contains("pair_head"),
    )
    .unwrap();
    assert!(silent.decoder.pair_head.is_some());
    let generate = |vae: &MeshVae, cfg: &VaeConfig| {
        Generator::new(vae, cfg, &m.mean, &m.std, &m.dit, &m.dit_cfg, &m.device)
            .generate(
                &[sphere_points(1.0, Vec3::ZERO)],
                &options(3),
                &mut |_, _| true,
            )
            .unwrap()
            .remove(0)
    };
    let (a, b) = (generate(&plain, &plain_cfg), generate(&silent, &head_cfg));
    assert!(!a.mesh.faces.is_empty());
    assert_eq!(a.mesh, b.mesh);
    assert_eq!(b.topology.non_manifold_edges, 0);
}

/// `meshflow bench pair-head`: the embeddings and their own distance matrix are one graph
/// with one set of margins, so they extract the same faces; only the head's corrections may
/// change the graph. A VAE without a head has nothing to trace.
#[test]
fn the_pair_head_trace_compares_one_graph_in_two_forms() {
    use meshflow::eval::pair_head_extraction::{PairHeadTraceError, trace_pair_head_extraction};
    use meshflow::model::module_tensors;
    let m = models();
    let opts = GenerateOptions {
        samples: 2,
        ..options(2)
    };
    let points = sphere_points(1.0, Vec3::ZERO);
    let trace =
        trace_pair_head_extraction(&m.generator(), &points, &opts, std::time::Duration::ZERO)
            .unwrap();
    assert_eq!(trace.candidates.len(), 2);
    for c in &trace.candidates {
        let counts = |s: &meshflow::eval::pair_head_extraction::SourceTiming| {
            (s.edges, s.clique_faces, s.faces)
        };
        assert!(c.kept_vertices > 0 && c.embeddings.faces > 0, "{c:?}");
        assert_eq!(counts(&c.embeddings), counts(&c.spacetime_distances));
        assert!(c.pair_head_distances.timing.runs >= 5);
    }
    let faces: usize = trace
        .candidates
        .iter()
        .map(|c| c.pair_head_distances.faces)
        .sum();
    assert_eq!(trace.pair_head_distances.faces, faces);

    let mut map = module_tensors(&m.vae);
    map.tensors.retain(|name, _| !name.contains("pair_head"));
    let plain_cfg = VaeConfig {
        pair_head: 0,
        ..m.vae_cfg.clone()
    };
    let plain = load_module(MeshVae::new(&plain_cfg, &m.device), &map, &|_| false).unwrap();
    let generator = Generator::new(
        &plain, &plain_cfg, &m.mean, &m.std, &m.dit, &m.dit_cfg, &m.device,
    );
    let err = trace_pair_head_extraction(&generator, &points, &opts, std::time::Duration::ZERO);
    assert!(matches!(err, Err(PairHeadTraceError::NoPairHead)));
}

#[test]
fn a_dit_that_reads_points_generates_reproducibly_and_batch_independently() {
    let m = models_reading(32);
    let generator = m.generator();
    let inputs = [sphere_points(1.0, Vec3::ZERO), sphere_points(2.0, Vec3::X)];
    let run = |inputs: &[Vec<Vec3>]| {
        generator
            .generate(inputs, &options(3), &mut |_, _| true)
            .unwrap()
    };
    let single = run(&inputs[..1]);
    let g = &single[0];
    g.mesh.validate().unwrap();
    assert!(!g.mesh.faces.is_empty());
    assert_eq!(g.topology.non_manifold_edges, 0);
    assert_eq!(run(&inputs[..1])[0].mesh.positions, g.mesh.positions);
    let batch = run(&inputs);
    assert_eq!(batch[0].mesh.faces, g.mesh.faces);
    for (p, q) in batch[0].mesh.positions.iter().zip(&g.mesh.positions) {
        assert!((*p - *q).length() < 1e-4);
    }
}

#[test]
fn progress_is_reported_and_cancellation_stops_between_steps() {
    let m = models();
    let generator = m.generator();
    let mut seen = Vec::new();
    generator
        .generate(
            &[sphere_points(1.0, Vec3::ZERO)],
            &options(5),
            &mut |i, n| {
                seen.push((i, n));
                true
            },
        )
        .unwrap();
    assert_eq!(seen, (1..=5).map(|i| (i, 5)).collect::<Vec<_>>());
    let err = generator
        .generate(
            &[sphere_points(1.0, Vec3::ZERO)],
            &options(5),
            &mut |i, _| i < 2,
        )
        .unwrap_err();
    assert!(
        matches!(err, GenerateError::Sampling(SampleError::Cancelled(2, 5))),
        "{err}"
    );
}

#[test]
fn awkward_inputs_give_clean_meshes() {
    // Points all on one plane (a card), all on one line, and a sphere with a few far
    // outliers: each gives a manifold, consistently wound mesh without degenerate faces or
    // folded edges (`TopologyReport::folded_edges`: the card no longer comes back as a closed
    // mesh flattened onto its plane, its two sides back to back at the rim), never a panic or
    // a hang.
    let m = models();
    let mut rng = meshflow::rng::Rng::new(11);
    let mut unit = || rng.next_f32() * 2.0 - 1.0;
    let card: Vec<Vec3> = (0..2048)
        .map(|_| Vec3::new(unit(), 0.6 * unit(), 0.0))
        .collect();
    let line: Vec<Vec3> = (0..1024).map(|_| Vec3::new(unit(), 0.0, 0.0)).collect();
    let mut outliers = sphere_points(1.0, Vec3::ZERO);
    outliers.extend([Vec3::splat(40.0), Vec3::new(-30.0, 5.0, 0.0)]);
    let opts = GenerateOptions {
        vertices: None,
        samples: 2,
        ..options(4)
    };
    for (name, points) in [("card", card), ("line", line), ("outliers", outliers)] {
        let out = m
            .generator()
            .generate(&[points], &opts, &mut |_, _| true)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let g = &out[0];
        g.mesh.validate().unwrap();
        let t = &g.topology;
        assert_eq!(
            (
                t.non_manifold_edges,
                t.inconsistent_winding_edges,
                t.degenerate_faces,
                t.folded_edges
            ),
            (0, 0, 0, 0),
            "{name}: {t:?}"
        );
    }
}

#[test]
fn bad_inputs_are_typed_errors() {
    let m = models();
    let generator = m.generator();
    let run = |points: Vec<Vec3>, opts: GenerateOptions| {
        generator
            .generate(&[points], &opts, &mut |_, _| true)
            .unwrap_err()
    };
    assert!(matches!(run(vec![], options(2)), GenerateError::NoPoints));
    assert!(matches!(
        run(vec![Vec3::ONE, Vec3::new(f32::NAN, 0.0, 0.0)], options(2)),
        GenerateError::NonFinite(1)
    ));
    assert!(matches!(
        run(vec![Vec3::ONE; 10], options(2)),
        GenerateError::Degenerate
    ));
    let few: Vec<Vec3> = (0..15)
        .map(|i| Vec3::new(i as f32, (i * i) as f32, 0.0))
        .collect();
    assert!(matches!(
        run(few, options(2)),
        GenerateError::TooFewPoints { got: 15, min: 16 }
    ));
    let points = sphere_points(1.0, Vec3::ZERO);
    for asked in [0, 513] {
        let opts = GenerateOptions {
            vertices: Some(asked),
            ..options(2)
        };
        let err = run(points.clone(), opts);
        assert!(
            matches!(err, GenerateError::Budget { max: 512, .. }),
            "{err}"
        );
    }
    let both = GenerateOptions {
        faces: Some(100),
        ..options(2)
    };
    assert!(matches!(
        run(points.clone(), both),
        GenerateError::VerticesAndFaces
    ));
    for asked in [0, 12, 841, 100_000] {
        let opts = GenerateOptions {
            vertices: None,
            faces: Some(asked),
            ..options(2)
        };
        let err = run(points.clone(), opts);
        assert!(
            matches!(
                err,
                GenerateError::Faces {
                    min: 13,
                    max: 840,
                    ..
                }
            ),
            "{err}"
        );
    }
    let no_steps = GenerateOptions {
        steps: 0,
        ..options(2)
    };
    assert!(matches!(
        run(points, no_steps),
        GenerateError::Sampling(SampleError::NoSteps)
    ));
}

#[test]
fn default_budget_comes_from_the_rule_within_the_vae_size() {
    let m = models();
    let opts = GenerateOptions {
        vertices: None,
        ..options(2)
    };
    let out = m
        .generator()
        .generate(&[sphere_points(1.0, Vec3::ZERO)], &opts, &mut |_, _| true)
        .unwrap();
    let (model_points, _) = to_model_frame(&sphere_points(1.0, Vec3::ZERO)).unwrap();
    let features = meshflow::pipeline::budget::shape_features(&model_points, 0);
    assert_eq!(out[0].features, features);
    assert_eq!(
        out[0].vertex_budget,
        meshflow::pipeline::budget::DEFAULT_RULE.budget(&features, 512)
    );
    // The budget is the input's, not the seed's: another seed, another input of the same
    // batch and the candidates of `--samples` all measure the same features.
    let seeded = |seed: u64, inputs: &[Vec<Vec3>], samples: usize| {
        let opts = GenerateOptions {
            seed,
            samples,
            ..opts.clone()
        };
        m.generator()
            .generate(inputs, &opts, &mut |_, _| true)
            .unwrap()
    };
    let sphere = sphere_points(1.0, Vec3::ZERO);
    // The same shape moved and scaled: the same model-frame points up to rounding.
    let moved = sphere_points(2.0, Vec3::X);
    let batch = seeded(7, &[moved, sphere.clone()], 1);
    assert_eq!(batch[0].vertex_budget, out[0].vertex_budget);
    for g in batch[1..].iter().chain(&seeded(3, &[sphere], 3)) {
        assert_eq!(g.features, features);
        assert_eq!(g.vertex_budget, out[0].vertex_budget);
    }
}

#[test]
fn meshes_are_surface_sampled_and_point_clouds_kept() {
    let sphere = icosphere(1);
    let sampled = input_points(&sphere, 3).unwrap();
    assert_eq!(
        sampled.len(),
        meshflow::pipeline::generate::CONDITION_POINTS
    );
    let cloud = meshflow::Mesh::from_points(sphere.positions.clone());
    assert_eq!(input_points(&cloud, 3).unwrap(), sphere.positions);
    let big = meshflow::Mesh::from_points(sampled.iter().chain(&sampled).copied().collect());
    assert_eq!(
        input_points(&big, 3).unwrap().len(),
        meshflow::pipeline::generate::CONDITION_POINTS
    );
}

/// Mean distance from each vertex to its nearest input point.
fn mean_distance(vertices: &[Vec3], points: &[Vec3]) -> f32 {
    let sum: f32 = vertices
        .iter()
        .map(|v| {
            points
                .iter()
                .map(|p| p.distance(*v))
                .fold(f32::INFINITY, f32::min)
        })
        .sum();
    sum / vertices.len() as f32
}

#[test]
fn fitting_puts_the_vertices_on_the_input_and_can_be_turned_off() {
    let m = models();
    let generator = m.generator();
    let points = sphere_points(2.0, Vec3::new(1.0, 0.0, -3.0));
    let raw = GenerateOptions {
        fit: meshflow::surface::fit::FitOptions::OFF,
        complete: meshflow::surface::complete::CompleteOptions {
            enabled: false,
            ..Default::default()
        },
        sharpen: meshflow::surface::sharpen::SharpenOptions {
            enabled: false,
            ..Default::default()
        },
        ..options(3)
    };
    // Fitting is judged before sharpening, which moves vertices off the samples and onto
    // the planes between them.
    let unsharpened = GenerateOptions {
        sharpen: meshflow::surface::sharpen::SharpenOptions {
            enabled: false,
            ..Default::default()
        },
        ..options(3)
    };
    let before = generator
        .generate(std::slice::from_ref(&points), &raw, &mut |_, _| true)
        .unwrap();
    let after = generator
        .generate(std::slice::from_ref(&points), &unsharpened, &mut |_, _| {
            true
        })
        .unwrap();
    let sharpened = generator
        .generate(std::slice::from_ref(&points), &options(3), &mut |_, _| true)
        .unwrap();
    let (before, after, sharpened) = (&before[0], &after[0], &sharpened[0]);
    assert_eq!(before.fit.iterations, 0);
    assert_eq!(after.fit.iterations, 3);
    let (d0, d1) = (
        mean_distance(&before.mesh.positions, &points),
        mean_distance(&after.mesh.positions, &points),
    );
    // The untrained DiT's vertices are anywhere; fitted, they sit on the sphere's samples.
    assert!(d1 < 0.5 * d0, "mean vertex distance {d0} -> {d1}");
    // Without completion nothing is closed either: the model's own faces.
    assert_eq!(
        before.close,
        meshflow::surface::close::CloseReport::default()
    );
    // Hole closing only adds to the same completed mesh, and can be turned off (compared
    // before sharpening, which changes the faces).
    let closed = after;
    let open = GenerateOptions {
        close: meshflow::surface::close::CloseOptions {
            enabled: false,
            ..Default::default()
        },
        ..unsharpened
    };
    let open = &generator
        .generate(std::slice::from_ref(&points), &open, &mut |_, _| true)
        .unwrap()[0];
    assert_eq!(open.close, meshflow::surface::close::CloseReport::default());
    assert!(closed.topology.holes <= open.topology.holes);
    assert_eq!(
        closed.mesh.faces.len(),
        open.mesh.faces.len() + closed.close.faces_added - closed.close.faces_cut
    );
    // Sharpening keeps the holes it was given, less those closed after it.
    assert!(sharpened.topology.holes <= closed.topology.holes);
    assert_eq!(
        sharpened.topology.holes < closed.topology.holes,
        sharpened.sharpen.holes_closed > 0
    );
    assert_eq!(closed.sharpen, Default::default());
    assert!(
        sharpened.sharpen.refined_faces > 0,
        "{:?}",
        sharpened.sharpen
    );
    for g in [before, after, sharpened, open] {
        g.mesh.validate().unwrap();
        assert_eq!(g.topology.non_manifold_edges, 0);
        assert_eq!(g.topology.inconsistent_winding_edges, 0);
    }
}

#[test]
fn a_face_count_sets_the_vertex_budget() {
    let m = models();
    let opts = GenerateOptions {
        vertices: None,
        faces: Some(90),
        ..options(2)
    };
    let out = m
        .generator()
        .generate(&[sphere_points(1.0, Vec3::ZERO)], &opts, &mut |_, _| true)
        .unwrap();
    assert_eq!(
        out[0].vertex_budget,
        meshflow::pipeline::generate::budget_for_faces(90, 512).unwrap()
    );
    assert_eq!(out[0].vertex_budget, 55);
}

#[test]
fn more_samples_keep_the_candidate_closest_to_the_input_with_holes_counted() {
    let models = models();
    let generator = models.generator();
    let points = sphere_points(2.0, Vec3::new(1.0, 0.0, -3.0));
    let run = |opts: &GenerateOptions| {
        generator
            .generate(std::slice::from_ref(&points), opts, &mut |_, _| true)
            .unwrap()
            .remove(0)
    };
    // The choice is made before sharpening (which only the kept mesh gets), so it is
    // compared on unsharpened meshes.
    let base = GenerateOptions {
        sharpen: meshflow::surface::sharpen::SharpenOptions {
            enabled: false,
            ..Default::default()
        },
        ..options(3)
    };
    let kept = run(&GenerateOptions {
        samples: 4,
        seed: 10,
        ..base.clone()
    });
    // Candidate j is the one-sample mesh of candidate_seed(10, j); the kept one is among them,
    // with the smallest score: Chamfer distance of its surface to the input points, times one
    // plus HOLE_WEIGHT per hole.
    let singles: Vec<_> = (0..4)
        .map(|j| {
            run(&GenerateOptions {
                seed: meshflow::pipeline::generate::candidate_seed(10, j),
                ..base.clone()
            })
        })
        .collect();
    let score = |g: &meshflow::pipeline::generate::Generated| {
        let surface = sample_surface(&g.mesh, 2048, 0).unwrap();
        chamfer_hausdorff(&surface.points, &points).unwrap().chamfer
            * (1.0 + meshflow::pipeline::generate::HOLE_WEIGHT * g.topology.holes as f64)
    };
    let scores: Vec<f64> = singles.iter().map(score).collect();
    let kept_at = singles
        .iter()
        .position(|g| g.mesh.faces == kept.mesh.faces && g.mesh.positions == kept.mesh.positions)
        .expect("the kept mesh is none of the candidates");
    let best = scores.iter().cloned().fold(f64::INFINITY, f64::min);
    assert_eq!(scores[kept_at], best, "kept {kept_at} of scores {scores:?}");
    // Out of range: a typed error before any sampling.
    for samples in [0, meshflow::pipeline::generate::MAX_SAMPLES + 1] {
        let err = generator
            .generate(
                std::slice::from_ref(&points),
                &GenerateOptions {
                    samples,
                    ..options(3)
                },
                &mut |_, _| true,
            )
            .unwrap_err();
        assert!(
            matches!(err, GenerateError::Samples(s) if s == samples),
            "{err}"
        );
    }
}
