//! The shipped pair in `weights/`: the DiT's manifest names the VAE it was trained on, by file
//! (and by latent space where it records one), and that identity holds for the VAE that ships
//! beside it.

use burn::tensor::Device;
use meshflow::pipeline::shipped::{load_dit, load_vae};

fn read(name: &str) -> Vec<u8> {
    std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/../weights/").to_string() + name).unwrap()
}

#[test]
fn the_shipped_dit_fits_the_shipped_vae() {
    let device = Device::flex();
    let (_, vae) = load_vae(
        &read("vae.manifest.json"),
        &read("vae.safetensors"),
        &device,
    )
    .unwrap();
    let dit_manifest: serde_json::Value =
        serde_json::from_slice(&read("dit.manifest.json")).unwrap();
    // The f16 files: the DiT names the f16 VAE's file (scripts/half-weights.mjs drops the
    // latent-space identity, which rounding changes).
    assert_eq!(
        dit_manifest["vae_sha256"].as_str(),
        Some(vae.sha256.as_str())
    );
    if let Some(space) = dit_manifest["vae_latent_space_sha256"].as_str() {
        assert_eq!(space, vae.latent_space_sha256);
    }
    load_dit(
        &read("dit.manifest.json"),
        &read("dit.safetensors"),
        &vae,
        &device,
    )
    .unwrap();
    // Another VAE (another file, another latent space) is refused.
    let mut other = vae.clone();
    other.latent_space_sha256 = "0".repeat(64);
    other.sha256 = "1".repeat(64);
    let Err(err) = load_dit(
        &read("dit.manifest.json"),
        &read("dit.safetensors"),
        &other,
        &device,
    ) else {
        panic!("a DiT of another latent space was accepted");
    };
    assert!(err.to_string().contains("another VAE"), "{err}");
}
