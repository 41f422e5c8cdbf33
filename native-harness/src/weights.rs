//! The weights a command runs: `--weights`, else the shipped ones wherever they are found,
//! else the copy compiled into the binary; loaded and checked against their manifests.

use std::path::{Path, PathBuf};

use anyhow::Result;
use meshflow::burn::tensor::Device;
use meshflow::model::MeshVae;
use meshflow::pipeline::shipped::{
    ShippedError, ShippedModels, VaeManifest, load_vae_dir, locate_weights,
};

use crate::bad_input;

/// `(name, bytes)` of each named file of the repository's `weights/` folder.
macro_rules! embed_weights {
    ($($name:literal),*) => {
        [$(($name, include_bytes!(concat!("../../weights/", $name)) as &[u8])),*]
    };
}

/// The shipped weights, compiled into the binary: the last resort of [`weights_dir`], so an
/// installed `meshflow` works with no repository and no weights folder beside it.
const EMBEDDED_WEIGHTS: [(&str, &[u8]); 4] = embed_weights!(
    "vae.manifest.json",
    "vae.safetensors",
    "dit.manifest.json",
    "dit.safetensors"
);

/// The weights folder to use: `--weights` when given, else the shipped weights found from any
/// folder, else the copy compiled into the binary
/// ([`meshflow::pipeline::shipped::locate_weights`]).
pub fn weights_dir(flag: Option<&Path>) -> Result<PathBuf> {
    locate_weights(flag, &EMBEDDED_WEIGHTS).map_err(bad_input)
}

/// A shipped-weights error as the CLI reports it: a file that cannot be read is an I/O
/// failure, weights that do not check out are bad input (exit status 2).
fn shipped_error(dir: &Path, e: ShippedError) -> anyhow::Error {
    match e {
        ShippedError::Read { .. } => anyhow::anyhow!(e),
        e => bad_input(format!("{}: {e}", dir.display())),
    }
}

/// Loads the VAE and DiT of a weights folder, each file checked against its manifest's sha256
/// and the DiT against the VAE it was trained on.
pub fn load_models(dir: &Path, device: &Device) -> Result<ShippedModels> {
    ShippedModels::load(dir, device).map_err(|e| shipped_error(dir, e))
}

/// Loads the VAE of a weights folder (sha256, configuration and shapes checked).
pub fn load_vae(dir: &Path, device: &Device) -> Result<(MeshVae, VaeManifest)> {
    load_vae_dir(dir, device).map_err(|e| shipped_error(dir, e))
}
