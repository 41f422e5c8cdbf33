//! MeshVAE training on the CPU backend: a small model overfits a few meshes to edge F1 >= 0.99,
//! and a run stopped at a checkpoint and resumed ends with exactly the same weights.
#![cfg(feature = "train")]

use std::path::PathBuf;

use burn::tensor::Device;
use meshflow::Mesh;
use meshflow::model::{MeshVae, VaeConfig, load_module};
use meshflow::normalize::Normalization;
use meshflow::primitives::{cube, grid, icosphere, octahedron};
use meshflow::train::TrainObserver;
use meshflow::train::vae::{VaeTrainConfig, train_vae, validate};

fn model_frame(m: Mesh) -> Mesh {
    Normalization::to_model_frame(m.aabb().unwrap()).apply_mesh(&m)
}

fn meshes() -> Vec<Mesh> {
    [octahedron(), cube(), icosphere(1), grid(5, 5)]
        .into_iter()
        .map(model_frame)
        .collect()
}

fn small_config(steps: usize) -> VaeTrainConfig {
    let model = VaeConfig {
        num_vertices: 64,
        num_latents: 16,
        latent_dim: 8,
        width_encoder: 64,
        width_decoder: 64,
        num_heads: 4,
        num_layers_encoder: 1,
        num_layers_decoder: 1,
        max_degree: 8,
        num_freqs: 6,
        edge_dim: 32,
        tau: 0.6,
    };
    let mut cfg = VaeTrainConfig::new(model);
    cfg.batch_size = 4;
    cfg.steps = steps;
    cfg.warmup_steps = 10;
    cfg.learning_rate = 3e-3;
    cfg.final_lr_ratio = 0.1;
    cfg.weight_decay = 0.0;
    cfg.kl_weight = 1e-4;
    cfg.lambda_neg = 0.25;
    cfg.augment = false;
    cfg.eval_every = 1_000_000;
    cfg.checkpoint_every = 1_000_000;
    cfg
}

struct Quiet {
    stop_at: Option<usize>,
    last: usize,
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

fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("meshflow-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn small_vae_overfits_a_few_meshes() {
    let device = Device::flex();
    let cfg = small_config(400);
    let data = meshes();
    let dir = temp_dir("overfit");
    let mut quiet = Quiet {
        stop_at: None,
        last: 0,
    };
    let trained = train_vae(&cfg, &data, &data, &dir, &device, &mut quiet).unwrap();
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
    let _ = std::fs::remove_dir_all(&dir);
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
    let mut quiet = Quiet {
        stop_at: None,
        last: 0,
    };
    let a = train_vae(&cfg, &data, &data, &straight, &device, &mut quiet).unwrap();

    // Stop after step 8 (a checkpoint), then start again in the same folder.
    let resumed = temp_dir("resumed");
    let mut stopping = Quiet {
        stop_at: Some(8),
        last: 0,
    };
    let partial = train_vae(&cfg, &data, &data, &resumed, &device, &mut stopping).unwrap();
    assert_eq!(partial.steps, 8);
    let mut quiet = Quiet {
        stop_at: None,
        last: 0,
    };
    let b = train_vae(&cfg, &data, &data, &resumed, &device, &mut quiet).unwrap();
    assert_eq!(b.steps, 12);
    assert_eq!(
        a.weights, b.weights,
        "resumed run matches the straight one exactly"
    );

    // A changed configuration is refused instead of silently mixing runs.
    let mut other = cfg.clone();
    other.learning_rate *= 2.0;
    assert!(train_vae(&other, &data, &data, &resumed, &device, &mut quiet).is_err());
    let _ = std::fs::remove_dir_all(&straight);
    let _ = std::fs::remove_dir_all(&resumed);
}
