//! The reference implementation's golden vectors (`vae_small`, `dit_small`): each model is
//! loaded from its golden file, run on the recorded inputs, and every output and recorded
//! intermediate is compared with the reference's, so a new machine, backend or driver can be
//! checked against the reference numerics (`meshflow verify`, the golden tests).

use std::path::{Path, PathBuf};

use burn::tensor::{Device, Tensor, TensorData};
use glam::Vec3;

use super::dit::{Condition, Dit, DitConfig, is_image_path};
use super::sampler::{SampleError, Solver, sample};
use super::schedule::ScheduleMode;
use super::tokens::assemble_features;
use super::{MeshVae, TensorMap, Trace, VaeConfig, WeightsError, load_module, spacetime_distances};

/// Largest accepted absolute difference from the reference.
pub const TOLERANCE: f32 = 1e-4;

/// Why a comparison could not be made (a difference over [`TOLERANCE`] is not an error: it is
/// in the report).
#[derive(Debug, thiserror::Error)]
pub enum GoldenError {
    /// The golden file could not be read.
    #[error("cannot read {}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// The golden file is not valid safetensors, or its parameters do not fit the model.
    #[error(transparent)]
    Weights(#[from] WeightsError),
    /// A tensor the comparison needs is not in the golden file.
    #[error("golden tensor {0} missing")]
    Missing(String),
    /// A model input is missing or does not have the rank the model takes.
    #[error("golden tensor {0} missing or of another rank")]
    Rank(String),
    /// This build produced a different number of values than the reference.
    #[error("{label}: {got} values, the reference has {want}")]
    Length {
        /// The compared tensor.
        label: String,
        /// Values produced here.
        got: usize,
        /// Values in the reference.
        want: usize,
    },
    /// Sampling stopped early.
    #[error(transparent)]
    Sample(#[from] SampleError),
}

/// One compared tensor: its name and the largest absolute difference from the reference.
#[derive(Clone, Debug, PartialEq)]
pub struct TensorDiff {
    /// The output's or recorded intermediate's name (without `output.` / `inter.`).
    pub name: String,
    /// Largest absolute difference over all its values.
    pub max_abs_diff: f32,
}

impl TensorDiff {
    /// Whether the difference is below [`TOLERANCE`].
    pub fn ok(&self) -> bool {
        self.max_abs_diff < TOLERANCE
    }
}

/// One model's comparison, tensors in the order they were computed.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelReport {
    /// The golden file's name (`vae_small`, `dit_small`).
    pub model: &'static str,
    /// Every compared tensor.
    pub tensors: Vec<TensorDiff>,
}

/// Compares both golden models on `device` with the files in `dir`; VAE first. Fails on the
/// first file or tensor that cannot be compared, before any report exists.
pub fn verify(dir: &Path, device: &Device) -> Result<Vec<ModelReport>, GoldenError> {
    Ok(vec![
        ModelReport {
            model: "vae_small",
            tensors: verify_vae(dir, device)?,
        },
        ModelReport {
            model: "dit_small",
            tensors: verify_dit(dir, device)?,
        },
    ])
}

/// One golden file's tensors and the differences found so far.
struct Golden {
    /// Every numeric tensor as f32 (integer ones such as RoPE positions converted).
    map: TensorMap,
    /// The file's `param.` tensors: the model's weights.
    params: TensorMap,
    diffs: Vec<TensorDiff>,
}

impl Golden {
    fn load(dir: &Path, name: &str) -> Result<Self, GoldenError> {
        let path = dir.join(format!("{name}.safetensors"));
        let bytes = std::fs::read(&path).map_err(|source| GoldenError::Read { path, source })?;
        Ok(Self {
            map: TensorMap::floats_of_safetensors(&bytes)?,
            params: TensorMap::from_safetensors(&bytes, "param.")?,
            diffs: Vec::new(),
        })
    }

    fn get(&self, name: &str) -> Result<&[f32], GoldenError> {
        self.map
            .tensors
            .get(name)
            .map(|(_, values)| values.as_slice())
            .ok_or_else(|| GoldenError::Missing(name.to_string()))
    }

    fn tensor<const D: usize>(
        &self,
        name: &str,
        device: &Device,
    ) -> Result<Tensor<D>, GoldenError> {
        self.map
            .tensor::<D>(name, device)
            .ok_or_else(|| GoldenError::Rank(name.to_string()))
    }

    /// Records the largest difference of `got` from the golden tensor `key` under `label`.
    fn compare(&mut self, label: &str, got: &[f32], key: &str) -> Result<(), GoldenError> {
        let want = self.get(key)?;
        if want.len() != got.len() {
            return Err(GoldenError::Length {
                label: label.to_string(),
                got: got.len(),
                want: want.len(),
            });
        }
        let max_abs_diff = got
            .iter()
            .zip(want)
            .map(|(a, b)| (a - b).abs())
            .fold(0f32, f32::max);
        self.diffs.push(TensorDiff {
            name: label.to_string(),
            max_abs_diff,
        });
        Ok(())
    }
}

fn values<const D: usize>(t: Tensor<D>) -> Vec<f32> {
    t.into_data()
        .convert::<f32>()
        .try_into_vec::<f32>()
        .expect("f32 data")
}

/// The MeshVAE (`vae_small`): the encoder input built by the token code, the posterior, every
/// recorded intermediate, the decoder's outputs and the spacetime distances.
pub fn verify_vae(dir: &Path, device: &Device) -> Result<Vec<TensorDiff>, GoldenError> {
    let mut g = Golden::load(dir, "vae_small")?;
    let cfg = VaeConfig::vae_small();
    let vae = load_module(MeshVae::new(&cfg, device), &g.params, &|_| false)?;
    let verts = g.get("input.padded_verts")?.to_vec();
    let normals = g.get("input.verts_normal")?.to_vec();
    let neighbours = g.get("input.neighbor_points")?.to_vec();
    let tokens = cfg.tokens();
    let per = 3 * cfg.max_degree;
    let mut x = Vec::new();
    for i in 0..verts.len() / 3 {
        // All-zero neighbour rows are padding; the reference keeps them as zeros too.
        let nb: Vec<Vec3> = neighbours[i * per..(i + 1) * per]
            .chunks_exact(3)
            .map(Vec3::from_slice)
            .collect();
        let v = Vec3::from_slice(&verts[i * 3..i * 3 + 3]);
        let n = Vec3::from_slice(&normals[i * 3..i * 3 + 3]);
        assemble_features(v, n, &nb, &tokens, &mut x);
    }
    g.compare("x", &x, "output.x")?;
    let b = verts.len() / 3 / cfg.num_vertices;
    let xt = Tensor::<3>::from_data(
        TensorData::new(x, [b, cfg.num_vertices, cfg.in_channels()]),
        device,
    );
    let mut trace = Trace::recording();
    let posterior = vae.encode(xt, &mut trace);
    g.compare(
        "posterior_mean",
        &values(posterior.mean.clone()),
        "output.posterior_mean",
    )?;
    g.compare(
        "posterior_logvar",
        &values(posterior.logvar),
        "output.posterior_logvar",
    )?;
    // Eval mode: the decoder reads the mean, not a sample.
    let out = vae.decode(posterior.mean, &mut trace);
    for (name, t) in std::mem::take(&mut trace.tensors) {
        g.compare(&name, &values(t), &format!("inter.{name}"))?;
    }
    g.compare("mask", &values(out.mask_logits), "output.mask")?;
    g.compare("verts", &values(out.positions), "output.verts")?;
    g.compare("verts_normal", &values(out.normals), "output.verts_normal")?;
    g.compare(
        "adjacency_emb",
        &values(out.edge_embeddings.clone()),
        "output.adjacency_emb",
    )?;
    let st = spacetime_distances(out.edge_embeddings.narrow(0, 0, 1));
    g.compare("spacetime", &values(st), "output.spacetime")?;
    let synthetic: Tensor<2> = g.tensor("input.synthetic_adjacency_emb", device)?;
    let st = spacetime_distances(synthetic.unsqueeze::<3>());
    g.compare(
        "synthetic_spacetime",
        &values(st),
        "output.synthetic_spacetime",
    )?;
    Ok(g.diffs)
}

/// The DiT (`dit_small`): the time embedding, one forward pass with its recorded
/// intermediates, and a 10-step sampling run step by step.
pub fn verify_dit(dir: &Path, device: &Device) -> Result<Vec<TensorDiff>, GoldenError> {
    let mut g = Golden::load(dir, "dit_small")?;
    let cfg = DitConfig::dit_small();
    let dit = load_module(Dit::new(&cfg, device), &g.params, &is_image_path)?;
    let t = g.get("input.timestep")?.to_vec();
    let positions: Vec<[f32; 3]> = g
        .get("input.rope_input")?
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    let condition = Condition::new(&cfg, &positions, &[], t.len(), device);
    let cond: Tensor<2> = g.tensor("input.proj_cond_on_temb", device)?;
    g.compare(
        "temb",
        &values(dit.time_embedding(&t, cond.clone())),
        "inter.temb",
    )?;
    let x: Tensor<3> = g.tensor("input.x", device)?;
    let mut trace = Trace::recording();
    let out = dit.forward(x, &t, cond.clone(), &condition, &mut trace);
    for (name, tensor) in std::mem::take(&mut trace.tensors) {
        g.compare(&name, &values(tensor), &format!("inter.{name}"))?;
    }
    g.compare("sample", &values(out), "output.sample")?;
    let noise: Tensor<3> = g.tensor("input.noise", device)?;
    let mut steps = Vec::new();
    let sampled = sample(
        &dit,
        noise,
        cond,
        &condition,
        10,
        ScheduleMode::Reference,
        Solver::Euler,
        &mut |_, _, x| {
            steps.extend(values(x.clone()));
            true
        },
    )?;
    g.compare("sample_trace", &steps, "output.sample_trace")?;
    g.compare("sampled", &values(sampled), "output.sampled")?;
    Ok(g.diffs)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn golden(pairs: &[(&str, Vec<f32>)]) -> Golden {
        let mut map = TensorMap::default();
        for (name, v) in pairs {
            map.tensors
                .insert(name.to_string(), (vec![v.len()], v.clone()));
        }
        Golden {
            map,
            params: TensorMap::default(),
            diffs: Vec::new(),
        }
    }

    #[test]
    fn compare_records_the_largest_absolute_difference() {
        let mut g = golden(&[("output.a", vec![1.0, -2.0, 3.0])]);
        g.compare("a", &[1.0, -2.5, 3.1], "output.a").unwrap();
        assert_eq!(g.diffs.len(), 1);
        assert_eq!(g.diffs[0].name, "a");
        assert!((g.diffs[0].max_abs_diff - 0.5).abs() < 1e-6);
        assert!(!g.diffs[0].ok());
        g.compare("a", &[1.0, -2.0, 3.0], "output.a").unwrap();
        assert!(g.diffs[1].ok());
    }

    #[test]
    fn compare_refuses_missing_tensors_and_other_lengths() {
        let mut g = golden(&[("output.a", vec![1.0, 2.0])]);
        assert_eq!(
            g.compare("b", &[1.0], "output.b").unwrap_err().to_string(),
            "golden tensor output.b missing"
        );
        assert_eq!(
            g.compare("a", &[1.0], "output.a").unwrap_err().to_string(),
            "a: 1 values, the reference has 2"
        );
        assert!(g.diffs.is_empty());
    }

    #[test]
    fn a_missing_folder_names_the_file() {
        let err = verify(Path::new("/nonexistent/golden"), &Device::flex()).unwrap_err();
        assert!(matches!(err, GoldenError::Read { .. }), "{err}");
        assert_eq!(
            err.to_string(),
            "cannot read /nonexistent/golden/vae_small.safetensors"
        );
    }
}
