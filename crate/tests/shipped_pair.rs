//! The shipped pair in `weights/`: the DiT's manifest names the VAE it was trained on, by file
//! and by latent space, and both identities hold for the VAE that ships beside it.

use burn::tensor::Device;
use meshflow::pipeline::shipped::{load_dit, load_vae};

fn read(name: &str) -> Vec<u8> {
    std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/../weights/").to_string() + name).unwrap()
}

#[test]
fn the_shipped_dit_fits_the_shipped_vae_latent_space() {
    let device = Device::flex();
    let (_, vae) = load_vae(
        &read("vae.manifest.json"),
        &read("vae.safetensors"),
        &device,
    )
    .unwrap();
    let dit_manifest: serde_json::Value =
        serde_json::from_slice(&read("dit.manifest.json")).unwrap();
    assert_eq!(
        dit_manifest["vae_latent_space_sha256"].as_str(),
        Some(vae.latent_space_sha256.as_str())
    );
    load_dit(
        &read("dit.manifest.json"),
        &read("dit.safetensors"),
        &vae,
        &device,
    )
    .unwrap();
    // Another latent space is refused even when the file's sha256 is claimed to match.
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
