//! Token features and vertex normals against the golden vectors produced by the reference
//! implementation (`shared/golden`, see its README). Skipped, with a note on stderr, when the
//! golden directory is absent; `MESHFLOW_GOLDEN` overrides its location.

use std::path::PathBuf;

use glam::Vec3;
use meshflow::normals::vertex_normals;
use meshflow::tokens::{TokenConfig, assemble_features, embed_dim, fourier_embed, in_channels};
use safetensors::{Dtype, SafeTensors};

fn golden_dir() -> Option<PathBuf> {
    let dir = std::env::var_os("MESHFLOW_GOLDEN")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/golden"));
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!("golden directory {} not found: skipping", dir.display());
        None
    }
}

fn load(name: &str) -> Option<Vec<u8>> {
    let path = golden_dir()?.join(name);
    Some(std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display())))
}

fn f32s(st: &SafeTensors, name: &str) -> (Vec<usize>, Vec<f32>) {
    let t = st.tensor(name).unwrap_or_else(|e| panic!("{name}: {e}"));
    assert_eq!(t.dtype(), Dtype::F32, "{name}");
    let v = t
        .data()
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect();
    (t.shape().to_vec(), v)
}

fn i64s(st: &SafeTensors, name: &str) -> (Vec<usize>, Vec<i64>) {
    let t = st.tensor(name).unwrap_or_else(|e| panic!("{name}: {e}"));
    assert_eq!(t.dtype(), Dtype::I64, "{name}");
    let v = t
        .data()
        .chunks_exact(8)
        .map(|b| i64::from_le_bytes(b.try_into().unwrap()))
        .collect();
    (t.shape().to_vec(), v)
}

fn vec3s(flat: &[f32]) -> Vec<Vec3> {
    flat.chunks_exact(3).map(Vec3::from_slice).collect()
}

fn max_abs_diff(a: &[f32], b: &[f32]) -> f32 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f32::max)
}

#[test]
fn fourier_embedding_matches_reference() {
    let Some(bytes) = load("vae_small.safetensors") else {
        return;
    };
    let st = SafeTensors::deserialize(&bytes).unwrap();
    let (shape, verts) = f32s(&st, "input.padded_verts");
    assert_eq!(shape, [2, 64, 3]);
    let (shape, want) = f32s(&st, "output.embed_padded_verts");
    assert_eq!(shape, [2, 64, embed_dim(16)]);
    let mut got = Vec::new();
    for v in vec3s(&verts) {
        fourier_embed(v, 16, &mut got);
    }
    let err = max_abs_diff(&got, &want);
    eprintln!("fourier embedding: max abs diff {err:e}");
    assert!(err < 1e-6, "max abs diff {err}");
    // The frequencies are 2^k, not pi 2^k (NeRF-style): that alternative is far off.
    let pi_scaled: Vec<f32> = vec3s(&verts)
        .iter()
        .flat_map(|v| {
            let mut row = vec![v.x, v.y, v.z];
            let args: Vec<f32> = v
                .to_array()
                .iter()
                .flat_map(|&c| (0..16).map(move |k| std::f32::consts::PI * 2f32.powi(k) * c))
                .collect();
            row.extend(args.iter().map(|a| a.sin()));
            row.extend(args.iter().map(|a| a.cos()));
            row
        })
        .collect();
    assert!(max_abs_diff(&pi_scaled, &want) > 0.1);
}

#[test]
fn encoder_input_matches_reference() {
    let Some(bytes) = load("vae_small.safetensors") else {
        return;
    };
    let st = SafeTensors::deserialize(&bytes).unwrap();
    let cfg = TokenConfig::vae_small();
    let (_, verts) = f32s(&st, "input.padded_verts");
    let (_, normals) = f32s(&st, "input.verts_normal");
    let (shape, neighbors) = f32s(&st, "input.neighbor_points");
    assert_eq!(shape, [2, 64, 3 * cfg.max_degree]);
    let (shape, want) = f32s(&st, "output.x");
    assert_eq!(shape, [2, 64, in_channels(&cfg)]);
    let (verts, normals) = (vec3s(&verts), vec3s(&normals));
    let mut got = Vec::new();
    for (i, nb) in neighbors.chunks_exact(3 * cfg.max_degree).enumerate() {
        assemble_features(verts[i], normals[i], &vec3s(nb), &cfg, &mut got);
    }
    let err = max_abs_diff(&got, &want);
    eprintln!("encoder input x: max abs diff {err:e}");
    assert!(err < 1e-6, "max abs diff {err}");
    // The neighbour block is copied verbatim.
    for (row, nb) in got
        .chunks_exact(in_channels(&cfg))
        .zip(neighbors.chunks_exact(24))
    {
        assert_eq!(&row[198..], nb);
    }
}

#[test]
fn vertex_normals_match_reference() {
    let Some(bytes) = load("extract_cases.safetensors") else {
        return;
    };
    let st = SafeTensors::deserialize(&bytes).unwrap();
    for (mesh, case) in [
        ("octahedron", "octahedron_full"),
        ("grid4x4", "grid4x4_full"),
        ("icosphere1", "icosphere1_full"),
    ] {
        let (_, verts) = f32s(&st, &format!("input.{case}.verts"));
        let (_, want) = f32s(&st, &format!("input.{case}.normals"));
        let (shape, faces) = i64s(&st, &format!("gt.{mesh}.faces"));
        assert_eq!(shape[1], 3);
        let faces: Vec<[u32; 3]> = faces
            .chunks_exact(3)
            .map(|f| [f[0] as u32, f[1] as u32, f[2] as u32])
            .collect();
        let got: Vec<f32> = vertex_normals(&vec3s(&verts), &faces)
            .iter()
            .flat_map(|n| n.to_array())
            .collect();
        let err = max_abs_diff(&got, &want);
        eprintln!("{mesh} vertex normals: max abs diff {err:e}");
        assert!(err < 1e-5, "{mesh}: max abs diff {err}");
    }
}
