//! Token features and vertex normals against the golden vectors produced by the reference
//! implementation (`shared/golden`, see its README).

mod common;

use common::{Golden, max_abs_diff};
use glam::Vec3;
use meshflow::geometry::normals::vertex_normals;
use meshflow::model::tokens::{
    TokenConfig, assemble_features, embed_dim, fourier_embed, in_channels,
};

fn vec3s(flat: &[f32]) -> Vec<Vec3> {
    flat.chunks_exact(3).map(Vec3::from_slice).collect()
}

#[test]
fn fourier_embedding_matches_reference() {
    let g = Golden::load("vae_small");
    let verts = g.f32("input.padded_verts");
    assert_eq!(verts.shape, [2, 64, 3]);
    let verts = verts.data;
    let want = g.f32("output.embed_padded_verts");
    assert_eq!(want.shape, [2, 64, embed_dim(16)]);
    let want = want.data;
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
    let g = Golden::load("vae_small");
    let cfg = TokenConfig::vae_small();
    let verts = g.f32("input.padded_verts").data;
    let normals = g.f32("input.verts_normal").data;
    let neighbors = g.f32("input.neighbor_points");
    assert_eq!(neighbors.shape, [2, 64, 3 * cfg.max_degree]);
    let neighbors = neighbors.data;
    let want = g.f32("output.x");
    assert_eq!(want.shape, [2, 64, in_channels(&cfg)]);
    let want = want.data;
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
    let g = Golden::load("extract_cases");
    for (mesh, case) in [
        ("octahedron", "octahedron_full"),
        ("grid4x4", "grid4x4_full"),
        ("icosphere1", "icosphere1_full"),
    ] {
        let verts = g.f32(&format!("input.{case}.verts")).data;
        let want = g.f32(&format!("input.{case}.normals")).data;
        let faces = g.triples(&format!("gt.{mesh}.faces"));
        let got: Vec<f32> = vertex_normals(&vec3s(&verts), &faces)
            .iter()
            .flat_map(|n| n.to_array())
            .collect();
        let err = max_abs_diff(&got, &want);
        eprintln!("{mesh} vertex normals: max abs diff {err:e}");
        assert!(err < 1e-5, "{mesh}: max abs diff {err}");
    }
}
