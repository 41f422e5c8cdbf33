//! Shared helpers for the integration tests: the golden vectors from the reference
//! implementation (`../shared/golden/` beside the checkout, or `$MESHFLOW_GOLDEN_DIR`).
#![allow(dead_code)]

use std::path::PathBuf;

use burn::tensor::Device;
use meshflow::pipeline::shipped::ShippedModels;
use safetensors::{Dtype, SafeTensors};

/// A fresh, empty folder under the system's temporary folder for one test, named
/// `meshflow-{tag}-` and a random suffix; removed with everything in it when the returned guard
/// drops, whether the test passes or panics (keep the guard in scope: `let dir =
/// temp_dir("x"); let dir = dir.path();`).
pub fn temp_dir(tag: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("meshflow-{tag}-"))
        .tempdir()
        .expect("a temporary folder")
}

/// The repository root (the folder above the crate).
pub fn repo_root() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

/// The shipped pair (`weights/`, the files the CLI and the page run) on Burn's CPU backend,
/// and that device.
pub fn shipped_on_cpu() -> (ShippedModels, Device) {
    let device = Device::flex();
    let models = ShippedModels::load(&repo_root().join("weights"), &device)
        .expect("the shipped weights load");
    (models, device)
}

/// The bundled lantern scan (`tests/fixtures/points/stone_lantern_2048.ply`) as the
/// generation's input points (seed 0).
pub fn lantern_points() -> Vec<glam::Vec3> {
    use meshflow::io::{Limits, read_path};
    let path = repo_root().join("tests/fixtures/points/stone_lantern_2048.ply");
    let mesh = read_path(&path, &Limits::default()).expect("the lantern scan reads");
    meshflow::pipeline::generate::input_points(&mesh, 0).expect("the lantern has points")
}

/// The folder holding the golden files. Missing golden files fail the tests loudly: they are
/// the only proof that this port matches the reference.
pub fn golden_dir() -> PathBuf {
    let dir = std::env::var_os("MESHFLOW_GOLDEN_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../shared/golden"))
        });
    assert!(
        dir.join("README.md").is_file(),
        "golden vectors not found at {} (set MESHFLOW_GOLDEN_DIR)",
        dir.display()
    );
    dir
}

/// A golden safetensors file and its JSON description.
pub struct Golden {
    bytes: Vec<u8>,
    pub json: serde_json::Value,
}

/// A tensor as flat data plus its shape.
pub struct Tensor<T> {
    pub shape: Vec<usize>,
    pub data: Vec<T>,
}

impl Golden {
    /// Loads `NAME.safetensors` and `NAME.json` from the golden folder.
    pub fn load(name: &str) -> Golden {
        let dir = golden_dir();
        let bytes =
            std::fs::read(dir.join(format!("{name}.safetensors"))).expect("golden safetensors");
        let json = std::fs::read_to_string(dir.join(format!("{name}.json"))).expect("golden json");
        Golden {
            bytes,
            json: serde_json::from_str(&json).expect("golden json parses"),
        }
    }

    fn raw(&self, name: &str) -> (Dtype, Vec<usize>, Vec<u8>) {
        let st = SafeTensors::deserialize(&self.bytes).expect("golden safetensors parses");
        let t = st
            .tensor(name)
            .unwrap_or_else(|_| panic!("golden tensor {name} missing"));
        (t.dtype(), t.shape().to_vec(), t.data().to_vec())
    }

    pub fn f32(&self, name: &str) -> Tensor<f32> {
        let (dtype, shape, data) = self.raw(name);
        let data = match dtype {
            Dtype::F32 => data
                .chunks_exact(4)
                .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
                .collect(),
            Dtype::F64 => data
                .chunks_exact(8)
                .map(|b| f64::from_le_bytes(b.try_into().unwrap()) as f32)
                .collect(),
            other => panic!("{name}: expected a float tensor, got {other:?}"),
        };
        Tensor { shape, data }
    }

    pub fn i64(&self, name: &str) -> Tensor<i64> {
        let (dtype, shape, data) = self.raw(name);
        assert_eq!(dtype, Dtype::I64, "{name}");
        Tensor {
            shape,
            data: data
                .chunks_exact(8)
                .map(|b| i64::from_le_bytes(b.try_into().unwrap()))
                .collect(),
        }
    }

    pub fn vec3(&self, name: &str) -> Vec<glam::Vec3> {
        let t = self.f32(name);
        assert_eq!(*t.shape.last().unwrap(), 3, "{name}");
        t.data.chunks_exact(3).map(glam::Vec3::from_slice).collect()
    }

    pub fn pairs(&self, name: &str) -> Vec<[u32; 2]> {
        let t = self.i64(name);
        t.data
            .chunks_exact(2)
            .map(|p| [p[0] as u32, p[1] as u32])
            .collect()
    }

    pub fn triples(&self, name: &str) -> Vec<[u32; 3]> {
        let t = self.i64(name);
        t.data
            .chunks_exact(3)
            .map(|p| [p[0] as u32, p[1] as u32, p[2] as u32])
            .collect()
    }
}

/// Largest absolute difference, asserting equal lengths.
pub fn max_abs_diff(a: &[f32], b: &[f32]) -> f32 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f32::max)
}

/// Faces in the golden files' canonical form: each rotated so its smallest index comes first
/// (orientation kept), then the list sorted.
pub fn canonical_faces(faces: &[[u32; 3]]) -> Vec<[u32; 3]> {
    let mut out: Vec<[u32; 3]> = faces
        .iter()
        .map(|&f| meshflow::geometry::topology::rotate_min_first(f))
        .collect();
    out.sort_unstable();
    out
}

/// Asserts that every compared tensor is within the golden tolerance, printing each
/// difference, and returns the largest.
pub fn assert_within_tolerance(diffs: &[meshflow::model::golden::TensorDiff]) -> f32 {
    let mut worst = 0f32;
    for d in diffs {
        eprintln!("{}: max abs diff {:.3e}", d.name, d.max_abs_diff);
        assert!(
            d.max_abs_diff < meshflow::model::golden::TOLERANCE,
            "{}: max abs diff {}",
            d.name,
            d.max_abs_diff
        );
        worst = worst.max(d.max_abs_diff);
    }
    worst
}

/// The loss and the gradient norm before clipping of each step of a training run, from its
/// `metrics.jsonl` (validation lines have neither).
pub fn loss_and_grad_norm(run_dir: &std::path::Path) -> Vec<(f64, f64)> {
    std::fs::read_to_string(run_dir.join("metrics.jsonl"))
        .unwrap()
        .lines()
        .filter_map(|l| {
            let v: serde_json::Value = serde_json::from_str(l).ok()?;
            Some((v["loss"].as_f64()?, v["grad_norm"].as_f64()?))
        })
        .collect()
}

/// Asserts that a training run cut into `parts` sub-batches trains as the whole batch does.
/// `run(parts, tag)` trains (in a folder named by `tag` and `parts`) and returns its weights
/// and each step's loss and gradient norm ([`loss_and_grad_norm`]). The whole batch's run and
/// a split one take `steps` steps with the same loss and gradient norm at each, within 1e-4
/// relative (float rounding: the same training in another order); two split runs have the
/// same weights bit for bit.
pub fn assert_split_trains_as_whole<W: PartialEq>(
    parts: usize,
    steps: usize,
    run: impl Fn(usize, &str) -> (W, Vec<(f64, f64)>),
) {
    let (_, whole) = run(1, "a");
    let (split, split_steps) = run(parts, "a");
    let (again, _) = run(parts, "b");
    assert!(split == again, "a split run is reproducible");
    assert_eq!((whole.len(), split_steps.len()), (steps, steps));
    let close = |x: f64, y: f64| (x - y).abs() <= 1e-4 * x.abs();
    for (step, (x, y)) in whole.iter().zip(&split_steps).enumerate() {
        assert!(close(x.0, y.0), "step {step}: loss {} vs {}", x.0, y.0);
        assert!(
            close(x.1, y.1),
            "step {step}: gradient norm {} vs {}",
            x.1,
            y.1
        );
    }
}
