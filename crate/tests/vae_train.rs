//! MeshVAE training on the CPU backend: a small model overfits a few meshes to edge F1 >= 0.99;
//! a run stopped at a checkpoint, or killed after one, resumes to exactly the same weights and
//! metrics; length buckets batch meshes of one length; bad configurations fail before a step.
#![cfg(feature = "train")]

mod common;

use burn::tensor::Device;
use common::temp_dir;
use meshflow::Mesh;
use meshflow::eval::metrics::edge_scores;
use meshflow::geometry::normalize::Normalization;
use meshflow::geometry::primitives::{cube, grid, icosphere, octahedron};
use meshflow::model::tokens::build_tokens;
use meshflow::model::{MeshVae, load_module};
use meshflow::train::TrainObserver;
use meshflow::train::vae::{
    NonEdgeWeights, TAU_GRID, VaeTrainConfig, best_grid_f1, epoch_batches, make_batch, train_vae,
    validate,
};

fn model_frame(m: Mesh) -> Mesh {
    Normalization::to_model_frame(m.aabb().unwrap()).apply_mesh(&m)
}

fn meshes() -> Vec<Mesh> {
    [octahedron(), cube(), icosphere(1), grid(5, 5)]
        .into_iter()
        .map(model_frame)
        .collect()
}

/// The `tiny` preset with the schedule and losses the overfitting test is tuned for.
fn small_config(steps: usize) -> VaeTrainConfig {
    let mut cfg = meshflow::train::presets::vae_tiny();
    cfg.steps = steps;
    cfg.warmup_steps = 10;
    cfg.learning_rate = 3e-3;
    cfg.final_lr_ratio = 0.1;
    cfg.weight_decay = 0.0;
    cfg.kl_weight = 1e-4;
    cfg.lambda_neg = 0.25;
    cfg.eval_every = 1_000_000;
    cfg.checkpoint_every = 1_000_000;
    cfg
}

/// An observer that prints nothing and stops the run after `stop_at` steps when set.
struct Quiet {
    stop_at: Option<usize>,
    last: usize,
}

impl Quiet {
    fn new() -> Self {
        Self {
            stop_at: None,
            last: 0,
        }
    }
}

impl TrainObserver for Quiet {
    fn step(&mut self, step: usize, _: &str) {
        self.last = step;
    }
    fn note(&mut self, _: &str) {}
    fn stop(&self) -> bool {
        self.stop_at.is_some_and(|s| self.last >= s)
    }
}

#[test]
fn small_vae_overfits_a_few_meshes() {
    let device = Device::flex();
    let cfg = small_config(400);
    let data = meshes();
    let dir = temp_dir("overfit");
    let dir = dir.path();
    let mut quiet = Quiet::new();
    let trained = train_vae(&cfg, &data, &data, dir, &device, &mut quiet).unwrap();
    assert_eq!(trained.steps, 400);
    let vae = load_module(MeshVae::new(&cfg.model, &device), &trained.weights, &|_| {
        false
    })
    .unwrap();
    let v = validate(&vae, &data, &cfg, &device, trained.steps).unwrap();
    eprintln!("{v:?}");
    assert!(v.edge_f1 >= 0.99, "edge F1 {}", v.edge_f1);
    assert!(v.mask_accuracy >= 0.99, "mask accuracy {}", v.mask_accuracy);
    let log = std::fs::read_to_string(dir.join("metrics.jsonl")).unwrap();
    assert!(log.lines().count() >= 400, "a metrics line per step");
}

#[test]
fn resuming_from_a_checkpoint_gives_the_same_weights() {
    let device = Device::flex();
    let mut cfg = small_config(12);
    cfg.augment = true;
    cfg.checkpoint_every = 4;
    cfg.ema_decay = Some(0.9);
    let data = meshes();

    let straight = temp_dir("straight");

    let straight = straight.path();
    let mut quiet = Quiet::new();
    let a = train_vae(&cfg, &data, &data, straight, &device, &mut quiet).unwrap();

    // Stop after step 7 (between scheduled checkpoints: the stop writes one), then start
    // again in the same folder.
    let resumed = temp_dir("resumed");
    let resumed = resumed.path();
    let mut stopping = Quiet {
        stop_at: Some(7),
        last: 0,
    };
    let partial = train_vae(&cfg, &data, &data, resumed, &device, &mut stopping).unwrap();
    assert_eq!(partial.steps, 7);
    let mut quiet = Quiet::new();
    let b = train_vae(&cfg, &data, &data, resumed, &device, &mut quiet).unwrap();
    assert_eq!(b.steps, 12);
    assert_eq!(
        a.weights, b.weights,
        "resumed run matches the straight one exactly"
    );

    // A changed configuration is refused instead of silently mixing runs.
    let mut other = cfg.clone();
    other.learning_rate *= 2.0;
    assert!(train_vae(&other, &data, &data, resumed, &device, &mut quiet).is_err());
}

/// The per-step loss lines of a run's metrics log, without the wall-clock fields.
fn step_losses(dir: &std::path::Path) -> Vec<String> {
    std::fs::read_to_string(dir.join("metrics.jsonl"))
        .unwrap()
        .lines()
        .filter_map(|l| {
            let mut v: serde_json::Value = serde_json::from_str(l).unwrap();
            let o = v.as_object_mut()?;
            o.get("loss")?;
            o.remove("meshes_per_s");
            o.remove("elapsed_s");
            Some(v.to_string())
        })
        .collect()
}

fn copy_dir(from: &std::path::Path, to: &std::path::Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
    }
}

#[test]
fn a_run_killed_after_a_checkpoint_resumes_with_the_same_metrics_and_weights() {
    let device = Device::flex();
    let mut cfg = small_config(12);
    cfg.augment = true;
    cfg.checkpoint_every = 4;
    cfg.ema_decay = Some(0.9);
    cfg.model.length_buckets = true;
    let data = meshes();

    let straight = temp_dir("kill-straight");

    let straight = straight.path();
    let mut quiet = Quiet::new();
    let a = train_vae(&cfg, &data, &data, straight, &device, &mut quiet).unwrap();

    // Run to the step-8 checkpoint and keep a copy of it; run on to step 10, then put the
    // step-8 checkpoint back: the state a kill at step 10 leaves (log ahead of checkpoint).
    let killed = temp_dir("kill-resumed");
    let killed = killed.path();
    let saved = temp_dir("kill-saved");
    let saved = saved.path();
    let mut stopping = Quiet {
        stop_at: Some(8),
        last: 0,
    };
    train_vae(&cfg, &data, &data, killed, &device, &mut stopping).unwrap();
    copy_dir(&killed.join("checkpoint"), saved);
    let mut stopping = Quiet {
        stop_at: Some(10),
        last: 0,
    };
    train_vae(&cfg, &data, &data, killed, &device, &mut stopping).unwrap();
    std::fs::remove_dir_all(killed.join("checkpoint")).unwrap();
    copy_dir(saved, &killed.join("checkpoint"));
    let b = train_vae(&cfg, &data, &data, killed, &device, &mut quiet).unwrap();

    assert_eq!(a.weights, b.weights, "same weights as the unbroken run");
    // The time axis goes on from the checkpoint's time instead of starting again at 0, so a
    // resumed run's curves plot against time as an unbroken run's do.
    let elapsed: Vec<f64> = std::fs::read_to_string(killed.join("metrics.jsonl"))
        .unwrap()
        .lines()
        .filter_map(|l| serde_json::from_str::<serde_json::Value>(l).ok()?["elapsed_s"].as_f64())
        .collect();
    assert_eq!(elapsed.len(), 12);
    assert!(
        elapsed.windows(2).all(|w| w[1] >= w[0]),
        "elapsed_s never goes back across the resume: {elapsed:?}"
    );
    assert!(b.earlier_s > 0.0 && b.earlier_s <= elapsed[8]);
    let (la, lb) = (step_losses(straight), step_losses(killed));
    assert_eq!(la.len(), 12);
    assert_eq!(
        la, lb,
        "same per-step metrics as the unbroken run, each step once"
    );
}

#[test]
fn length_buckets_batch_meshes_of_one_length_and_cover_each_epoch() {
    let mut cfg = small_config(1);
    cfg.model.length_buckets = true;
    cfg.batch_size = 3;
    // Slots for N = 64, r = 4: 8, 16, 32, 64.
    let counts = [6, 8, 9, 16, 17, 25, 33, 42, 64, 5, 7, 30];
    for (count, slots) in [(1, 8), (8, 8), (9, 16), (17, 32), (33, 64), (64, 64)] {
        assert_eq!(cfg.model.slots_for(count), slots, "{count} vertices");
    }
    for epoch in 0..3 {
        let batches = epoch_batches(&counts, &cfg, epoch);
        assert_eq!(batches, epoch_batches(&counts, &cfg, epoch), "seeded");
        let mut seen: Vec<usize> = batches.iter().flatten().copied().collect();
        seen.sort_unstable();
        assert_eq!(
            seen,
            (0..counts.len()).collect::<Vec<_>>(),
            "each mesh once"
        );
        for b in &batches {
            assert!(!b.is_empty() && b.len() <= 3);
            let slots = cfg.model.slots_for(counts[b[0]]);
            assert!(b.iter().all(|&i| cfg.model.slots_for(counts[i]) == slots));
        }
    }
    cfg.model.length_buckets = false;
    assert_eq!(
        cfg.model.slots_for(5),
        64,
        "without buckets every mesh takes N slots"
    );
}

#[test]
fn near_negatives_weigh_close_non_edges_and_nothing_else() {
    // A 5 x 5 grid, padded: its edges are 0 in the weights, pairs of real vertices closer
    // than 2 mean edge lengths get the near weight, farther ones the plain weight, padding 0.
    let device = Device::flex();
    let mesh = model_frame(grid(5, 5));
    let cfg = small_config(1);
    let tokens = build_tokens(&mesh, &cfg.model.tokens_for(mesh.positions.len()), 0).unwrap();
    let (n, real) = (tokens.mask.len(), tokens.num_real);
    let weights = NonEdgeWeights {
        weight: 0.25,
        near_weight: 1.0,
        near_radius: 2.0,
    };
    let plane = |w: NonEdgeWeights| -> Vec<f32> {
        make_batch(std::slice::from_ref(&tokens), w, &device)
            .non_edges
            .into_data()
            .convert::<f32>()
            .try_into_vec::<f32>()
            .unwrap()
    };
    let got = plane(weights);
    let p = &tokens.positions;
    let mean_edge = tokens
        .edges
        .iter()
        .map(|&[i, j]| p[i as usize].distance(p[j as usize]))
        .sum::<f32>()
        / tokens.edges.len() as f32;
    let (mut near, mut far) = (0, 0);
    for i in 0..n {
        for j in 0..n {
            let w = got[i * n + j];
            let is_edge = tokens.edges.contains(&[i as u32, j as u32]);
            if i >= j || j >= real || is_edge {
                assert_eq!(w, 0.0, "({i}, {j})");
            } else if p[i].distance(p[j]) < 2.0 * mean_edge {
                assert_eq!(w, 1.0, "({i}, {j})");
                near += 1;
            } else {
                assert_eq!(w, 0.25, "({i}, {j})");
                far += 1;
            }
        }
    }
    assert!(
        near > 0 && far > 0,
        "both kinds occur: {near} near, {far} far"
    );
    // Uniform weights: every real non-edge i < j the same, as the paper's loss has it.
    let uniform = plane(NonEdgeWeights::uniform(0.25));
    let count = uniform.iter().filter(|&&w| w == 0.25).count();
    assert_eq!(count, near + far);
    assert_eq!(uniform.iter().filter(|&&w| w != 0.0).count(), count);
}

#[test]
fn latent_noise_reaches_training_and_none_leaves_it_as_it_was() {
    let device = Device::flex();
    let data = meshes();
    let weights = |noise: f32, tag: &str| {
        let mut cfg = small_config(3);
        cfg.latent_noise = noise;
        let dir = temp_dir(tag);
        let dir = dir.path();
        let mut quiet = Quiet::new();
        let trained = train_vae(&cfg, &data, &data, dir, &device, &mut quiet).unwrap();
        trained.weights
    };
    let plain = weights(0.0, "noise-off");
    assert_eq!(plain, weights(0.0, "noise-off-again"));
    assert_ne!(plain, weights(0.5, "noise-on"));
}

#[test]
fn the_plain_configuration_weighs_every_non_edge_by_lambda_neg() {
    let mut cfg = small_config(1);
    assert_eq!(cfg.non_edge_weights(), NonEdgeWeights::uniform(0.25));
    cfg.near_negative_weight = 3.0;
    let w = cfg.non_edge_weights();
    assert_eq!((w.weight, w.near_weight, w.near_radius), (0.25, 3.0, 2.0));
}

#[test]
fn the_best_grid_threshold_is_the_best_of_scoring_at_each_one() {
    // 400 pairs with pseudo-random scores in [-4, 4] (some exactly on the grid), a third of
    // them edges: the histogram's best F1 equals scoring the pairs at every grid tau.
    let mut state = 12345u64;
    let mut next = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 33) as u32
    };
    let pairs: Vec<([u32; 2], f32, bool)> = (0..400u32)
        .map(|k| {
            let r = next();
            let d = if r % 7 == 0 {
                TAU_GRID[(r % 25) as usize]
            } else {
                (r % 8000) as f32 / 1000.0 - 4.0
            };
            ([k, k + 1000], d, next() % 3 == 0)
        })
        .collect();
    let actual: Vec<[u32; 2]> = pairs.iter().filter(|p| p.2).map(|p| p.0).collect();
    let (mut edges_above, mut non_edges_above) = ([0usize; 26], [0usize; 26]);
    for &(_, d, is_edge) in &pairs {
        let above = TAU_GRID.partition_point(|&tau| d > tau);
        if is_edge {
            edges_above[above] += 1;
        } else {
            non_edges_above[above] += 1;
        }
    }
    let (mut want_f1, mut want_tau) = (0.0, f32::NAN);
    for &tau in &TAU_GRID {
        let predicted: Vec<[u32; 2]> = pairs.iter().filter(|p| p.1 > tau).map(|p| p.0).collect();
        let f1 = edge_scores(&predicted, &actual).f1;
        if f1 > want_f1 {
            (want_f1, want_tau) = (f1, tau);
        }
    }
    let (f1, tau) = best_grid_f1(&edges_above, &non_edges_above, 0.0, 0.6);
    assert!((f1 - want_f1).abs() < 1e-12, "{f1} against {want_f1}");
    assert_eq!(tau, want_tau);
    // The model's own tau stands when nothing on the grid beats it.
    assert_eq!(
        best_grid_f1(&edges_above, &non_edges_above, 1.0, 0.6),
        (1.0, 0.6)
    );
}

#[test]
fn bad_configurations_fail_before_any_step_naming_the_field() {
    let device = Device::flex();
    let data = meshes();
    let mut quiet = Quiet::new();
    let mut json: serde_json::Value = serde_json::to_value(small_config(5)).unwrap();
    json["learning_rat"] = 0.1.into();
    let err = serde_json::from_value::<VaeTrainConfig>(json).unwrap_err();
    assert!(err.to_string().contains("learning_rat"), "{err}");

    type Spoil = fn(&mut VaeTrainConfig);
    let cases: [(&str, Spoil); 8] = [
        ("latent_dim", |c| c.model.latent_dim = 0),
        ("data_parallel", |c| c.data_parallel = 0),
        ("num_latents", |c| c.model.num_latents = 48),
        ("batch_size", |c| c.batch_size = 0),
        ("learning_rate", |c| c.learning_rate = f64::NAN),
        ("near_negative_weight", |c| c.near_negative_weight = -1.0),
        ("near_negative_radius", |c| c.near_negative_radius = 0.0),
        ("latent_noise", |c| c.latent_noise = f32::NAN),
    ];
    for (field, spoil) in cases {
        let mut cfg = small_config(5);
        spoil(&mut cfg);
        let dir = temp_dir(&format!("bad-{field}"));
        let dir = dir.path();
        let err = train_vae(&cfg, &data, &data, dir, &device, &mut quiet)
            .err()
            .unwrap_or_else(|| panic!("{field}: accepted"));
        assert!(err.to_string().contains(field), "{field}: {err}");
        assert!(!dir.join("metrics.jsonl").exists(), "{field}: no step ran");
    }
}

/// The whole small VAE trained for 60 steps on [`meshes`]: the weights decoder-only runs
/// start from.
fn trained_base(dir: &str) -> meshflow::model::TensorMap {
    let mut quiet = Quiet::new();
    let data = meshes();
    train_vae(
        &small_config(60),
        &data,
        &data,
        temp_dir(dir).path(),
        &Device::flex(),
        &mut quiet,
    )
    .unwrap()
    .weights
}

/// A decoder-only run starts from trained weights, keeps the encoder side bit for bit (so a DiT
/// trained on its latents still fits: the latent-space identity is unchanged), lowers the
/// validation loss of the decoder, and refuses to start without weights to start from.
#[test]
fn decoder_only_training_keeps_the_latent_space() {
    use meshflow::pipeline::shipped::{is_encoder_side, latent_space_sha256};
    use meshflow::train::vae::train_vae_from;
    let (device, data) = (Device::flex(), meshes());
    let mut quiet = Quiet::new();
    let first = trained_base("dec-base");
    let mut cfg = small_config(60);
    cfg.decoder_only = true;
    cfg.seed = 3;
    let dir = temp_dir("dec-only");
    let dir = dir.path();
    assert!(train_vae(&cfg, &data, &data, dir, &device, &mut quiet).is_err());
    let tuned = train_vae_from(&cfg, Some(&first), &data, &data, dir, &device, &mut quiet)
        .unwrap()
        .weights;
    let (mut kept, mut changed) = (0, 0);
    for (name, tensor) in &first.tensors {
        if is_encoder_side(name) {
            assert_eq!(&tuned.tensors[name], tensor, "{name} changed");
            kept += 1;
        } else if &tuned.tensors[name] != tensor {
            changed += 1;
        }
    }
    assert!(kept > 0 && changed > 0, "kept {kept}, changed {changed}");
    let stats = ([0.1f32; 8], [1.0f32; 8]);
    assert_eq!(
        latent_space_sha256(&first, &stats.0, &stats.1),
        latent_space_sha256(&tuned, &stats.0, &stats.1)
    );
    let loss = |w| {
        let vae = load_module(MeshVae::new(&cfg.model, &device), w, &|_| false).unwrap();
        validate(&vae, &data, &cfg, &device, 0).unwrap().val_loss
    };
    let (before, after) = (loss(&first), loss(&tuned));
    assert!(after < before, "validation loss {before} -> {after}");
}

/// A decoder of another size on a trained encoder (`init` holding the encoder side alone): the
/// encoder stays bit for bit, the new decoder learns from its seeded start, and a full `init`
/// whose decoder has the old shapes is refused with the tensor it could not load.
#[test]
fn decoder_only_training_can_start_a_decoder_of_another_size() {
    use meshflow::model::TensorMap;
    use meshflow::pipeline::shipped::is_encoder_side;
    use meshflow::train::vae::train_vae_from;
    let (device, data) = (Device::flex(), meshes());
    let mut quiet = Quiet::new();
    let base = small_config(60);
    let first = trained_base("wide-base");
    let mut cfg = small_config(60);
    cfg.decoder_only = true;
    cfg.model.width_decoder *= 2;
    cfg.model.num_layers_decoder += 1;
    assert!(cfg.model.same_encoder(&base.model) && cfg.model != base.model);
    let mut other_latents = base.model.clone();
    other_latents.latent_dim *= 2;
    assert!(!other_latents.same_encoder(&base.model));

    let dir = temp_dir("wide-dec");

    let dir = dir.path();
    let err = train_vae_from(&cfg, Some(&first), &data, &data, dir, &device, &mut quiet)
        .err()
        .expect("old decoder shapes accepted");
    assert!(err.to_string().contains("does not match"), "{err}");

    let encoder = TensorMap {
        tensors: first
            .tensors
            .iter()
            .filter(|(name, _)| is_encoder_side(name))
            .map(|(name, t)| (name.clone(), t.clone()))
            .collect(),
    };
    let wide = train_vae_from(&cfg, Some(&encoder), &data, &data, dir, &device, &mut quiet)
        .unwrap()
        .weights;
    for (name, tensor) in &encoder.tensors {
        assert_eq!(&wide.tensors[name], tensor, "{name} changed");
    }
    let untrained = meshflow::model::seeded_init(MeshVae::new(&cfg.model, &device), cfg.seed);
    let untrained = load_module(untrained, &encoder, &|_| false);
    assert!(untrained.is_err(), "the encoder alone is not a whole VAE");
    let loss = |w: &TensorMap| {
        let vae = load_module(MeshVae::new(&cfg.model, &device), w, &|_| false).unwrap();
        validate(&vae, &data, &cfg, &device, 0).unwrap().val_loss
    };
    // Where the run started: the trained encoder and the seeded decoder.
    let start = meshflow::model::load_module_keeping(
        meshflow::model::seeded_init(MeshVae::new(&cfg.model, &device), cfg.seed),
        &encoder,
        &|_| false,
        &|name| !is_encoder_side(name),
    )
    .unwrap();
    let (before, after) = (loss(&meshflow::model::module_tensors(&start)), loss(&wide));
    assert!(after < 0.5 * before, "validation loss {before} -> {after}");
}

/// Vertex blocks (`num_layers_vertex`) added to a trained decoder start as the identity: the
/// decoder with them, loaded from weights without them, scores exactly as before; a
/// decoder-only run from there trains them (their output projections leave zero) and lowers
/// the validation loss.
#[test]
fn vertex_blocks_start_as_the_identity_and_then_learn() {
    use meshflow::model::{load_module_keeping, module_tensors, seeded_init};
    use meshflow::train::vae::train_vae_from;
    let (device, data) = (Device::flex(), meshes());
    let mut quiet = Quiet::new();
    let base_cfg = small_config(60);
    let base = trained_base("vertex-base");
    let mut cfg = small_config(60);
    cfg.decoder_only = true;
    cfg.model.num_layers_vertex = 1;
    assert!(cfg.model.same_encoder(&base_cfg.model));

    let plain = load_module(MeshVae::new(&base_cfg.model, &device), &base, &|_| false).unwrap();
    let new_blocks = |name: &str| name.contains("vertex_blocks");
    let grown = load_module_keeping(
        seeded_init(MeshVae::new(&cfg.model, &device), cfg.seed),
        &base,
        &|_| false,
        &new_blocks,
    )
    .unwrap();
    let before = validate(&plain, &data, &base_cfg, &device, 0).unwrap();
    let grown_before = validate(&grown, &data, &cfg, &device, 0).unwrap();
    assert_eq!(before.val_loss, grown_before.val_loss);
    assert_eq!(before.edge_f1, grown_before.edge_f1);

    let dir = temp_dir("vertex-blocks");

    let dir = dir.path();
    let trained = train_vae_from(&cfg, Some(&base), &data, &data, dir, &device, &mut quiet)
        .unwrap()
        .weights;
    let out_projection = "decoder.vertex_blocks.0.attn1.to_out.0.weight";
    let zero = &module_tensors(&grown).tensors[out_projection].1;
    assert!(zero.iter().all(|&v| v == 0.0));
    assert!(trained.tensors[out_projection].1.iter().any(|&v| v != 0.0));
    let vae = load_module(MeshVae::new(&cfg.model, &device), &trained, &|_| false).unwrap();
    let after = validate(&vae, &data, &cfg, &device, 0).unwrap();
    assert!(
        after.val_loss < before.val_loss,
        "validation loss {} -> {}",
        before.val_loss,
        after.val_loss
    );
}

/// Edge-embedding channels added to a trained decoder (`widen_edge_embeddings`) start nearly
/// silent and then learn: a decoder-only run from the widened weights moves the added output
/// rows and lowers the validation loss the widened decoder started at.
#[test]
fn widened_edge_embeddings_learn_in_a_decoder_only_run() {
    use meshflow::model::widen_edge_embeddings;
    use meshflow::train::vae::train_vae_from;
    let (device, data) = (Device::flex(), meshes());
    let mut quiet = Quiet::new();
    let base_cfg = small_config(60);
    let base = trained_base("edge-base");
    let mut cfg = small_config(60);
    cfg.decoder_only = true;
    cfg.model.edge_dim = 2 * base_cfg.model.edge_dim;
    assert!(cfg.model.continues_decoder_of(&base_cfg.model));
    let mut widened = base.clone();
    widen_edge_embeddings(
        &mut widened,
        base_cfg.model.edge_dim,
        cfg.model.edge_dim,
        0.1,
        5,
    )
    .unwrap();
    let loss = |w: &meshflow::model::TensorMap| {
        let vae = load_module(MeshVae::new(&cfg.model, &device), w, &|_| false).unwrap();
        validate(&vae, &data, &cfg, &device, 0).unwrap().val_loss
    };
    let dir = temp_dir("edge-wide");
    let dir = dir.path();
    let trained = train_vae_from(&cfg, Some(&widened), &data, &data, dir, &device, &mut quiet)
        .unwrap()
        .weights;
    // Row 3 * edge_dim / 4 is the first added time channel.
    let (name, hidden) = (
        "decoder.adjacency_head.2.weight",
        cfg.model.width_decoder / 2,
    );
    let row = 3 * cfg.model.edge_dim / 4;
    let added = |w: &meshflow::model::TensorMap| {
        w.tensors[name].1[row * hidden..(row + 1) * hidden].to_vec()
    };
    assert_ne!(added(&widened), added(&trained));
    let (before, after) = (loss(&widened), loss(&trained));
    assert!(after < before, "validation loss {before} -> {after}");
}

/// A pair head added to a trained decoder starts silent (the same validation figures as
/// without it) and then learns in a decoder-only run: its output layer leaves zero and the
/// validation loss, which now scores the refined distances too, falls.
#[test]
fn a_pair_head_starts_silent_and_learns_in_a_decoder_only_run() {
    use meshflow::model::{load_module_keeping, module_tensors, seeded_init};
    use meshflow::train::vae::train_vae_from;
    let (device, data) = (Device::flex(), meshes());
    let mut quiet = Quiet::new();
    let base_cfg = small_config(60);
    let base = trained_base("pair-base");
    let mut cfg = small_config(60);
    cfg.decoder_only = true;
    cfg.model.pair_head = 16;
    assert!(cfg.model.continues_decoder_of(&base_cfg.model));
    let plain = load_module(MeshVae::new(&base_cfg.model, &device), &base, &|_| false).unwrap();
    let grown = load_module_keeping(
        seeded_init(MeshVae::new(&cfg.model, &device), cfg.seed),
        &base,
        &|_| false,
        &|name| name.contains("pair_head"),
    )
    .unwrap();
    let before = validate(&plain, &data, &base_cfg, &device, 0).unwrap();
    let grown_before = validate(&grown, &data, &cfg, &device, 0).unwrap();
    assert_eq!(before.edge_f1, grown_before.edge_f1);
    assert_eq!(before.edge_f1_best_tau, grown_before.edge_f1_best_tau);

    let dir = temp_dir("pair-head");

    let dir = dir.path();
    let trained = train_vae_from(&cfg, Some(&base), &data, &data, dir, &device, &mut quiet)
        .unwrap()
        .weights;
    let output = "decoder.pair_head.2.weight";
    assert!(
        module_tensors(&grown).tensors[output]
            .1
            .iter()
            .all(|&v| v == 0.0)
    );
    assert!(trained.tensors[output].1.iter().any(|&v| v != 0.0));
    let vae = load_module(MeshVae::new(&cfg.model, &device), &trained, &|_| false).unwrap();
    let after = validate(&vae, &data, &cfg, &device, 0).unwrap();
    assert!(
        after.val_loss < grown_before.val_loss,
        "validation loss {} -> {}",
        grown_before.val_loss,
        after.val_loss
    );
}

#[test]
fn validation_scores_edges_at_the_threshold_extraction_uses() {
    // The manifest's final validation must describe the VAE as it ships: its edges scored at
    // `extraction_tau` when the configuration sets one, at `model.tau` otherwise.
    use meshflow::model::seeded_init;
    let (device, data) = (Device::flex(), meshes());
    let cfg = small_config(1);
    let vae = seeded_init(MeshVae::new(&cfg.model, &device), 3);
    let at = |tau: Option<f32>| {
        let mut c = cfg.clone();
        c.extraction_tau = tau;
        validate(&vae, &data, &c, &device, 0).unwrap()
    };
    let plain = at(None);
    let own = at(Some(cfg.model.tau));
    assert_eq!(
        (plain.edge_precision, plain.edge_recall, plain.val_loss),
        (own.edge_precision, own.edge_recall, own.val_loss)
    );
    // Every pair above the lowest threshold, none above the highest; the loss keeps model.tau.
    let all = at(Some(-1e30));
    assert_eq!(all.edge_recall, 1.0);
    assert_eq!(all.val_loss, plain.val_loss);
    let none = at(Some(1e30));
    assert_eq!((none.edge_recall, none.edge_f1), (0.0, 0.0));
}

/// Training scores a pair head's refined distances from its candidates alone (`vae_losses`):
/// the same loss, and the same gradients, as the adjacency loss over the whole refined matrix
/// (`MeshVae::edge_distances`), which it replaces.
#[test]
fn the_pair_loss_from_the_candidates_is_the_loss_of_the_refined_matrix() {
    use burn::optim::GradientsParams;
    use burn::tensor::Tensor;
    use burn::tensor::activation::softplus;
    use meshflow::model::{module_tensors, seeded_init, spacetime_distances};
    use meshflow::train::vae::vae_losses;
    let device = Device::flex().autodiff();
    let mut cfg = small_config(1);
    cfg.model.pair_head = 16;
    // A head with a non-zero output layer, so that every candidate moves by its own amount.
    let mut map = module_tensors(&seeded_init(MeshVae::new(&cfg.model, &device), 7));
    for name in ["decoder.pair_head.2.weight", "decoder.pair_head.2.bias"] {
        let values = &mut map.tensors.get_mut(name).expect(name).1;
        for (k, v) in values.iter_mut().enumerate() {
            *v = 0.5 * (k as f32 * 1.3 + 0.4).sin();
        }
    }
    let vae = load_module(MeshVae::new(&cfg.model, &device), &map, &|_| false).unwrap();
    let data = meshes();
    let largest = data.iter().map(|m| m.positions.len()).max().unwrap();
    let tokens: Vec<_> = data
        .iter()
        .map(|m| build_tokens(m, &cfg.model.tokens_for(largest), 0).unwrap())
        .collect();
    let batch = make_batch(
        &tokens,
        NonEdgeWeights::uniform(cfg.lambda_neg as f32),
        &device,
    );
    let [b, _, _] = batch.edges.dims();
    let latents = cfg.model.slots_for(largest) / (cfg.model.num_vertices / cfg.model.num_latents);
    let zeros = Tensor::<3>::zeros([b, latents, cfg.model.latent_dim], &device);

    let fast = vae_losses(&vae, &batch, zeros, &cfg)
        .pair_adjacency
        .expect("a pair head's loss");
    let posterior = vae.encode(batch.features.clone(), &mut Default::default());
    let out = vae.decode(posterior.mean, &mut Default::default());
    // The whole refined matrix on the device, as training scored it before.
    let distances = spacetime_distances(out.edge_embeddings);
    let host = distances
        .clone()
        .into_data()
        .convert::<f32>()
        .try_into_vec::<f32>()
        .unwrap();
    let pairs = vae
        .pair_corrections(distances.clone(), &host, out.features, &batch.real_slots)
        .expect("candidates");
    let [_, n, _] = distances.dims();
    let added = Tensor::<1>::zeros([b * n * n], &device).select_assign(
        0,
        pairs.index,
        pairs.corrections,
        burn::tensor::IndexingUpdateOp::Add,
    );
    let refined = distances + added.reshape([b, n, n]);
    let per_mesh = |t: Tensor<3>| t.sum_dim(2).sum_dim(1).reshape([b]);
    let tau = cfg.model.tau as f64;
    let whole = ((per_mesh(softplus(refined.clone().neg() + tau, 1.0) * batch.edges.clone())
        + per_mesh(softplus(refined - tau, 1.0) * batch.non_edges.clone()))
        / per_mesh(batch.edges.clone()).clamp_min(1.0))
    .mean();

    let value = |t: &Tensor<1>| {
        t.clone()
            .into_data()
            .convert::<f32>()
            .try_into_vec::<f32>()
            .unwrap()[0]
    };
    let (a, w) = (value(&fast), value(&whole));
    assert!((a - w).abs() <= 1e-5 * w.abs(), "{a} against {w}");
    let grads = |loss: Tensor<1>| GradientsParams::from_grads(loss.backward(), &vae);
    let (fast, whole) = (grads(fast), grads(whole));
    let ids = [
        vae.decoder.adjacency_head.output.weight.id,
        vae.decoder.pair_head.as_ref().unwrap().hidden.weight.id,
    ];
    for id in ids {
        let flat = |g: &GradientsParams| {
            g.get::<2>(id)
                .expect("a gradient")
                .into_data()
                .convert::<f32>()
                .try_into_vec::<f32>()
                .unwrap()
        };
        let (f, w) = (flat(&fast), flat(&whole));
        let scale = w.iter().fold(0f32, |m, v| m.max(v.abs()));
        assert!(scale > 0.0);
        for (x, y) in f.iter().zip(&w) {
            assert!((x - y).abs() <= 1e-4 * scale, "{x} against {y}");
        }
    }
}

/// A batch cut into sub-batches that run at once on the CPU's threads (`data_parallel`) trains
/// as the whole batch does, for the whole VAE (three uneven sub-batches) and for a decoder-only
/// run with a pair head (two): at every step the same loss and the same gradient norm before
/// clipping (so each sub-batch's gradient is weighted by its share: AdamW and the clip would
/// hide a wrong overall scale from the loss), up to float rounding. Weights are not compared
/// element by element: parameters whose gradient is zero in exact arithmetic (a bias before a
/// translation-invariant distance) get rounding noise that AdamW normalises to full-size
/// steps. Two split runs agree bit for bit, so a split run still resumes exactly.
#[test]
fn sub_batches_on_threads_train_as_the_whole_batch() {
    use meshflow::train::vae::train_vae_from;
    let (device, data) = (Device::flex(), meshes());
    let base = trained_base("split-base");
    let mut whole_vae = small_config(8);
    whole_vae.ema_decay = Some(0.9);
    let mut decoder = small_config(8);
    decoder.decoder_only = true;
    decoder.model.pair_head = 16;
    for (cfg, parts) in [(whole_vae, 3), (decoder, 2)] {
        let run = |parts: usize, tag: &str| {
            let mut c = cfg.clone();
            c.data_parallel = parts;
            let dir = temp_dir(&format!("split-{tag}-{parts}-{}", cfg.decoder_only));
            let dir = dir.path();
            let init = cfg.decoder_only.then_some(&base);
            let weights = train_vae_from(&c, init, &data, &data, dir, &device, &mut Quiet::new())
                .unwrap()
                .weights;
            let steps = common::loss_and_grad_norm(dir);
            (weights, steps)
        };
        common::assert_split_trains_as_whole(parts, 8, run);
    }
}
