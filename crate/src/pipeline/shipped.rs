//! The shipped weights (`weights/`): `vae.safetensors` and `dit.safetensors`, each beside a
//! manifest that records its configuration, sha256 and provenance. This module reads the
//! fields inference needs and loads the networks from bytes, so the CLI and the browser check
//! the same things: the sha256 of each file, that the DiT was trained on this VAE's latents,
//! and that names and shapes match the configurations.

#[cfg(not(target_arch = "wasm32"))]
use std::path::Path;

use burn::tensor::Device;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::model::dit::{Dit, DitConfig, is_image_path};
use crate::model::{MeshVae, TensorMap, VaeConfig, WeightsError, load_module};
use crate::pipeline::generate::Generator;

/// Why shipped weights were refused.
#[derive(Debug, thiserror::Error)]
pub enum ShippedError {
    #[error("{what} manifest: {source}")]
    Manifest {
        what: &'static str,
        source: serde_json::Error,
    },
    #[error("{what} weights: sha256 {actual} does not match the manifest's {expected}")]
    Checksum {
        what: &'static str,
        expected: String,
        actual: String,
    },
    #[error("{what} configuration: {reason}")]
    Config { what: &'static str, reason: String },
    #[error("the DiT was trained on latents of another VAE (sha256 {dit_vae}, not {vae})")]
    VaeMismatch { dit_vae: String, vae: String },
    #[error("{what} weights: {source}")]
    Weights {
        what: &'static str,
        source: WeightsError,
    },
    #[error("cannot read {path}: {source}")]
    Read {
        path: String,
        source: std::io::Error,
    },
    #[error(
        "no shipped weights found (tried {tried}) and the built-in copy could not be written \
         ({source}); pass --weights DIR or set MESHFLOW_WEIGHTS"
    )]
    NotFound {
        tried: String,
        source: std::io::Error,
    },
}

/// How weights were made, as `meshflow train vae|dit` records it in their manifest: for
/// people and for reproducing a run; inference reads none of it, and every field may be
/// absent.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Provenance {
    /// Scalars in the weights.
    pub parameters: usize,
    /// The command line that trained them.
    pub command: String,
    /// The training configuration (the schema of `weights/vae.train.json` or
    /// `weights/dit.train.json`).
    pub training: serde_json::Value,
    /// The weights a fine-tune started from (`--init`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub init_sha256: Option<String>,
    /// The shard build's identity (sha256 of its manifest).
    pub data: String,
    /// Training examples (meshes that fit the model).
    #[serde(alias = "train_meshes")]
    pub train_examples: usize,
    /// The last validation record of the run (in DiT manifests written before this field, its
    /// flow loss alone).
    #[serde(alias = "final_validation_loss")]
    pub final_validation: serde_json::Value,
    pub wall_time_s: f64,
    pub machine: String,
    pub backend: String,
}

/// `vae.manifest.json`: what inference reads (configuration, checksum, latent statistics) and
/// the weights' [`Provenance`]. `meshflow train vae` writes it; [`load_vae`] reads it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct VaeManifest {
    pub model: VaeConfig,
    pub sha256: String,
    /// Per latent channel, over the posterior means of the training meshes.
    pub latent_mean: Vec<f32>,
    pub latent_std: Vec<f32>,
    /// [`latent_space_sha256`] of the loaded weights (computed by [`load_vae`], not read).
    #[serde(skip)]
    pub latent_space_sha256: String,
    #[serde(flatten)]
    pub provenance: Provenance,
}

/// `dit.manifest.json`: what inference reads (configuration, checksum, the VAE it belongs to)
/// and the weights' [`Provenance`]. `meshflow train dit` writes it; [`load_dit`] reads it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DitManifest {
    pub model: DitConfig,
    pub sha256: String,
    /// The VAE whose latents the DiT was trained on.
    pub vae_sha256: String,
    /// That VAE's [`latent_space_sha256`]: a VAE whose decoder was fine-tuned afterwards
    /// (encoder and latent statistics untouched) makes the same latents, so the DiT still fits
    /// it. Absent in manifests written before it existed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vae_latent_space_sha256: Option<String>,
    #[serde(flatten)]
    pub provenance: Provenance,
}

/// Whether a VAE tensor belongs to the encoder side (encoder and the pre-KL projection): the
/// part that defines the latents a DiT learns.
pub fn is_encoder_side(name: &str) -> bool {
    name.starts_with("encoder.") || name.starts_with("pre_kl.")
}

/// The identity of a VAE's latent space: sha256 over its encoder-side tensors (sorted by name;
/// per tensor the name, each dimension as u64 and the values, little-endian) and then the
/// latent mean and standard deviation the DiT normalises by. Two VAEs with the same value
/// encode every mesh to the same normalised latents.
pub fn latent_space_sha256(weights: &TensorMap, latent_mean: &[f32], latent_std: &[f32]) -> String {
    let mut h = Sha256::new();
    for (name, (shape, values)) in &weights.tensors {
        if !is_encoder_side(name) {
            continue;
        }
        h.update(name.as_bytes());
        for &d in shape {
            h.update((d as u64).to_le_bytes());
        }
        for v in values {
            h.update(v.to_le_bytes());
        }
    }
    for v in latent_mean.iter().chain(latent_std) {
        h.update(v.to_le_bytes());
    }
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

/// Lower-case hex sha256 of `bytes`.
pub fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

fn check_sha(what: &'static str, bytes: &[u8], expected: &str) -> Result<(), ShippedError> {
    let actual = sha256_hex(bytes);
    if actual != expected {
        return Err(ShippedError::Checksum {
            what,
            expected: expected.into(),
            actual,
        });
    }
    Ok(())
}

/// Parses a VAE manifest and loads `weights` (safetensors) into a VAE on `device`.
pub fn load_vae(
    manifest: &[u8],
    weights: &[u8],
    device: &Device,
) -> Result<(MeshVae, VaeManifest), ShippedError> {
    let what = "VAE";
    let mut m: VaeManifest = serde_json::from_slice(manifest)
        .map_err(|source| ShippedError::Manifest { what, source })?;
    check_sha(what, weights, &m.sha256)?;
    m.model
        .validate()
        .map_err(|reason| ShippedError::Config { what, reason })?;
    let d = m.model.latent_dim;
    if m.latent_mean.len() != d || m.latent_std.len() != d {
        return Err(ShippedError::Config {
            what,
            reason: format!("latent mean/std must have {d} channels"),
        });
    }
    let map = TensorMap::from_safetensors(weights, "")
        .map_err(|source| ShippedError::Weights { what, source })?;
    let vae = load_module(MeshVae::new(&m.model, device), &map, &|_| false)
        .map_err(|source| ShippedError::Weights { what, source })?;
    m.latent_space_sha256 = latent_space_sha256(&map, &m.latent_mean, &m.latent_std);
    Ok((vae, m))
}

/// Parses a DiT manifest and loads `weights` into a DiT on `device`, refusing a DiT trained on
/// another VAE than `vae` (the same VAE file, or one with the same latent space: see
/// [`latent_space_sha256`]). The reference's image-conditioning tensors are ignored.
pub fn load_dit(
    manifest: &[u8],
    weights: &[u8],
    vae: &VaeManifest,
    device: &Device,
) -> Result<(Dit, DitManifest), ShippedError> {
    let what = "DiT";
    let m: DitManifest = serde_json::from_slice(manifest)
        .map_err(|source| ShippedError::Manifest { what, source })?;
    check_sha(what, weights, &m.sha256)?;
    let same_latents = m.vae_latent_space_sha256.as_ref() == Some(&vae.latent_space_sha256);
    if m.vae_sha256 != vae.sha256 && !same_latents {
        return Err(ShippedError::VaeMismatch {
            dit_vae: m.vae_sha256,
            vae: vae.sha256.clone(),
        });
    }
    m.model
        .validate()
        .map_err(|reason| ShippedError::Config { what, reason })?;
    let map = TensorMap::from_safetensors(weights, "")
        .map_err(|source| ShippedError::Weights { what, source })?;
    let dit = load_module(Dit::new(&m.model, device), &map, &is_image_path)
        .map_err(|source| ShippedError::Weights { what, source })?;
    Ok((dit, m))
}

/// The shipped pair, loaded and checked: the VAE, the DiT trained on its latents, and their
/// manifests. The CLI loads it from a weights folder, the browser from fetched bytes.
pub struct ShippedModels {
    pub vae: MeshVae,
    pub vae_manifest: VaeManifest,
    pub dit: Dit,
    pub dit_manifest: DitManifest,
}

impl ShippedModels {
    /// Loads both models from their manifests (JSON) and safetensors bytes: [`load_vae`], then
    /// [`load_dit`] against that VAE.
    pub fn from_bytes(
        vae_manifest: &[u8],
        vae_weights: &[u8],
        dit_manifest: &[u8],
        dit_weights: &[u8],
        device: &Device,
    ) -> Result<Self, ShippedError> {
        let (vae, vae_manifest) = load_vae(vae_manifest, vae_weights, device)?;
        let (dit, dit_manifest) = load_dit(dit_manifest, dit_weights, &vae_manifest, device)?;
        Ok(Self {
            vae,
            vae_manifest,
            dit,
            dit_manifest,
        })
    }

    /// Loads `dir/{vae,dit}.{manifest.json,safetensors}` ([`read_shipped`]).
    #[cfg(not(target_arch = "wasm32"))]
    pub fn load(dir: &Path, device: &Device) -> Result<Self, ShippedError> {
        let (vae_manifest, vae_weights) = read_shipped(dir, "vae")?;
        let (dit_manifest, dit_weights) = read_shipped(dir, "dit")?;
        Self::from_bytes(
            &vae_manifest,
            &vae_weights,
            &dit_manifest,
            &dit_weights,
            device,
        )
    }

    /// A generator over these models with the shipped budget rule.
    pub fn generator<'a>(&'a self, device: &'a Device) -> Generator<'a> {
        Generator::from_shipped(
            &self.vae,
            &self.vae_manifest,
            &self.dit,
            &self.dit_manifest,
            device,
        )
    }
}

/// The weights folder to use: `flag` when given, else the first that holds a
/// `vae.manifest.json` of: `$MESHFLOW_WEIGHTS`, `./weights`, `weights/` beside the executable
/// or in `../share/meshflow/` from it; else `embedded` (the files of a weights folder compiled
/// into the executable), written once to a cache folder ([`unpack_weights`]), so an installed
/// CLI works from any folder, with or without the repository.
#[cfg(not(target_arch = "wasm32"))]
pub fn locate_weights(
    flag: Option<&Path>,
    embedded: &[(&str, &[u8])],
) -> Result<std::path::PathBuf, ShippedError> {
    use std::path::PathBuf;
    if let Some(dir) = flag {
        return Ok(dir.to_path_buf());
    }
    let mut tried: Vec<PathBuf> = Vec::new();
    if let Some(env) = std::env::var_os("MESHFLOW_WEIGHTS") {
        tried.push(PathBuf::from(env));
    }
    tried.push(PathBuf::from("weights"));
    if let Some(exe_dir) = std::env::current_exe()
        .ok()
        .and_then(|e| e.parent().map(Path::to_path_buf))
    {
        tried.push(exe_dir.join("weights"));
        tried.push(exe_dir.join("../share/meshflow/weights"));
    }
    if let Some(found) = tried.iter().find(|d| d.join("vae.manifest.json").is_file()) {
        return Ok(found.clone());
    }
    unpack_weights(embedded).map_err(|source| ShippedError::NotFound {
        tried: tried
            .iter()
            .map(|d| d.display().to_string())
            .collect::<Vec<_>>()
            .join(", "),
        source,
    })
}

/// Writes the files of `embedded` once into a cache folder named by their manifests' checksum
/// (`$XDG_CACHE_HOME` or `~/.cache`, `meshflow/weights-<sha256 prefix>/`) and returns it. The
/// folder is filled under a temporary name and renamed into place, so a reader never sees half
/// of it.
#[cfg(not(target_arch = "wasm32"))]
pub fn unpack_weights(embedded: &[(&str, &[u8])]) -> std::io::Result<std::path::PathBuf> {
    use std::path::PathBuf;
    let cache = std::env::var_os("XDG_CACHE_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))
        .unwrap_or_else(std::env::temp_dir)
        .join("meshflow");
    // The manifests name their safetensors by sha256, so hashing them (not 25 MB of weights on
    // every run) identifies the pair.
    let manifests: Vec<u8> = embedded
        .iter()
        .filter(|(name, _)| name.ends_with(".manifest.json"))
        .flat_map(|(_, bytes)| bytes.iter().copied())
        .collect();
    let dir = cache.join(format!("weights-{}", &sha256_hex(&manifests)[..16]));
    if dir.join("dit.safetensors").is_file() {
        return Ok(dir);
    }
    let partial = cache.join(format!("weights-partial-{}", std::process::id()));
    std::fs::create_dir_all(&partial)?;
    for (name, bytes) in embedded {
        std::fs::write(partial.join(name), bytes)?;
    }
    if std::fs::rename(&partial, &dir).is_err() {
        // Another process put it in place first.
        let _ = std::fs::remove_dir_all(&partial);
    }
    Ok(dir)
}

/// Reads `dir/NAME.manifest.json` and `dir/NAME.safetensors` (NAME: `vae` or `dit`).
#[cfg(not(target_arch = "wasm32"))]
pub fn read_shipped(dir: &Path, name: &str) -> Result<(Vec<u8>, Vec<u8>), ShippedError> {
    let read = |file: String| {
        let path = dir.join(file);
        std::fs::read(&path).map_err(|source| ShippedError::Read {
            path: path.display().to_string(),
            source,
        })
    };
    Ok((
        read(format!("{name}.manifest.json"))?,
        read(format!("{name}.safetensors"))?,
    ))
}

/// Loads the VAE of a weights folder (sha256, configuration and shapes checked).
#[cfg(not(target_arch = "wasm32"))]
pub fn load_vae_dir(dir: &Path, device: &Device) -> Result<(MeshVae, VaeManifest), ShippedError> {
    let (manifest, weights) = read_shipped(dir, "vae")?;
    load_vae(&manifest, &weights, device)
}

/// Writes `dir/NAME.safetensors`, `NAME.json` (the model configuration) and
/// `NAME.manifest.json`, each file whole or not at all; the manifest last, so a manifest never
/// names weights that are not there yet.
#[cfg(not(target_arch = "wasm32"))]
pub fn write_weights(
    dir: &Path,
    name: &str,
    bytes: &[u8],
    model: &impl Serialize,
    manifest: &impl Serialize,
) -> std::io::Result<()> {
    use crate::io::write_atomic;
    write_atomic(&dir.join(format!("{name}.safetensors")), bytes)?;
    write_atomic(
        &dir.join(format!("{name}.json")),
        serde_json::to_string_pretty(model)?.as_bytes(),
    )?;
    write_atomic(
        &dir.join(format!("{name}.manifest.json")),
        serde_json::to_string_pretty(manifest)?.as_bytes(),
    )?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shipped(name: &str) -> Vec<u8> {
        let path = format!("{}/../weights/{name}", env!("CARGO_MANIFEST_DIR"));
        std::fs::read(path).expect("the shipped weights")
    }

    /// The one manifest type reads what training wrote (the shipped files, whose older VAE
    /// field `train_meshes` is an alias) and writes back what it read.
    #[test]
    fn shipped_manifests_round_trip_with_their_provenance() {
        let vae: VaeManifest = serde_json::from_slice(&shipped("vae.manifest.json")).unwrap();
        let dit: DitManifest = serde_json::from_slice(&shipped("dit.manifest.json")).unwrap();
        for p in [&vae.provenance, &dit.provenance] {
            assert!(p.parameters > 0 && p.train_examples > 0 && p.wall_time_s > 0.0);
            assert!(p.command.contains("meshflow train"), "{}", p.command);
            assert!(
                p.training
                    .get("steps")
                    .is_some_and(|s| s.as_u64() > Some(0))
            );
        }
        assert_eq!(vae.latent_mean.len(), vae.model.latent_dim);
        let again: VaeManifest =
            serde_json::from_str(&serde_json::to_string(&vae).unwrap()).unwrap();
        assert_eq!(again, vae);
        let again: DitManifest =
            serde_json::from_str(&serde_json::to_string(&dit).unwrap()).unwrap();
        assert_eq!(again, dit);
    }
}
