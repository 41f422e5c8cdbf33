//! Training runs that end in shippable weights, as `meshflow train vae|dit` runs them: the
//! data read from a shard build and checked against the model, an optional `--init` checked
//! against the configuration, the training loop, and the weights written with their manifest
//! (sha256, latent statistics, provenance). Each run is prepared first ([`VaeRun::prepare`],
//! [`DitRun::prepare`]) so the caller can say what is about to train, then trained.

use std::path::{Path, PathBuf};
use std::time::Instant;

use burn::tensor::Device;

use crate::Mesh;
use crate::data::dataset::Split;
use crate::data::shards::{ShardsError, load_split};
use crate::device::{BackendKind, machine_description};
use crate::model::{MeshVae, TensorMap, WeightsError, load_module, widen_edge_embeddings};
use crate::pipeline::shipped::{
    DitManifest, Provenance, ShippedError, VaeManifest, is_encoder_side, load_dit, load_vae,
    load_vae_dir, read_shipped, sha256_hex, write_weights,
};
use crate::train::dit::{DitTrainConfig, LatentExample, encode_latents, train_dit};
use crate::train::run::Trained;
use crate::train::vae::{VaeTrainConfig, latent_statistics, train_vae_from};
use crate::train::{TrainError, TrainObserver, data_version};

/// Added edge-embedding channels start at this fraction of the trained ones' spread
/// ([`widen_edge_embeddings`]): small enough to leave the trained distances almost unchanged.
const WIDENED_EDGE_SCALE: f32 = 0.1;

/// Why a run could not start or finish.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The request cannot be met (a bad configuration, no data that fits, a mismatched
    /// `--init`).
    #[error("{0}")]
    BadInput(String),
    #[error(transparent)]
    Shards(#[from] ShardsError),
    #[error("{dir}: {source}")]
    Shipped { dir: String, source: ShippedError },
    #[error(transparent)]
    Train(#[from] TrainError),
    #[error(transparent)]
    Weights(#[from] WeightsError),
    #[error("{0}")]
    Io(#[from] std::io::Error),
    #[error("{0}")]
    Json(#[from] serde_json::Error),
}

impl RunError {
    /// Whether the caller asked for something that cannot be (as opposed to a failure).
    pub fn is_bad_input(&self) -> bool {
        match self {
            Self::BadInput(_) => true,
            Self::Shipped { source, .. } => !matches!(source, ShippedError::Read { .. }),
            _ => false,
        }
    }
}

fn shipped(dir: &Path) -> impl Fn(ShippedError) -> RunError + '_ {
    move |source| RunError::Shipped {
        dir: dir.display().to_string(),
        source,
    }
}

/// What a finished run wrote.
pub struct RunSummary {
    pub steps: usize,
    pub wall_s: f64,
    /// The safetensors file written.
    pub weights: PathBuf,
}

/// Where a run writes and what its manifest records about how it ran.
pub struct RunTarget<'a> {
    /// The run folder: checkpoints, `metrics.jsonl` (a run found there resumes) and the
    /// weights.
    pub out: &'a Path,
    pub backend: BackendKind,
    /// The command line that started the run.
    pub command: String,
}

impl RunTarget<'_> {
    /// The manifest's provenance of `weights` trained with `training` on `train_examples`
    /// examples of the shard build `shards`.
    #[allow(clippy::too_many_arguments)]
    fn provenance(
        &self,
        weights: &TensorMap,
        training: &impl serde::Serialize,
        init_sha256: Option<String>,
        shards: &Path,
        train_examples: usize,
        final_validation: &impl serde::Serialize,
        wall_time_s: f64,
    ) -> Result<Provenance, RunError> {
        Ok(Provenance {
            parameters: weights.tensors.values().map(|(_, v)| v.len()).sum(),
            command: self.command.clone(),
            training: serde_json::to_value(training)?,
            init_sha256,
            data: data_version(shards),
            train_examples,
            final_validation: serde_json::to_value(final_validation)?,
            wall_time_s,
            machine: machine_description(),
            backend: self.backend.name().into(),
        })
    }
}

/// A MeshVAE run, ready to train.
pub struct VaeRun {
    pub config: VaeTrainConfig,
    pub train: Vec<Mesh>,
    pub val: Vec<Mesh>,
    shards: PathBuf,
    init: Option<(TensorMap, VaeManifest)>,
}

impl VaeRun {
    /// Validates `config`, reads the train split's meshes that fit (the first `limit`, 0 =
    /// all) and `val_meshes` validation meshes from `shards`, and checks `init` (a weights
    /// folder whose VAE has this configuration; required by a decoder-only configuration).
    pub fn prepare(
        config: VaeTrainConfig,
        shards: &Path,
        limit: usize,
        val_meshes: usize,
        init: Option<&Path>,
        device: &Device,
    ) -> Result<Self, RunError> {
        config
            .validate()
            .map_err(|e| RunError::BadInput(format!("configuration: {e}")))?;
        let fits = |m: &Mesh| m.positions.len() <= config.model.num_vertices;
        let mut train: Vec<Mesh> = load_split(shards, Split::Train)?
            .into_iter()
            .filter(fits)
            .collect();
        if limit > 0 {
            train.truncate(limit);
        }
        let val: Vec<Mesh> = load_split(shards, Split::Val)?
            .into_iter()
            .filter(fits)
            .take(val_meshes)
            .collect();
        if train.is_empty() {
            return Err(RunError::BadInput(format!(
                "no training mesh in {} has at most {} vertices",
                shards.display(),
                config.model.num_vertices
            )));
        }
        let init = match init {
            Some(dir) => {
                // One read: the checked load (sha256, shapes) and the tensors come from the
                // same bytes.
                let (manifest_bytes, bytes) = read_shipped(dir, "vae").map_err(shipped(dir))?;
                let (_, manifest) = load_vae(&manifest_bytes, &bytes, device)
                    .map_err(|e| RunError::BadInput(format!("--init {}: {e}", dir.display())))?;
                let mut map = TensorMap::from_safetensors(&bytes, "")?;
                if config.decoder_only && manifest.model.same_encoder(&config.model) {
                    // A decoder of another size on the same encoder starts afresh; one of the
                    // same shapes, or with vertex blocks added, keeps the trained decoder.
                    if !config.model.continues_decoder_of(&manifest.model) {
                        map.tensors.retain(|name, _| is_encoder_side(name));
                    } else if config.model.edge_dim > manifest.model.edge_dim {
                        widen_edge_embeddings(
                            &mut map,
                            manifest.model.edge_dim,
                            config.model.edge_dim,
                            WIDENED_EDGE_SCALE,
                            config.seed,
                        )
                        .map_err(|e| {
                            RunError::BadInput(format!("--init {}: {e}", dir.display()))
                        })?;
                    }
                } else if !manifest.model.same_shapes(&config.model) {
                    return Err(RunError::BadInput(format!(
                        "--init {}: its VAE configuration differs from the training \
                         configuration's{}",
                        dir.display(),
                        if config.decoder_only {
                            " in the encoder"
                        } else {
                            ""
                        }
                    )));
                }
                Some((map, manifest))
            }
            None if config.decoder_only => {
                return Err(RunError::BadInput(
                    "configuration: decoder_only needs --init WEIGHTS (the VAE whose encoder it \
                     keeps)"
                        .into(),
                ));
            }
            None => None,
        };
        Ok(Self {
            config,
            train,
            val,
            shards: shards.to_path_buf(),
            init,
        })
    }

    /// Trains into `target.out` and writes `vae.{safetensors,json,manifest.json}` there.
    pub fn train(
        self,
        target: &RunTarget,
        device: &Device,
        observer: &mut dyn TrainObserver,
    ) -> Result<RunSummary, RunError> {
        let (cfg, out) = (&self.config, target.out);
        std::fs::create_dir_all(out)?;
        let started = Instant::now();
        let trained = train_vae_from(
            cfg,
            self.init.as_ref().map(|(map, _)| map),
            &self.train,
            &self.val,
            out,
            device,
            observer,
        )?;
        let wall_s = trained.earlier_s + started.elapsed().as_secs_f64();
        let vae = load_module(MeshVae::new(&cfg.model, device), &trained.weights, &|_| {
            false
        })?;
        // A decoder-only run keeps the encoder, so the statistics the DiT normalises by stay
        // the initial VAE's exactly (recomputing could differ in the last bit).
        let (latent_mean, latent_std) = match &self.init {
            Some((_, m)) if cfg.decoder_only => (m.latent_mean.clone(), m.latent_std.clone()),
            _ => latent_statistics(&vae, &cfg.model, &self.train, device),
        };
        let bytes = trained.weights.to_safetensors(None);
        let model = cfg.trained_model();
        let manifest = VaeManifest {
            model: model.clone(),
            sha256: sha256_hex(&bytes),
            latent_mean,
            latent_std,
            latent_space_sha256: String::new(),
            provenance: target.provenance(
                &trained.weights,
                cfg,
                self.init.as_ref().map(|(_, m)| m.sha256.clone()),
                &self.shards,
                self.train.len(),
                &trained.last_validation,
                wall_s,
            )?,
        };
        write_weights(out, "vae", &bytes, &model, &manifest)?;
        Ok(RunSummary {
            steps: trained.steps,
            wall_s,
            weights: out.join("vae.safetensors"),
        })
    }
}

/// A DiT run on a trained VAE's latents, ready to train.
pub struct DitRun {
    pub config: DitTrainConfig,
    /// The train and validation meshes that fit the VAE, encoded.
    pub train: Vec<LatentExample>,
    pub val: Vec<LatentExample>,
    /// Seconds spent encoding.
    pub encode_s: f64,
    vae_manifest: VaeManifest,
    shards: PathBuf,
    init: Option<(TensorMap, String)>,
    /// When encoding started: the run's wall time counts from here.
    started: Instant,
}

impl DitRun {
    /// Loads the VAE of `vae_dir`, takes `config` (default: the shipped recipe for its latent
    /// shape, [`crate::train::presets::dit_ship`]; `steps` overrides its steps) and checks it
    /// against the VAE, checks
    /// `init` (a DiT of this configuration trained on this VAE's latents), and encodes the
    /// train and validation meshes of `shards` that fit the VAE.
    pub fn prepare(
        config: Option<DitTrainConfig>,
        steps: Option<usize>,
        vae_dir: &Path,
        shards: &Path,
        init: Option<&Path>,
        device: &Device,
    ) -> Result<Self, RunError> {
        let (vae, vae_manifest) = load_vae_dir(vae_dir, device).map_err(shipped(vae_dir))?;
        let vcfg = &vae_manifest.model;
        let mut config = config
            .unwrap_or_else(|| crate::train::presets::dit_ship(vcfg.num_latents, vcfg.latent_dim));
        if let Some(s) = steps {
            config.steps = s;
        }
        let (dit_shape, vae_shape) = (
            (config.model.num_latents, config.model.latent_dim),
            (vcfg.num_latents, vcfg.latent_dim),
        );
        if dit_shape != vae_shape {
            return Err(RunError::BadInput(format!(
                "the DiT takes {} x {} latents but the VAE makes {} x {}",
                dit_shape.0, dit_shape.1, vae_shape.0, vae_shape.1
            )));
        }
        config
            .validate()
            .map_err(|e| RunError::BadInput(format!("configuration: {e}")))?;
        let init = match init {
            Some(dir) => {
                // The checked load (sha256, shapes, the VAE's latent space) and the tensors
                // come from the same bytes.
                let (manifest_bytes, bytes) = read_shipped(dir, "dit").map_err(shipped(dir))?;
                let (_, manifest) = load_dit(&manifest_bytes, &bytes, &vae_manifest, device)
                    .map_err(|e| RunError::BadInput(format!("--init {}: {e}", dir.display())))?;
                if !manifest.model.same_shapes(&config.model) {
                    return Err(RunError::BadInput(format!(
                        "--init {}: its DiT configuration differs from the training \
                         configuration's",
                        dir.display()
                    )));
                }
                Some((TensorMap::from_safetensors(&bytes, "")?, manifest.sha256))
            }
            None => None,
        };
        let started = Instant::now();
        let encode = |split| -> Result<Vec<LatentExample>, RunError> {
            let meshes: Vec<Mesh> = load_split(shards, split)?
                .into_iter()
                .filter(|m| m.positions.len() <= vcfg.num_vertices)
                .collect();
            let (mean, std) = (&vae_manifest.latent_mean, &vae_manifest.latent_std);
            Ok(encode_latents(&vae, vcfg, &meshes, mean, std, device))
        };
        let train = encode(Split::Train)?;
        let val = encode(Split::Val)?;
        if train.is_empty() {
            return Err(RunError::BadInput(format!(
                "no training mesh in {} fits the VAE",
                shards.display()
            )));
        }
        Ok(Self {
            config,
            train,
            val,
            encode_s: started.elapsed().as_secs_f64(),
            vae_manifest,
            shards: shards.to_path_buf(),
            init,
            started,
        })
    }

    /// Trains into `target.out` and writes `dit.{safetensors,json,manifest.json}` there (the
    /// manifest's wall time includes [`Self::prepare`]'s encoding).
    pub fn train(
        self,
        target: &RunTarget,
        device: &Device,
        observer: &mut dyn TrainObserver,
    ) -> Result<RunSummary, RunError> {
        let (cfg, out) = (&self.config, target.out);
        std::fs::create_dir_all(out)?;
        let Trained {
            weights,
            steps,
            last_validation: last_val,
            earlier_s,
        } = train_dit(
            cfg,
            self.init.as_ref().map(|(map, _)| map),
            &self.train,
            &self.val,
            out,
            device,
            observer,
        )?;
        let bytes = weights.to_safetensors(None);
        let wall_s = earlier_s + self.started.elapsed().as_secs_f64();
        let manifest = DitManifest {
            model: cfg.model.clone(),
            sha256: sha256_hex(&bytes),
            vae_sha256: self.vae_manifest.sha256.clone(),
            vae_latent_space_sha256: Some(self.vae_manifest.latent_space_sha256.clone()),
            provenance: target.provenance(
                &weights,
                cfg,
                self.init.as_ref().map(|(_, sha)| sha.clone()),
                &self.shards,
                self.train.len(),
                &last_val,
                wall_s,
            )?,
        };
        write_weights(out, "dit", &bytes, &cfg.model, &manifest)?;
        Ok(RunSummary {
            steps,
            wall_s,
            weights: out.join("dit.safetensors"),
        })
    }
}
