//! MeshVAE: a mesh of N vertex tokens becomes N/r continuous latent tokens and comes back as
//! per-vertex mask logits, positions, normals and edge embeddings.
//!
//! Paper: "MeshFlow: Efficient Artistic Mesh Generation via MeshVAE and Flow-based Diffusion
//! Transformer" (CVPR 2026). Layout and conventions: docs/design.md section 2; parameter names are
//! the reference state-dict names (golden `vae_small`).
//!
//! ```text
//! x [B,N,C] -> proj_in -> TokenMerge(r) -> cross-attn(queries = merged, context = all N)
//!   -> L_e self-attn blocks -> LayerNorm -> pre_kl -> [mean | logvar] -> z [B,N/r,D]
//! z -> post_kl -> L_d self-attn blocks -> TokenSplit(r) -> cross-attn(context = latents)
//!   -> L_v self-attn blocks over the N vertex tokens (0 in the reference layout)
//!   -> LayerNorm -> heads: mask (1), vertex (3), normal (3, tanh), edge embedding (E)
//! ```

use burn::module::Module;
use burn::nn::{LayerNorm, Linear};
use burn::tensor::activation::{leaky_relu, tanh};
use burn::tensor::{Device, Tensor, TensorData};
use serde::{Deserialize, Serialize};

use super::layers::{CrossAttentionBlock, SelfAttentionBlock, layer_norm, linear};
use crate::model::tokens::{TokenConfig, embed_dim};

/// Size of a MeshVAE. Stored as JSON beside the weights.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VaeConfig {
    /// N: vertex tokens per mesh (real + padding).
    pub num_vertices: usize,
    /// N / r latent tokens.
    pub num_latents: usize,
    /// Channels per latent token.
    pub latent_dim: usize,
    pub width_encoder: usize,
    pub width_decoder: usize,
    pub num_heads: usize,
    pub num_layers_encoder: usize,
    pub num_layers_decoder: usize,
    /// Neighbour slots per token in the encoder input.
    pub max_degree: usize,
    /// Fourier frequencies per coordinate.
    pub num_freqs: usize,
    /// Edge-embedding channels (half space, half time).
    pub edge_dim: usize,
    /// Spacetime threshold: an edge iff d > tau.
    pub tau: f32,
    /// Pad each mesh to the smallest of N/8, N/4, N/2 and N vertex slots that holds it
    /// (N/(8r) ... N/r latents), in training and at inference alike, instead of always to N.
    /// Nothing in the model depends on the token count, and every product in it scales with
    /// it, so a 60-vertex mesh costs 64 slots, not 512. Off in the reference layout.
    #[serde(default)]
    pub length_buckets: bool,
    /// L_v: self-attention blocks over the N decoded vertex tokens, between the decoder's
    /// cross-attention and its heads. Not in the paper: there each vertex's edge embedding is
    /// computed from the latents alone, without seeing the other vertices it must be joined
    /// to or kept apart from. Each block starts as the identity (zero output projections,
    /// [`crate::model::seeded_init`]), so a trained decoder that gains one decodes exactly as
    /// before until it is trained. 0 (the reference layout) is left out of the JSON.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub num_layers_vertex: usize,
    /// Hidden width of the pair head (0, the reference layout, left out of the JSON: none).
    /// Not in the paper: there a pair's score is the spacetime distance of two embeddings
    /// each decoded on its own. The pair head rescores each vertex's
    /// [`PAIR_CANDIDATES`] highest-scoring partners from both vertices' decoder features
    /// ([`MeshVae::pair_corrections`]), adding a learned correction to their distance. Its
    /// output layer starts at zero, so a trained decoder that gains one scores exactly as
    /// before until it is trained.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub pair_head: usize,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

/// The smallest length bucket (vertex slots) of a model of 512 vertices or more.
pub const SMALLEST_BUCKET: usize = 64;

impl VaeConfig {
    /// The golden `vae_small` configuration.
    pub fn vae_small() -> Self {
        Self {
            num_vertices: 64,
            num_latents: 16,
            latent_dim: 8,
            width_encoder: 64,
            width_decoder: 64,
            num_heads: 4,
            num_layers_encoder: 2,
            num_layers_decoder: 2,
            max_degree: 8,
            num_freqs: 16,
            edge_dim: 32,
            tau: 0.6,
            length_buckets: false,
            num_layers_vertex: 0,
            pair_head: 0,
        }
    }

    /// Merge ratio r = N / num_latents.
    pub fn merge_ratio(&self) -> usize {
        self.num_vertices / self.num_latents
    }

    /// The token layout the encoder expects at full length (N slots).
    pub fn tokens(&self) -> TokenConfig {
        TokenConfig {
            num_vertices: self.num_vertices,
            max_degree: self.max_degree,
            num_freqs: self.num_freqs,
        }
    }

    /// Vertex slots for a mesh of `vertices` vertices: N, or with
    /// [`length_buckets`](Self::length_buckets) the smallest power-of-two bucket from
    /// min(N/8, 64) up that holds it (each a multiple of the merge ratio; a bucket that is not
    /// is skipped). The smallest bucket stays 64 as N grows, so raising the capacity leaves a
    /// small mesh's padding, and so its result, as it was.
    pub fn slots_for(&self, vertices: usize) -> usize {
        if self.length_buckets {
            let r = self.merge_ratio().max(1);
            let mut slots = (self.num_vertices / 8).min(SMALLEST_BUCKET);
            while slots > 0 && slots < self.num_vertices {
                if slots >= r && slots.is_multiple_of(r) && vertices <= slots {
                    return slots;
                }
                slots *= 2;
            }
        }
        self.num_vertices
    }

    /// The token layout for a mesh of `vertices` vertices ([`Self::slots_for`] slots).
    pub fn tokens_for(&self, vertices: usize) -> TokenConfig {
        TokenConfig {
            num_vertices: self.slots_for(vertices),
            ..self.tokens()
        }
    }

    /// Encoder input channels: two Fourier blocks and the neighbour block.
    pub fn in_channels(&self) -> usize {
        2 * embed_dim(self.num_freqs) + 3 * self.max_degree
    }

    /// Multiply-add FLOPs (2 per multiply-add) of the matrix products in one forward pass of
    /// one mesh padded to `slots` vertex slots (N, or its length bucket): every Linear, the
    /// attention scores and weighted sums, and the Gram matrices of the pairwise spacetime
    /// distances. Elementwise work (norms, activations, softmax, the losses) is left out, so
    /// FLOP/s figures from this are matrix-product throughput.
    pub fn forward_flops(&self, slots: usize) -> f64 {
        let r = self.merge_ratio() as f64;
        let (n, l) = (slots as f64, slots as f64 / r);
        let (we, wd) = (self.width_encoder as f64, self.width_decoder as f64);
        let (c, d, e) = (
            self.in_channels() as f64,
            self.latent_dim as f64,
            self.edge_dim as f64,
        );
        let linear = |rows: f64, k: f64, m: f64| 2.0 * rows * k * m;
        // q, k, v, out projections plus scores and weighted sums, then the 4x feed-forward.
        let attention = |lq: f64, lk: f64, w: f64| {
            linear(lq, w, w) * 2.0 + linear(lk, w, w) * 2.0 + 4.0 * lq * lk * w
        };
        let block = |lq: f64, lk: f64, w: f64| attention(lq, lk, w) + linear(lq, w, 4.0 * w) * 2.0;
        let encoder = linear(n, c, we)
            + linear(l, r * we, we)
            + block(l, n, we)
            + self.num_layers_encoder as f64 * block(l, l, we)
            + linear(l, we, 2.0 * d);
        let heads = linear(n, wd, wd / 2.0) * 4.0 + linear(n, wd / 2.0, 7.0 + e);
        let decoder = linear(l, d, wd)
            + self.num_layers_decoder as f64 * block(l, l, wd)
            + linear(n, wd / r, wd)
            + block(n, l, wd)
            + self.num_layers_vertex as f64 * block(n, n, wd)
            + heads;
        let distances = 2.0 * n * n * e;
        // The pair head on each vertex's candidates (none when pair_head is 0).
        let (hp, input) = (self.pair_head as f64, 2.0 * wd + 1.0 + PAIR_CONTEXT as f64);
        let pairs = n * PAIR_CANDIDATES as f64 * (linear(1.0, input, hp) + linear(1.0, hp, 1.0));
        encoder + decoder + distances + pairs
    }

    /// Whether `other` encodes meshes with the same encoder shapes: every size the encoder and
    /// the pre-KL projection read is equal, whatever the decoder's width, depth, edge
    /// channels and threshold. A decoder-only run may change those and keep the encoder.
    pub fn same_encoder(&self, other: &VaeConfig) -> bool {
        let decoder_free = |c: &VaeConfig| VaeConfig {
            width_decoder: 0,
            num_layers_decoder: 0,
            num_layers_vertex: 0,
            edge_dim: 0,
            pair_head: 0,
            tau: 0.0,
            ..c.capacity_free()
        };
        decoder_free(self) == decoder_free(other)
    }

    /// Whether a decoder-only run of this configuration starts from `other`'s whole trained
    /// decoder: the same shapes, with as many vertex blocks ([`Self::num_layers_vertex`]) or
    /// more (added ones start as the identity), as many edge-embedding channels or more
    /// (added ones start nearly silent, [`widen_edge_embeddings`]), and the same pair head or
    /// a new one where it had none (it starts silent). The threshold and the capacity
    /// ([`Self::same_shapes`]) may differ: they are not shapes.
    pub fn continues_decoder_of(&self, other: &VaeConfig) -> bool {
        self.num_layers_vertex >= other.num_layers_vertex
            && self.edge_dim >= other.edge_dim
            && (other.pair_head == 0 || other.pair_head == self.pair_head)
            && VaeConfig {
                num_layers_vertex: other.num_layers_vertex,
                edge_dim: other.edge_dim,
                pair_head: other.pair_head,
                tau: other.tau,
                ..self.capacity_free()
            } == other.capacity_free()
    }

    /// Whether `other`'s weights load into this configuration and mean the same: equal but
    /// for the capacity (`num_vertices`, `num_latents` at the same merge ratio), which no
    /// weight depends on (no positional embedding; TokenMerge acts on runs of r tokens), and
    /// the threshold (a trained model's is its extraction threshold, a training
    /// configuration's its loss margin). A model trained at 512 vertices runs, and continues
    /// training, at 2,048.
    pub fn same_shapes(&self, other: &VaeConfig) -> bool {
        let untuned = |c: &VaeConfig| VaeConfig {
            tau: 0.0,
            ..c.capacity_free()
        };
        untuned(self) == untuned(other)
    }

    /// This configuration with the capacity taken out (the merge ratio kept).
    fn capacity_free(&self) -> VaeConfig {
        VaeConfig {
            num_vertices: self.merge_ratio(),
            num_latents: 1,
            ..self.clone()
        }
    }

    /// Checks the sizes fit together; the message names the offending field.
    pub fn validate(&self) -> Result<(), String> {
        let positive = [
            ("num_vertices", self.num_vertices),
            ("num_latents", self.num_latents),
            ("latent_dim", self.latent_dim),
            ("width_encoder", self.width_encoder),
            ("width_decoder", self.width_decoder),
            ("num_heads", self.num_heads),
            ("edge_dim", self.edge_dim),
        ];
        if let Some((name, _)) = positive.iter().find(|(_, v)| *v == 0) {
            return Err(format!("{name} must be positive"));
        }
        if !self.num_vertices.is_multiple_of(self.num_latents) {
            return Err("num_vertices must be a multiple of num_latents".into());
        }
        let r = self.merge_ratio();
        for (name, w) in [
            ("width_encoder", self.width_encoder),
            ("width_decoder", self.width_decoder),
        ] {
            if !w.is_multiple_of(self.num_heads) {
                return Err(format!("{name} must be a multiple of num_heads"));
            }
        }
        if !self.width_decoder.is_multiple_of(r) {
            return Err("width_decoder must be a multiple of the merge ratio".into());
        }
        if !self.edge_dim.is_multiple_of(2) {
            return Err("edge_dim must be even (space | time halves)".into());
        }
        if !(self.tau.is_finite()) {
            return Err("tau must be finite".into());
        }
        Ok(())
    }
}

/// Linear . LeakyReLU(0.01) . Linear: one decoder output head.
#[derive(Module, Debug)]
pub struct Head {
    /// Reference name `0`.
    pub hidden: Linear,
    /// Reference name `2`.
    pub output: Linear,
}

impl Head {
    fn new(width: usize, out: usize, device: &Device) -> Self {
        Self::with_hidden(width, width / 2, out, device)
    }

    fn with_hidden(width: usize, hidden: usize, out: usize, device: &Device) -> Self {
        Self {
            hidden: linear(width, hidden, true, device),
            output: linear(hidden, out, true, device),
        }
    }

    fn forward(&self, x: Tensor<3>) -> Tensor<3> {
        self.output
            .forward(leaky_relu(self.hidden.forward(x), 0.01))
    }

    /// The head over pairs of rows of `vertices` (`[V, W]`), `(i[p], j[p])`, each with its
    /// `extra` row (`[P, E]`): the head's value at `[v_i + v_j, v_i * v_j, extra]` (hidden
    /// width `2W + E`), as `[P]`. That input is never built: the hidden layer is linear, so
    /// its part for `v_i + v_j` is each vertex's own projection gathered twice, and only the
    /// product needs a `[P, W]` tensor. Per pair this reads `W` instead of `2W + E` columns and
    /// writes none, where building the input cost more than the head (issue 15 item 8).
    fn forward_pairs(
        &self,
        vertices: Tensor<2>,
        i: Tensor<1, burn::tensor::Int>,
        j: Tensor<1, burn::tensor::Int>,
        extra: Tensor<2>,
    ) -> Tensor<1> {
        let [_, w] = vertices.dims();
        let [p, e] = extra.dims();
        // Burn's Linear weight is `[in, out]`: rows 0..W take the sum, W..2W the product.
        let weight = self.hidden.weight.val();
        let own = vertices.clone().matmul(weight.clone().narrow(0, 0, w));
        let mut hidden = own.clone().select(0, i.clone())
            + own.select(0, j.clone())
            + (vertices.clone().select(0, i) * vertices.select(0, j))
                .matmul(weight.clone().narrow(0, w, w))
            + extra.matmul(weight.narrow(0, 2 * w, e));
        if let Some(bias) = &self.hidden.bias {
            hidden = hidden + bias.val().unsqueeze_dim(0);
        }
        self.output.forward(leaky_relu(hidden, 0.01)).reshape([p])
    }
}

#[derive(Module, Debug)]
pub struct Encoder {
    pub proj_in: Linear,
    /// TokenMerge: r consecutive tokens concatenated, mapped to one.
    pub downsample_mlp: Linear,
    pub cross_attn_block: CrossAttentionBlock,
    pub blocks: Vec<SelfAttentionBlock>,
    pub norm_out: LayerNorm,
}

#[derive(Module, Debug)]
pub struct Decoder {
    pub blocks: Vec<SelfAttentionBlock>,
    /// TokenSplit: each latent's channels cut into r chunks, each mapped to one token.
    pub upsample_mlp: Linear,
    pub cross_attn_block: CrossAttentionBlock,
    /// Self-attention over the vertex tokens ([`VaeConfig::num_layers_vertex`]).
    pub vertex_blocks: Vec<SelfAttentionBlock>,
    pub norm_out: LayerNorm,
    pub mask_head: Head,
    pub verts_head: Head,
    pub verts_normal_head: Head,
    pub adjacency_head: Head,
    /// [`VaeConfig::pair_head`]: `[h_i + h_j | h_i * h_j | d_ij | context]` to a correction of
    /// d_ij ([`pair_context`]).
    pub pair_head: Option<Head>,
}

/// The MeshVAE. Build with [`MeshVae::new`]; load weights with
/// [`crate::pipeline::shipped::load_vae`].
#[derive(Module, Debug)]
pub struct MeshVae {
    pub encoder: Encoder,
    /// Linear(width_encoder, 2 latent_dim) = [mean | logvar].
    pub pre_kl: Linear,
    /// Linear(latent_dim, width_decoder).
    pub post_kl: Linear,
    pub decoder: Decoder,
    /// Merge ratio r.
    pub ratio: usize,
}

/// The encoder's posterior over latents.
#[derive(Clone, Debug)]
pub struct Posterior {
    /// `[B, N/r, D]`.
    pub mean: Tensor<3>,
    /// `[B, N/r, D]`, clamped to [-30, 20].
    pub logvar: Tensor<3>,
}

/// Decoder outputs, per vertex token.
#[derive(Clone, Debug)]
pub struct Decoded {
    /// `[B, N, 1]` logits: a real vertex iff > 0.
    pub mask_logits: Tensor<3>,
    /// `[B, N, 3]`.
    pub positions: Tensor<3>,
    /// `[B, N, 3]`, in (-1, 1) by tanh.
    pub normals: Tensor<3>,
    /// `[B, N, edge_dim]`.
    pub edge_embeddings: Tensor<3>,
    /// `[B, N, width_decoder]`: the normalised vertex features every head reads (the pair
    /// head reads two of them).
    pub features: Tensor<3>,
}

/// Named intermediate tensors, recorded only when enabled (the golden test compares them).
#[derive(Default)]
pub struct Trace {
    pub enabled: bool,
    pub tensors: Vec<(String, Tensor<3>)>,
}

impl Trace {
    /// A trace that records.
    pub fn recording() -> Self {
        Self {
            enabled: true,
            tensors: Vec::new(),
        }
    }

    pub fn record(&mut self, name: &str, t: &Tensor<3>) {
        if self.enabled {
            self.tensors.push((name.to_string(), t.clone()));
        }
    }
}

impl MeshVae {
    /// A randomly initialised VAE of the given size.
    pub fn new(cfg: &VaeConfig, device: &Device) -> Self {
        let (we, wd, r) = (cfg.width_encoder, cfg.width_decoder, cfg.merge_ratio());
        let encoder = Encoder {
            proj_in: linear(cfg.in_channels(), we, true, device),
            downsample_mlp: linear(r * we, we, true, device),
            cross_attn_block: CrossAttentionBlock::new(we, cfg.num_heads, device),
            blocks: (0..cfg.num_layers_encoder)
                .map(|_| SelfAttentionBlock::new(we, cfg.num_heads, device))
                .collect(),
            norm_out: layer_norm(we, device),
        };
        let decoder = Decoder {
            blocks: (0..cfg.num_layers_decoder)
                .map(|_| SelfAttentionBlock::new(wd, cfg.num_heads, device))
                .collect(),
            upsample_mlp: linear(wd / r, wd, true, device),
            cross_attn_block: CrossAttentionBlock::new(wd, cfg.num_heads, device),
            vertex_blocks: (0..cfg.num_layers_vertex)
                .map(|_| SelfAttentionBlock::new(wd, cfg.num_heads, device))
                .collect(),
            norm_out: layer_norm(wd, device),
            mask_head: Head::new(wd, 1, device),
            verts_head: Head::new(wd, 3, device),
            verts_normal_head: Head::new(wd, 3, device),
            adjacency_head: Head::new(wd, cfg.edge_dim, device),
            pair_head: (cfg.pair_head > 0)
                .then(|| Head::with_hidden(2 * wd + 1 + PAIR_CONTEXT, cfg.pair_head, 1, device)),
        };
        Self {
            encoder,
            pre_kl: linear(we, 2 * cfg.latent_dim, true, device),
            post_kl: linear(cfg.latent_dim, wd, true, device),
            decoder,
            ratio: r,
        }
    }

    /// Encoder input features `[B, N, C]` (from [`crate::model::tokens::build_tokens`]) to the
    /// posterior.
    pub fn encode(&self, x: Tensor<3>, trace: &mut Trace) -> Posterior {
        let e = &self.encoder;
        let [b, n, _] = x.dims();
        let tokens = e.proj_in.forward(x);
        trace.record("encoder.proj_in", &tokens);
        let w = tokens.dims()[2];
        let merged =
            e.downsample_mlp
                .forward(tokens.clone().reshape([b, n / self.ratio, self.ratio * w]));
        trace.record("encoder.downsample_mlp", &merged);
        let mut h = e.cross_attn_block.forward(merged, tokens);
        trace.record("encoder.cross_attn_block", &h);
        for (i, block) in e.blocks.iter().enumerate() {
            h = block.forward(h);
            trace.record(&format!("encoder.blocks.{i}"), &h);
        }
        let h = e.norm_out.forward(h);
        let moments = self.pre_kl.forward(h);
        let d = moments.dims()[2] / 2;
        let mean = moments.clone().narrow(2, 0, d);
        let logvar = moments.narrow(2, d, d).clamp(-30.0, 20.0);
        Posterior { mean, logvar }
    }

    /// The score of every pair of decoded vertices, read back as `[B, N, N]` row-major: the
    /// spacetime distances of the edge embeddings, refined by the pair head (if any) from the
    /// vertex `features` at the candidates among each mesh's real vertex slots `real[b]`
    /// ([`pair_candidates`]), the corrections added on the host ([`add_pair_corrections`]).
    /// Both tensors as [`MeshVae::decode`] gives them. Reads back synchronously; the error is
    /// the readback's message.
    pub fn edge_distances(
        &self,
        edge_embeddings: Tensor<3>,
        features: Tensor<3>,
        real: &[Vec<u32>],
    ) -> Result<Vec<f32>, String> {
        let distances = spacetime_distances(edge_embeddings);
        let n = distances.dims()[1];
        let mut host = read_f32(distances.clone())?;
        if let Some(pairs) = self.pair_corrections(distances, &host, features, real) {
            let corrections = read_f32(pairs.corrections)?;
            add_pair_corrections(&mut host, n, &pairs.pairs, &corrections);
        }
        Ok(host)
    }

    /// [`Self::pair_corrections`], reading `distances` back synchronously for the candidates
    /// (training, where the corrections stay on the device for the loss).
    pub fn read_pair_corrections(
        &self,
        distances: Tensor<3>,
        features: Tensor<3>,
        real: &[Vec<u32>],
    ) -> Option<PairCorrections> {
        self.decoder.pair_head.as_ref()?;
        let host = read_f32(distances.clone()).expect("f32 distances");
        self.pair_corrections(distances, &host, features, real)
    }

    /// The pair head's corrections to the spacetime distances `distances` (`[B, N, N]`, from
    /// [`spacetime_distances`]; `host` is the same read back) at the candidates
    /// ([`pair_candidates`], with their [`pair_context`]) among the `real` slots of each mesh,
    /// from the decoder's `features` ([`Decoded::features`]). `None` without a pair head or
    /// without candidates.
    pub fn pair_corrections(
        &self,
        distances: Tensor<3>,
        host: &[f32],
        features: Tensor<3>,
        real: &[Vec<u32>],
    ) -> Option<PairCorrections> {
        let head = self.decoder.pair_head.as_ref()?;
        let n = distances.dims()[1];
        let pairs = pair_candidates(host, n, real);
        if pairs.is_empty() {
            return None;
        }
        let context = pair_context(host, n, &pairs);
        let [b, _, w] = features.dims();
        let device = features.device();
        let index = |f: &dyn Fn(&[u32; 3]) -> usize| {
            let values: Vec<i64> = pairs.iter().map(|p| f(p) as i64).collect();
            Tensor::<1, burn::tensor::Int>::from_data(
                TensorData::new(values, [pairs.len()]),
                &device,
            )
        };
        let at = index(&|&[k, i, j]| (k as usize * n + i as usize) * n + j as usize);
        let d = distances.reshape([b * n * n]).select(0, at.clone());
        let context = Tensor::<2>::from_data(
            TensorData::new(
                context.iter().flatten().copied().collect::<Vec<f32>>(),
                [pairs.len(), PAIR_CONTEXT],
            ),
            &device,
        );
        let corrections = head.forward_pairs(
            features.reshape([b * n, w]),
            index(&|&[k, i, _]| k as usize * n + i as usize),
            index(&|&[k, _, j]| k as usize * n + j as usize),
            Tensor::cat(vec![d.clone().reshape([pairs.len(), 1]), context], 1),
        );
        Some(PairCorrections {
            pairs,
            index: at,
            distances: d,
            corrections,
        })
    }

    /// Latents `[B, N/r, D]` to per-vertex outputs.
    pub fn decode(&self, z: Tensor<3>, trace: &mut Trace) -> Decoded {
        let d = &self.decoder;
        let mut h = self.post_kl.forward(z);
        trace.record("post_kl", &h);
        for (i, block) in d.blocks.iter().enumerate() {
            h = block.forward(h);
            trace.record(&format!("decoder.blocks.{i}"), &h);
        }
        let [b, m, w] = h.dims();
        // Chunk j of latent i becomes token r*i + j.
        let split = d
            .upsample_mlp
            .forward(h.clone().reshape([b, m * self.ratio, w / self.ratio]));
        trace.record("decoder.upsample_mlp", &split);
        let mut x = d.cross_attn_block.forward(split, h);
        trace.record("decoder.cross_attn_block", &x);
        for (i, block) in d.vertex_blocks.iter().enumerate() {
            x = block.forward(x);
            trace.record(&format!("decoder.vertex_blocks.{i}"), &x);
        }
        let x = d.norm_out.forward(x);
        trace.record("decoder.norm_out", &x);
        Decoded {
            mask_logits: d.mask_head.forward(x.clone()),
            positions: d.verts_head.forward(x.clone()),
            normals: tanh(d.verts_normal_head.forward(x.clone())),
            edge_embeddings: d.adjacency_head.forward(x.clone()),
            features: x,
        }
    }
}

/// A tensor read back as f32 values; the error is the readback's message.
fn read_f32<const D: usize>(t: Tensor<D>) -> Result<Vec<f32>, String> {
    t.try_into_data()
        .map_err(|e| e.to_string())?
        .convert::<f32>()
        .try_into_vec::<f32>()
        .map_err(|e| format!("{e:?}"))
}

/// How many partners of each real vertex the pair head rescores: its highest-scoring ones.
/// Ground-truth meshes here have about six neighbours a vertex; the confusions the pair head
/// is for (a quad's other diagonal, two hops, the other side of a thin part) rank just below.
pub const PAIR_CANDIDATES: usize = 16;

/// What a pair head adds at a batch's candidate pairs ([`MeshVae::pair_corrections`]).
pub struct PairCorrections {
    /// The candidates, `(b, i, j)` with `i < j`, sorted ([`pair_candidates`]).
    pub pairs: Vec<[u32; 3]>,
    /// `[P]`: each candidate's flat index into `[B, N, N]`, `(b N + i) N + j`.
    pub index: Tensor<1, burn::tensor::Int>,
    /// `[P]`: the spacetime distance of each candidate, as the head read it.
    pub distances: Tensor<1>,
    /// `[P]`: the head's correction to add to it.
    pub corrections: Tensor<1>,
}

/// Adds a pair head's `corrections` (read back from [`PairCorrections::corrections`]) to
/// `distances` (`[B, n, n]` row-major, read back) at their `pairs`: the refined scores
/// [`MeshVae::edge_distances`] gives, for callers that read back asynchronously.
pub fn add_pair_corrections(
    distances: &mut [f32],
    n: usize,
    pairs: &[[u32; 3]],
    corrections: &[f32],
) {
    for (&[b, i, j], &c) in pairs.iter().zip(corrections) {
        distances[(b as usize * n + i as usize) * n + j as usize] += c;
    }
}

/// The pairs a pair head rescores in a batch of spacetime distances (`distances`, `[B, n, n]`
/// row-major): for mesh `b` and each of its real vertex slots `i` (`real[b]`, slots below
/// `n`), its [`PAIR_CANDIDATES`] highest-scoring real partners. Each pair once, as `(b, i, j)`
/// with `i < j`, sorted.
pub fn pair_candidates(distances: &[f32], n: usize, real: &[Vec<u32>]) -> Vec<[u32; 3]> {
    // Meshes are independent; each one's list comes out sorted, so their concatenation is.
    let meshes: Vec<&Vec<u32>> = real.iter().collect();
    crate::parallel::map_in_parallel(meshes, |b, slots| {
        mesh_pair_candidates(&distances[b * n * n..(b + 1) * n * n], n, b as u32, slots)
    })
    .concat()
}

/// [`pair_candidates`] of mesh `b`, whose distances are `plane` (`[n, n]`).
fn mesh_pair_candidates(plane: &[f32], n: usize, b: u32, slots: &[u32]) -> Vec<[u32; 3]> {
    let mut pairs = Vec::with_capacity(slots.len() * PAIR_CANDIDATES);
    let mut row: Vec<(f32, usize)> = Vec::with_capacity(n);
    for &i in slots {
        let i = i as usize;
        row.clear();
        // Read the upper triangle, so a pair has one score whatever its order.
        row.extend(
            slots
                .iter()
                .map(|&j| j as usize)
                .filter(|&j| j != i)
                .map(|j| {
                    let (a, c) = (i.min(j), i.max(j));
                    (plane[a * n + c], j)
                }),
        );
        let k = PAIR_CANDIDATES.min(row.len());
        if k < row.len() {
            row.select_nth_unstable_by(k, |x, y| y.0.total_cmp(&x.0));
        }
        for &(_, j) in &row[..k] {
            pairs.push([b, i.min(j) as u32, i.max(j) as u32]);
        }
    }
    pairs.sort_unstable();
    pairs.dedup();
    pairs
}

/// What a pair head reads about a candidate's neighbourhood besides the two vertices' features
/// ([`pair_context`]).
pub const PAIR_CONTEXT: usize = 2;

/// The range [`pair_context`] clamps to: well past the thresholds the decoders here are
/// extracted at (-3 to 1).
pub const PAIR_CONTEXT_RANGE: f32 = 10.0;

/// Where each candidate pair `(b, i, j)` of [`pair_candidates`] stands among the candidates of
/// both its vertices, from the distances `distances` (`[B, n, n]`, upper triangle read), as
/// `[triangle, rival]`:
/// - triangle: the best `min(d_ik, d_kj)` over the vertices `k` that are candidates of both
///   `i` and `j`: how strongly `(i, j)` would close a triangle;
/// - rival: the best `min(d_ik, d_kj, d_il, d_lj, d_kl)` over two such vertices `k, l`: the
///   strongest quad `i-k-j-l` whose other diagonal `(k, l)` competes with `(i, j)`. A
///   quad's artist-drawn diagonal and the one left out look alike to a score of the pair
///   alone (docs/experiments/2026-11-28-edge-f1-limit.md).
///
/// Both are clamped to `[-PAIR_CONTEXT_RANGE, PAIR_CONTEXT_RANGE]`; the lower end also
/// stands for "no such vertex".
pub fn pair_context(distances: &[f32], n: usize, pairs: &[[u32; 3]]) -> Vec<[f32; 2]> {
    // Each vertex's candidate partners, sorted, at `b n + i`.
    let slot = |b: u32, i: u32| b as usize * n + i as usize;
    let mut partners: Vec<Vec<u32>> = vec![Vec::new(); distances.len() / (n * n).max(1) * n];
    for &[b, i, j] in pairs {
        partners[slot(b, i)].push(j);
        partners[slot(b, j)].push(i);
    }
    for list in &mut partners {
        list.sort_unstable();
    }
    let floor = -PAIR_CONTEXT_RANGE;
    // Each pair's context is independent of the others': contiguous chunks on the threads.
    let chunk = pairs.len().div_ceil(CONTEXT_CHUNKS).max(1);
    let chunks: Vec<&[[u32; 3]]> = pairs.chunks(chunk).collect();
    let partners = &partners;
    crate::parallel::map_in_parallel(chunks, |_, chunk| {
        let mut common: Vec<(u32, f32)> = Vec::new();
        chunk
            .iter()
            .map(|&[b, i, j]| {
                let plane = &distances[b as usize * n * n..(b as usize + 1) * n * n];
                let d = |a: u32, c: u32| plane[a.min(c) as usize * n + a.max(c) as usize];
                let (pi, pj) = (&partners[slot(b, i)], &partners[slot(b, j)]);
                // The shared partners k, each with its weaker side min(d_ik, d_kj).
                common.clear();
                let (mut x, mut y) = (0, 0);
                while x < pi.len() && y < pj.len() {
                    match pi[x].cmp(&pj[y]) {
                        std::cmp::Ordering::Less => x += 1,
                        std::cmp::Ordering::Greater => y += 1,
                        std::cmp::Ordering::Equal => {
                            let k = pi[x];
                            common.push((k, d(i, k).min(d(k, j))));
                            x += 1;
                            y += 1;
                        }
                    }
                }
                let triangle = common.iter().map(|c| c.1).fold(floor, f32::max);
                let mut rival = floor;
                for (a, &(k, side_k)) in common.iter().enumerate() {
                    for &(l, side_l) in &common[a + 1..] {
                        rival = rival.max(side_k.min(side_l).min(d(k, l)));
                    }
                }
                [
                    triangle.clamp(floor, PAIR_CONTEXT_RANGE),
                    rival.clamp(floor, PAIR_CONTEXT_RANGE),
                ]
            })
            .collect::<Vec<_>>()
    })
    .concat()
}

/// How many pieces [`pair_context`] cuts its pairs into for the threads: a few per core, so
/// that pieces of unequal cost still share out evenly.
const CONTEXT_CHUNKS: usize = 8;

/// The adjacency head's output layer, reference names (`[out, in]` weight and `[out]` bias).
const EDGE_OUTPUT_WEIGHT: &str = "decoder.adjacency_head.2.weight";
const EDGE_OUTPUT_BIAS: &str = "decoder.adjacency_head.2.bias";

/// Widens trained VAE weights (`map`, reference names) from `from` to `to` edge-embedding
/// channels, both even, so that a decoder-only run can continue them with a more expressive
/// pair score. The spacetime layout is kept: the old space channels stay the first of the new
/// space half and the old time channels the first of the new time half. The added output rows
/// are drawn from a normal distribution with `scale` times the old rows' standard deviation
/// (seeded by `seed`) and their biases are 0: exactly 0 would leave them without a gradient
/// (a pair's distance in a channel where every vertex sits at the same point does not move),
/// while a small scale leaves every spacetime distance close to the trained one.
pub fn widen_edge_embeddings(
    map: &mut crate::model::weights::TensorMap,
    from: usize,
    to: usize,
    scale: f32,
    seed: u64,
) -> Result<(), String> {
    if !from.is_multiple_of(2) || !to.is_multiple_of(2) || to < from {
        return Err(format!(
            "edge_dim can only grow between even sizes (from {from} to {to})"
        ));
    }
    let (w_shape, weight) = map
        .tensors
        .get(EDGE_OUTPUT_WEIGHT)
        .cloned()
        .ok_or_else(|| format!("{EDGE_OUTPUT_WEIGHT} is missing"))?;
    let (b_shape, bias) = map
        .tensors
        .get(EDGE_OUTPUT_BIAS)
        .cloned()
        .ok_or_else(|| format!("{EDGE_OUTPUT_BIAS} is missing"))?;
    if w_shape.len() != 2 || w_shape[0] != from || b_shape != [from] {
        return Err(format!(
            "{EDGE_OUTPUT_WEIGHT} is {w_shape:?} and {EDGE_OUTPUT_BIAS} {b_shape:?}; \
             expected [{from}, hidden] and [{from}]"
        ));
    }
    let hidden = w_shape[1];
    let n = weight.len() as f64;
    let mean = weight.iter().map(|&x| x as f64).sum::<f64>() / n;
    let std = (weight
        .iter()
        .map(|&x| (x as f64 - mean).powi(2))
        .sum::<f64>()
        / n)
        .sqrt();
    let mut rng = crate::rng::Rng::new(seed);
    let (half_from, half_to) = (from / 2, to / 2);
    let mut wide_weight = Vec::with_capacity(to * hidden);
    let mut wide_bias = Vec::with_capacity(to);
    for half in 0..2 {
        for row in 0..half_to {
            if row < half_from {
                let old = half * half_from + row;
                wide_weight.extend_from_slice(&weight[old * hidden..(old + 1) * hidden]);
                wide_bias.push(bias[old]);
            } else {
                wide_weight.extend((0..hidden).map(|_| (rng.normal() * std) as f32 * scale));
                wide_bias.push(0.0);
            }
        }
    }
    map.tensors
        .insert(EDGE_OUTPUT_WEIGHT.into(), (vec![to, hidden], wide_weight));
    map.tensors
        .insert(EDGE_OUTPUT_BIAS.into(), (vec![to], wide_bias));
    Ok(())
}

/// Spacetime distances `[B, N, N]` of edge embeddings `[B, N, E]`:
/// `|s_i - s_j|^2 - |t_i - t_j|^2`, s = first half, t = second half.
pub fn spacetime_distances(h: Tensor<3>) -> Tensor<3> {
    let e = h.dims()[2] / 2;
    let sq = |x: Tensor<3>| {
        let norms = x.clone().square().sum_dim(2); // [B, N, 1]
        let gram = x.clone().matmul(x.swap_dims(1, 2)); // [B, N, N]
        norms.clone() + norms.swap_dims(1, 2) - gram * 2.0
    };
    let s = h.clone().narrow(2, 0, e);
    let t = h.narrow(2, e, e);
    sq(s) - sq(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Only a configuration that adds vertex blocks or moves tau, and changes nothing else,
    /// starts from another's whole decoder; a reference-layout file keeps its JSON without the
    /// new field.
    #[test]
    fn only_added_vertex_blocks_or_another_tau_keep_the_trained_decoder() {
        let base = VaeConfig::vae_small();
        let grown = VaeConfig {
            num_layers_vertex: 2,
            ..base.clone()
        };
        assert!(grown.continues_decoder_of(&base));
        assert!(base.continues_decoder_of(&base));
        assert!(!base.continues_decoder_of(&grown));
        let other_tau = VaeConfig {
            tau: -2.5,
            ..grown.clone()
        };
        assert!(other_tau.continues_decoder_of(&base));
        let wider = VaeConfig {
            width_decoder: 128,
            ..grown.clone()
        };
        assert!(!wider.continues_decoder_of(&base));
        assert!(wider.same_encoder(&base));
        assert!(
            !serde_json::to_string(&base)
                .unwrap()
                .contains("num_layers_vertex")
        );
        let round: VaeConfig =
            serde_json::from_str(&serde_json::to_string(&grown).unwrap()).unwrap();
        assert_eq!(round, grown);
        assert!(grown.forward_flops(64) > base.forward_flops(64));
        let wider_edges = VaeConfig {
            edge_dim: 64,
            ..grown.clone()
        };
        assert!(wider_edges.continues_decoder_of(&base));
        assert!(!base.continues_decoder_of(&wider_edges));
    }

    /// The shipped layout (512 vertices, 128 latents, length buckets) raised to 2,048 keeps
    /// every bucket it had and adds 1,024 and 2,048; the two load each other's weights and
    /// continue each other's decoder, and another merge ratio or width does not.
    #[test]
    fn raising_the_capacity_keeps_the_small_buckets_and_the_shapes() {
        let shipped = VaeConfig {
            num_vertices: 512,
            num_latents: 128,
            length_buckets: true,
            ..VaeConfig::vae_small()
        };
        let raised = VaeConfig {
            num_vertices: 2048,
            num_latents: 512,
            ..shipped.clone()
        };
        let counts = [1, 64, 65, 128, 200, 256, 300, 512, 513, 1024, 1025, 2048];
        let slots = |c: &VaeConfig| counts.map(|n| c.slots_for(n));
        assert_eq!(
            slots(&shipped),
            [64, 64, 128, 128, 256, 256, 512, 512, 512, 512, 512, 512]
        );
        assert_eq!(
            slots(&raised),
            [64, 64, 128, 128, 256, 256, 512, 512, 1024, 1024, 2048, 2048]
        );
        assert!(raised.same_shapes(&shipped) && shipped.same_shapes(&raised));
        let trained = VaeConfig {
            tau: -2.5,
            ..shipped.clone()
        };
        assert!(raised.same_shapes(&trained));
        assert!(raised.same_encoder(&shipped));
        assert!(raised.continues_decoder_of(&shipped));
        let other_ratio = VaeConfig {
            num_latents: 256,
            ..raised.clone()
        };
        assert!(!other_ratio.same_shapes(&shipped));
        assert!(!other_ratio.same_encoder(&shipped));
        let wider = VaeConfig {
            width_encoder: shipped.width_encoder * 2,
            ..raised.clone()
        };
        assert!(!wider.same_shapes(&shipped));
    }

    /// Each real vertex's highest-scoring partners are candidates, each pair once and in order,
    /// and padding slots never are.
    #[test]
    fn pair_candidates_are_each_real_vertexs_best_partners() {
        let (n, real) = (24, [(0..20).collect::<Vec<u32>>(), vec![4, 9, 23]]);
        let mut rng = crate::rng::Rng::new(11);
        let mut distances = vec![0f32; 2 * n * n];
        for b in 0..2 {
            for i in 0..n {
                for j in i + 1..n {
                    let v = rng.normal() as f32;
                    distances[b * n * n + i * n + j] = v;
                    distances[b * n * n + j * n + i] = v;
                }
            }
        }
        let pairs = pair_candidates(&distances, n, &real);
        assert!(pairs.windows(2).all(|w| w[0] < w[1]));
        for &[b, i, j] in &pairs {
            assert!(i < j && real[b as usize].contains(&i) && real[b as usize].contains(&j));
        }
        for (b, slots) in real.iter().enumerate() {
            for &i in slots {
                let i = i as usize;
                let score = |j: usize| distances[b * n * n + i.min(j) * n + i.max(j)];
                let mut partners: Vec<usize> = slots
                    .iter()
                    .map(|&j| j as usize)
                    .filter(|&j| j != i)
                    .collect();
                partners.sort_by(|&x, &y| score(y).total_cmp(&score(x)));
                for &j in partners.iter().take(PAIR_CANDIDATES) {
                    let pair = [b as u32, i.min(j) as u32, i.max(j) as u32];
                    assert!(pairs.binary_search(&pair).is_ok(), "{pair:?} missing");
                }
            }
        }
        // Mesh 1 has 3 real vertices (not the first slots): its 3 pairs, no more.
        assert_eq!(pairs.iter().filter(|p| p[0] == 1).count(), 3);
    }

    /// A quad 0-1-2-3 with both diagonals scored: each diagonal's rival is the other one (as
    /// weak as the quad's weakest side allows), its triangle the quad's sides; a lone pair has
    /// neither.
    #[test]
    fn pair_context_sees_the_quads_other_diagonal() {
        let n = 6;
        let mut d = vec![-5f32; n * n];
        let mut set = |i: usize, j: usize, v: f32| d[i * n + j] = v;
        for (i, j) in [(0, 1), (1, 2), (2, 3), (0, 3)] {
            set(i, j, 2.0);
        }
        set(0, 2, 1.0);
        set(1, 3, 0.5);
        set(4, 5, 3.0);
        let pairs: Vec<[u32; 3]> = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3), (4, 5)]
            .iter()
            .map(|&(i, j)| [0, i, j])
            .collect();
        let context = pair_context(&d, n, &pairs);
        let of = |i: u32, j: u32| context[pairs.iter().position(|p| p[1..] == [i, j]).unwrap()];
        assert_eq!(of(0, 2), [2.0, 0.5]);
        assert_eq!(of(1, 3), [2.0, 1.0]);
        // A side: triangles through the diagonals (1.0 via vertex 2, 0.5 via vertex 3).
        assert_eq!(of(0, 1), [1.0, 0.5]);
        assert_eq!(of(4, 5), [-PAIR_CONTEXT_RANGE, -PAIR_CONTEXT_RANGE]);
    }

    /// The head over pairs without their input built gives what the head gives over the
    /// built input `[v_i + v_j, v_i * v_j, extra]`, up to float rounding.
    #[test]
    fn the_head_over_pairs_is_the_head_over_their_built_input() {
        let device = Device::flex();
        let (v, w, e, p) = (40, 12, 3, 200);
        let head = Head::with_hidden(2 * w + e, 8, 1, &device);
        let mut rng = crate::rng::Rng::new(3);
        let mut normal = |len: usize| (0..len).map(|_| rng.normal() as f32).collect::<Vec<f32>>();
        let vertices = Tensor::<2>::from_data(TensorData::new(normal(v * w), [v, w]), &device);
        let extra = Tensor::<2>::from_data(TensorData::new(normal(p * e), [p, e]), &device);
        let (i, j): (Vec<i64>, Vec<i64>) = (0..p as i64).map(|k| (k * 7 % 40, k * 13 % 39)).unzip();
        let index = |x: Vec<i64>| {
            Tensor::<1, burn::tensor::Int>::from_data(TensorData::new(x, [p]), &device)
        };
        let (i, j) = (index(i), index(j));
        let (h_i, h_j) = (
            vertices.clone().select(0, i.clone()),
            vertices.clone().select(0, j.clone()),
        );
        let built = Tensor::cat(vec![h_i.clone() + h_j.clone(), h_i * h_j, extra.clone()], 1);
        let values = |t: Tensor<1>| t.into_data().convert::<f32>().try_to_vec::<f32>().unwrap();
        let expected = values(head.forward(built.unsqueeze_dim(0)).reshape([p]));
        let got = values(head.forward_pairs(vertices, i, j, extra));
        let scale = expected.iter().fold(0f32, |m, x| m.max(x.abs()));
        assert!(
            scale > 0.1,
            "a head whose output is near zero tests nothing ({scale})"
        );
        for (k, (a, b)) in got.iter().zip(&expected).enumerate() {
            assert!((a - b).abs() <= 1e-5 * scale, "pair {k}: {a} against {b}");
        }
    }

    /// A new pair head changes nothing until trained; once its output layer is not zero it
    /// moves the candidates' distances and no other pair's.
    #[test]
    fn the_pair_head_starts_silent_and_rescores_only_candidates() {
        use crate::model::seeded_init;
        use crate::model::weights::{load_module, module_tensors};
        let device = Device::flex();
        let cfg = VaeConfig {
            pair_head: 16,
            ..VaeConfig::vae_small()
        };
        assert!(cfg.continues_decoder_of(&VaeConfig::vae_small()));
        assert!(
            serde_json::to_string(&cfg)
                .unwrap()
                .contains("\"pair_head\":16")
        );
        let vae = seeded_init(MeshVae::new(&cfg, &device), 5);
        let z = crate::model::sampler::normal_noise(
            &mut crate::rng::Rng::new(11),
            [2, cfg.num_latents, cfg.latent_dim],
            &device,
        );
        let out = vae.decode(z, &mut Trace::default());
        let real = [
            (0..cfg.num_vertices as u32).collect(),
            (0..10).collect::<Vec<u32>>(),
        ];
        let values = |t: Tensor<3>| t.into_data().convert::<f32>().try_to_vec::<f32>().unwrap();
        let plain = values(spacetime_distances(out.edge_embeddings.clone()));
        let silent = vae
            .edge_distances(out.edge_embeddings.clone(), out.features.clone(), &real)
            .unwrap();
        assert_eq!(plain, silent);

        let mut map = module_tensors(&vae);
        map.tensors
            .get_mut("decoder.pair_head.2.bias")
            .expect("the pair head's output bias")
            .1 = vec![1.5];
        let trained = load_module(MeshVae::new(&cfg, &device), &map, &|_| false).unwrap();
        let refined = trained
            .edge_distances(out.edge_embeddings.clone(), out.features.clone(), &real)
            .unwrap();
        let pairs = pair_candidates(&plain, cfg.num_vertices, &real);
        let n = cfg.num_vertices;
        for (at, (&a, &b)) in refined.iter().zip(&plain).enumerate() {
            let (k, i, j) = (at / (n * n), at / n % n, at % n);
            let candidate = pairs.binary_search(&[k as u32, i as u32, j as u32]).is_ok();
            if candidate {
                assert!((a - b - 1.5).abs() < 1e-4, "({k}, {i}, {j}): {b} -> {a}");
            } else {
                assert_eq!(a, b, "({k}, {i}, {j}) is not a candidate");
            }
        }
    }

    /// Widened weights decode the same vertices and, with silent added channels, exactly the
    /// same spacetime distances; with the scale used in training, nearly the same.
    #[test]
    fn widened_edge_embeddings_keep_the_trained_distances() {
        use crate::model::seeded_init;
        use crate::model::weights::{TensorMap, load_module, module_tensors};
        let device = Device::flex();
        let base = VaeConfig::vae_small();
        let wide = VaeConfig {
            edge_dim: 48,
            ..base.clone()
        };
        let vae = seeded_init(MeshVae::new(&base, &device), 3);
        let map: TensorMap = module_tensors(&vae);
        let z = crate::model::sampler::normal_noise(
            &mut crate::rng::Rng::new(11),
            [2, base.num_latents, base.latent_dim],
            &device,
        );
        let distances = |m: &MeshVae| {
            let out = m.decode(z.clone(), &mut Trace::default());
            (
                spacetime_distances(out.edge_embeddings)
                    .into_data()
                    .convert::<f32>()
                    .try_to_vec::<f32>()
                    .unwrap(),
                out.positions
                    .into_data()
                    .convert::<f32>()
                    .try_to_vec::<f32>()
                    .unwrap(),
            )
        };
        let (d0, p0) = distances(&vae);
        // With the scale used in training the distances move by about 1% of their typical
        // size on average and by under 10% at worst (over latent seeds); the bounds leave 2x.
        for (scale, mean_tolerance, worst_tolerance) in [(0.0, 0.0, 0.0), (0.1, 0.02, 0.2)] {
            let mut widened = map.clone();
            widen_edge_embeddings(&mut widened, 32, 48, scale, 7).unwrap();
            let grown = load_module(MeshVae::new(&wide, &device), &widened, &|_| false).unwrap();
            let (d, p) = distances(&grown);
            assert_eq!(p, p0);
            let typical = d0.iter().map(|x| x.abs()).sum::<f32>() / d0.len() as f32;
            let change: Vec<f32> = d.iter().zip(&d0).map(|(a, b)| (a - b).abs()).collect();
            let mean = change.iter().sum::<f32>() / change.len() as f32;
            let worst = change.iter().copied().fold(0.0, f32::max);
            assert!(
                mean <= mean_tolerance * typical && worst <= worst_tolerance * typical,
                "scale {scale}: mean {mean}, worst {worst} against {typical}"
            );
        }
        let mut odd = map.clone();
        assert!(widen_edge_embeddings(&mut odd, 32, 47, 0.1, 7).is_err());
        assert!(widen_edge_embeddings(&mut odd, 16, 32, 0.1, 7).is_err());
    }
}
