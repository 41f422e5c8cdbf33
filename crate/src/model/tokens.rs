//! The MeshVAE's per-vertex input tokens for one mesh (docs/design.md section 2, golden `vae_small`).
//!
//! Rules, all implemented here and nowhere else:
//! - **Frame.** The mesh must already be in the model frame [-1, 1]
//!   ([`crate::geometry::normalize::Normalization::to_model_frame`]) and cleaned ([`crate::geometry::clean`]);
//!   [`build_tokens`] does not normalise.
//! - **Order.** Real vertices become tokens in [`vertex_order`]: ascending `(z, y, x)` compared
//!   with `f32::total_cmp`, ties by original index (MeshGPT-style, deterministic). The order
//!   matters: the encoder's TokenMerge concatenates runs of 4 *consecutive* tokens into one
//!   latent, so consecutive tokens should be spatial neighbours, and the DiT's latent positions
//!   come from those groups.
//! - **Fourier features.** [`fourier_embed`] maps a 3-vector to `3 + 6 F` values
//!   `[x, y, z | sin(2^k c) | cos(2^k c)]`, `c` over (x, y, z), `k` in `0..F`, coordinate-major
//!   (index inside the sin block `c * F + k`). The frequencies are plain powers of two (no pi),
//!   verified against the golden `output.embed_padded_verts` (`crate/tests/golden_tokens.rs`).
//!   The argument `2^k * c` is an exact `f32` product (a power of two), as in an `f32`
//!   implementation; its sine and cosine are evaluated in `f64` and rounded once.
//! - **Features per token** (`in_channels = 2 (3 + 6 F) + 3 max_degree` values):
//!   `[Fourier(position) | Fourier(normal) | neighbour block]`. Normals are `mesh.normals` when
//!   present, else area-weighted [`vertex_normals`].
//! - **Neighbour block.** The positions of the token's neighbours through mesh edges, in
//!   ascending *token* index, 3 floats each, zero-padded to `max_degree`. A vertex with more
//!   than `max_degree` neighbours keeps the first `max_degree` in that order (the data filter
//!   rejects degree > 50, so with `max_degree >= 50` nothing is cut).
//! - **Padding.** Tokens `num_real..N` copy randomly chosen real tokens (features, position,
//!   normal), drawn with [`Rng::new(seed)`](Rng::new) `.below(num_real)` once per padding token,
//!   in token order; their mask is false. Padding tokens have no edges.
//! - **Edges.** The ground-truth adjacency ([`topology::edges`] of the faces) in token indices,
//!   each `[i, j]` with `i < j`, sorted; only real tokens.
//! - **Errors.** An empty mesh, more real vertices than `N`, a face index out of range, or a
//!   normal count that is neither 0 nor one per vertex.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::Mesh;
use crate::geometry::mesh::MeshError;
use crate::geometry::normals::vertex_normals;
use crate::geometry::topology;
use crate::rng::Rng;

/// Shape of the token tensor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct TokenConfig {
    /// N: tokens per mesh (real + padding), e.g. 1024; a multiple of the merge ratio 4.
    pub num_vertices: usize,
    /// Neighbours per token in the neighbour block.
    pub max_degree: usize,
    /// Fourier frequencies F per coordinate.
    pub num_freqs: usize,
}

impl TokenConfig {
    /// The configuration of the golden `vae_small` (N = 64, max degree 8, 16 frequencies).
    pub fn vae_small() -> Self {
        Self {
            num_vertices: 64,
            max_degree: 8,
            num_freqs: 16,
        }
    }

    /// Length of [`fourier_embed`]'s output: `3 + 6 num_freqs`.
    pub fn embed_dim(&self) -> usize {
        embed_dim(self.num_freqs)
    }

    /// Channels per token, see [`in_channels`].
    pub fn in_channels(&self) -> usize {
        in_channels(self)
    }
}

/// Length of [`fourier_embed`]'s output for `num_freqs` frequencies: `3 + 6 num_freqs`.
pub fn embed_dim(num_freqs: usize) -> usize {
    3 + 6 * num_freqs
}

/// Channels per token: `2 (3 + 6 num_freqs) + 3 max_degree` (222 for the golden config).
pub fn in_channels(cfg: &TokenConfig) -> usize {
    2 * embed_dim(cfg.num_freqs) + 3 * cfg.max_degree
}

/// Why [`build_tokens`] refused a mesh.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TokenError {
    #[error("the mesh has no vertices")]
    Empty,
    #[error("{vertices} vertices do not fit in {capacity} tokens")]
    TooManyVertices { vertices: usize, capacity: usize },
    #[error("invalid mesh: {0}")]
    InvalidMesh(MeshError),
}

/// The tokens of one mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct VertexTokens {
    /// `N x in_channels`, row-major.
    pub features: Vec<f32>,
    /// Channels per row of `features`.
    pub in_channels: usize,
    /// Token positions (N, padding included).
    pub positions: Vec<Vec3>,
    /// Token unit normals (N, padding included).
    pub normals: Vec<Vec3>,
    /// True for the `num_real` real tokens (the first ones), false for padding.
    pub mask: Vec<bool>,
    /// Token `i < num_real` -> original vertex index.
    pub order: Vec<u32>,
    /// Padding token `num_real + i` copies real token `padding_source[i]`.
    pub padding_source: Vec<u32>,
    /// Ground-truth edges in token indices, `i < j`, sorted, real tokens only.
    pub edges: Vec<[u32; 2]>,
    pub num_real: usize,
}

impl VertexTokens {
    /// Feature row of token `i`.
    pub fn row(&self, i: usize) -> &[f32] {
        &self.features[i * self.in_channels..(i + 1) * self.in_channels]
    }
}

/// Token order of the vertices: ascending `(z, y, x)` by `total_cmp`, ties by index. Returns
/// `order[token] = vertex`.
pub fn vertex_order(positions: &[Vec3]) -> Vec<u32> {
    let mut order: Vec<u32> = (0..positions.len() as u32).collect();
    // Stable sort: equal keys keep ascending index.
    order.sort_by(|&a, &b| {
        let (p, q) = (positions[a as usize], positions[b as usize]);
        p.z.total_cmp(&q.z)
            .then(p.y.total_cmp(&q.y))
            .then(p.x.total_cmp(&q.x))
    });
    order
}

/// Frequency `k` of the Fourier features: `2^k` (see the module doc).
pub fn fourier_frequency(k: usize) -> f32 {
    2f32.powi(k as i32)
}

/// Appends the `3 + 6 num_freqs` Fourier features of `v` to `out` (layout in the module doc).
pub fn fourier_embed(v: Vec3, num_freqs: usize, out: &mut Vec<f32>) {
    let c = v.to_array();
    out.extend_from_slice(&c);
    let start = out.len();
    out.resize(start + 6 * num_freqs, 0.0);
    let (sin, cos) = out[start..].split_at_mut(3 * num_freqs);
    for (a, &x) in c.iter().enumerate() {
        for k in 0..num_freqs {
            let arg = (fourier_frequency(k) * x) as f64;
            sin[a * num_freqs + k] = arg.sin() as f32;
            cos[a * num_freqs + k] = arg.cos() as f32;
        }
    }
}

/// Appends one token's feature row: `[Fourier(position) | Fourier(normal) | neighbours]`, the
/// neighbour positions taken in the given order, cut or zero-padded to `max_degree`.
pub fn assemble_features(
    position: Vec3,
    normal: Vec3,
    neighbors: &[Vec3],
    cfg: &TokenConfig,
    out: &mut Vec<f32>,
) {
    fourier_embed(position, cfg.num_freqs, out);
    fourier_embed(normal, cfg.num_freqs, out);
    let kept = neighbors.len().min(cfg.max_degree);
    for p in &neighbors[..kept] {
        out.extend_from_slice(&p.to_array());
    }
    out.resize(out.len() + 3 * (cfg.max_degree - kept), 0.0);
}

/// The mesh's edges renumbered into token order (`order[t]` = the vertex of token `t`), each
/// as (i, j) with i < j, sorted: the ground-truth adjacency the VAE's edge loss compares with.
pub fn token_edges(faces: &[[u32; 3]], order: &[u32]) -> Vec<[u32; 2]> {
    let mut rank = vec![0u32; order.len()];
    for (t, &v) in order.iter().enumerate() {
        rank[v as usize] = t as u32;
    }
    let mut edges: Vec<[u32; 2]> = topology::edges(faces)
        .into_iter()
        .map(|[a, b]| {
            let (a, b) = (rank[a as usize], rank[b as usize]);
            [a.min(b), a.max(b)]
        })
        .collect();
    edges.sort_unstable();
    edges
}

/// Builds the tokens of `mesh` (model frame, cleaned) by the rules in the module doc.
pub fn build_tokens(mesh: &Mesh, cfg: &TokenConfig, seed: u64) -> Result<VertexTokens, TokenError> {
    let n = mesh.positions.len();
    if n == 0 {
        return Err(TokenError::Empty);
    }
    if n > cfg.num_vertices {
        return Err(TokenError::TooManyVertices {
            vertices: n,
            capacity: cfg.num_vertices,
        });
    }
    mesh.validate().map_err(TokenError::InvalidMesh)?;
    let computed;
    let normals: &[Vec3] = if mesh.normals.is_empty() {
        computed = vertex_normals(&mesh.positions, &mesh.faces);
        &computed
    } else {
        &mesh.normals
    };
    let order = vertex_order(&mesh.positions);
    let edges = token_edges(&mesh.faces, &order);
    let adj = topology::adjacency(n, &edges);

    let channels = in_channels(cfg);
    let total = cfg.num_vertices;
    let mut features = Vec::with_capacity(total * channels);
    let mut positions = Vec::with_capacity(total);
    let mut token_normals = Vec::with_capacity(total);
    let mut neighbors = Vec::with_capacity(cfg.max_degree);
    for (t, &v) in order.iter().enumerate() {
        let (p, nrm) = (mesh.positions[v as usize], normals[v as usize]);
        neighbors.clear();
        neighbors.extend(
            adj[t]
                .iter()
                .take(cfg.max_degree)
                .map(|&u| mesh.positions[order[u as usize] as usize]),
        );
        assemble_features(p, nrm, &neighbors, cfg, &mut features);
        positions.push(p);
        token_normals.push(nrm);
    }
    let mut rng = Rng::new(seed);
    let mut padding_source = Vec::with_capacity(total - n);
    for _ in n..total {
        let src = rng.below(n);
        padding_source.push(src as u32);
        features.extend_from_within(src * channels..(src + 1) * channels);
        positions.push(positions[src]);
        token_normals.push(token_normals[src]);
    }
    let mut mask = vec![true; n];
    mask.resize(total, false);
    Ok(VertexTokens {
        features,
        in_channels: channels,
        positions,
        normals: token_normals,
        mask,
        order,
        padding_source,
        edges,
        num_real: n,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::primitives::{grid, icosphere, octahedron};

    #[test]
    fn channel_counts() {
        assert_eq!(in_channels(&TokenConfig::vae_small()), 222);
        assert_eq!(embed_dim(16), 99);
        let mut out = Vec::new();
        fourier_embed(Vec3::new(0.5, -0.25, 1.0), 16, &mut out);
        assert_eq!(out.len(), 99);
        assert_eq!(&out[..3], &[0.5, -0.25, 1.0]);
        // sin block: coordinate-major, then the cos block.
        assert!((out[3 + 2] - (4.0f32 * 0.5).sin()).abs() < 1e-7);
        assert!((out[3 + 16 + 1] - (2.0f32 * -0.25).sin()).abs() < 1e-7);
        assert!((out[3 + 48 + 32] - 1f32.cos()).abs() < 1e-7);
    }

    #[test]
    fn order_is_zyx_with_index_ties() {
        let p = vec![
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, -1.0),
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(-1.0, 0.0, 0.0),
        ];
        assert_eq!(vertex_order(&p), vec![2, 4, 1, 3, 0]);
    }

    #[test]
    fn octahedron_tokens() {
        let m = octahedron();
        let cfg = TokenConfig {
            num_vertices: 8,
            max_degree: 3,
            num_freqs: 2,
        };
        let t = build_tokens(&m, &cfg, 1).unwrap();
        assert_eq!(t.in_channels, 2 * 15 + 9);
        assert_eq!(t.features.len(), 8 * t.in_channels);
        // -z first, +z last; the four equator vertices ordered by (y, x).
        assert_eq!(t.order, vec![5, 3, 1, 0, 2, 4]);
        assert_eq!(t.mask, [true, true, true, true, true, true, false, false]);
        assert_eq!(t.edges.len(), 12);
        // Token 0 (-z) neighbours tokens 1..=4, cut to 3: -y, -x, +x.
        let row = t.row(0);
        let nb = &row[30..39];
        assert_eq!(nb, &[0., -1., 0., -1., 0., 0., 1., 0., 0.]);
        for i in 6..8 {
            let src = t.padding_source[i - 6] as usize;
            assert_eq!(t.row(i), t.row(src));
            assert_eq!(t.positions[i], t.positions[src]);
        }
        // Normals of the octahedron point along the vertex.
        for (p, n) in t.positions.iter().zip(&t.normals) {
            assert!((*p - *n).length() < 1e-6);
        }
    }

    #[test]
    fn zero_padding_of_neighbours_and_point_clouds() {
        let m = grid(1, 1); // one quad cut in two triangles: degrees 2 and 3
        let cfg = TokenConfig {
            num_vertices: 4,
            max_degree: 4,
            num_freqs: 1,
        };
        let t = build_tokens(&m, &cfg, 0).unwrap();
        assert_eq!(t.num_real, 4);
        assert!(t.padding_source.is_empty());
        let deg = |i: usize| t.edges.iter().filter(|e| e.contains(&(i as u32))).count();
        for i in 0..4 {
            let nb = &t.row(i)[18..];
            let nonzero = nb.chunks(3).filter(|c| c.iter().any(|&x| x != 0.0)).count();
            // The neighbour at the origin is all zeros too; count it by degree instead.
            assert!(nonzero <= deg(i));
            assert!(nb[3 * deg(i)..].iter().all(|&x| x == 0.0));
        }
        let pc = Mesh::from_points(vec![Vec3::ZERO, Vec3::ONE]);
        let t = build_tokens(&pc, &cfg, 3).unwrap();
        assert!(t.edges.is_empty());
        assert!(t.normals.iter().all(|&n| n == Vec3::Z));
    }

    #[test]
    fn errors() {
        let cfg = TokenConfig {
            num_vertices: 16,
            max_degree: 8,
            num_freqs: 4,
        };
        assert_eq!(
            build_tokens(&Mesh::default(), &cfg, 0),
            Err(TokenError::Empty)
        );
        assert!(matches!(
            build_tokens(&icosphere(1), &cfg, 0),
            Err(TokenError::TooManyVertices {
                vertices: 42,
                capacity: 16
            })
        ));
        let bad = Mesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![[0, 1, 3]]);
        assert!(matches!(
            build_tokens(&bad, &cfg, 0),
            Err(TokenError::InvalidMesh(MeshError::IndexOutOfRange {
                index: 3,
                ..
            }))
        ));
        let mut m = octahedron();
        m.normals = vec![Vec3::Z];
        assert!(matches!(
            build_tokens(&m, &cfg, 0),
            Err(TokenError::InvalidMesh(MeshError::NormalCount { .. }))
        ));
    }

    #[test]
    fn padding_is_seeded() {
        let cfg = TokenConfig {
            num_vertices: 64,
            max_degree: 8,
            num_freqs: 4,
        };
        let m = icosphere(1);
        let a = build_tokens(&m, &cfg, 5).unwrap();
        assert_eq!(a, build_tokens(&m, &cfg, 5).unwrap());
        assert_ne!(
            a.padding_source,
            build_tokens(&m, &cfg, 6).unwrap().padding_source
        );
    }
}
