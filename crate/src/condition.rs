//! Point-cloud conditioning of the DiT: the RoPE-3D position of every latent token, and the
//! vertex-count condition.
//!
//! Training and inference must give latent tokens statistically alike positions:
//! - **Training** ([`latent_positions`]): latent `i` merges vertex tokens `r i .. r i + r`
//!   (in [`crate::tokens::vertex_order`], ascending `(z, y, x)`); its position is the voxel of
//!   the first of them. Padding latents hold copies of random real vertices.
//! - **Inference** ([`inference_positions`]): for a budget of `V` vertices, draw `ceil(V / r)`
//!   points uniformly from the input's surface samples, order them by the same `(z, y, x)` rule,
//!   and give latent `i` the voxel of point `i`; the remaining (padding) latents take random
//!   ones of those points, like padding vertices copy random real ones.
//!
//! The vertex-count condition is `vertex_count / num_latents` (DESIGN.md section 2).

use glam::Vec3;

use crate::rng::Rng;
use crate::tokens::{VertexTokens, vertex_order};
use crate::voxel::voxel_index;

/// Voxel `[x, y, z]` of a model-frame point, as RoPE input (f32).
fn rope_cell(p: Vec3) -> [f32; 3] {
    voxel_index(p).map(|c| c as f32)
}

/// Positions of the `N / r` latent tokens of one training mesh (see the module doc).
pub fn latent_positions(tokens: &VertexTokens, ratio: usize) -> Vec<[f32; 3]> {
    tokens
        .positions
        .chunks(ratio)
        .map(|group| rope_cell(group[0]))
        .collect()
}

/// Positions of `num_latents` tokens for generating `vertex_budget` vertices from surface
/// samples of the input (model frame). Seeded.
pub fn inference_positions(
    surface: &[Vec3],
    vertex_budget: usize,
    num_latents: usize,
    ratio: usize,
    seed: u64,
) -> Vec<[f32; 3]> {
    if surface.is_empty() || num_latents == 0 {
        return vec![[0.0; 3]; num_latents];
    }
    let real = vertex_budget.div_ceil(ratio.max(1)).clamp(1, num_latents);
    let mut rng = Rng::new(seed);
    let mut picked: Vec<Vec3> = (0..real)
        .map(|_| surface[rng.below(surface.len())])
        .collect();
    let order = vertex_order(&picked);
    picked = order.iter().map(|&i| picked[i as usize]).collect();
    let mut cells: Vec<[f32; 3]> = picked.iter().map(|&p| rope_cell(p)).collect();
    while cells.len() < num_latents {
        cells.push(cells[rng.below(real)]);
    }
    cells
}

/// The vertex-count condition fed to the time embedding.
pub fn vertex_condition(vertex_count: usize, num_latents: usize) -> f32 {
    vertex_count as f32 / num_latents.max(1) as f32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::normalize::Normalization;
    use crate::primitives::icosphere;
    use crate::tokens::{TokenConfig, build_tokens};

    #[test]
    fn training_positions_follow_the_token_groups() {
        let mesh = icosphere(1);
        let mesh = Normalization::to_model_frame(mesh.aabb().unwrap()).apply_mesh(&mesh);
        let cfg = TokenConfig {
            num_vertices: 64,
            max_degree: 8,
            num_freqs: 4,
        };
        let t = build_tokens(&mesh, &cfg, 1).unwrap();
        let pos = latent_positions(&t, 4);
        assert_eq!(pos.len(), 16);
        for (i, p) in pos.iter().enumerate() {
            assert_eq!(*p, rope_cell(t.positions[4 * i]));
            assert!(p.iter().all(|&c| (0.0..32.0).contains(&c)));
        }
        // Real groups are in (z, y, x) order, so their z cells never decrease.
        let real_groups = t.num_real / 4;
        assert!(pos[..real_groups].windows(2).all(|w| w[0][2] <= w[1][2]));
    }

    #[test]
    fn inference_positions_are_sorted_then_padded_and_seeded() {
        let surface: Vec<Vec3> = (0..500)
            .map(|i| {
                let a = i as f32 * 0.37;
                Vec3::new(a.sin(), (a * 0.5).cos(), (i as f32 / 250.0) - 1.0)
            })
            .collect();
        let pos = inference_positions(&surface, 100, 64, 4, 7);
        assert_eq!(pos.len(), 64);
        assert!(pos[..25].windows(2).all(|w| w[0][2] <= w[1][2]));
        for p in &pos[25..] {
            assert!(pos[..25].contains(p), "padding copies a real position");
        }
        assert_eq!(pos, inference_positions(&surface, 100, 64, 4, 7));
        assert_eq!(inference_positions(&[], 10, 8, 4, 0), vec![[0.0; 3]; 8]);
        assert_eq!(inference_positions(&surface, 10_000, 8, 4, 0).len(), 8);
    }
}
