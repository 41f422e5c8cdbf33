//! Rectified-flow diffusion transformer over the VAE's latent tokens, conditioned on the point
//! cloud through RoPE-3D positions of the tokens and on the vertex budget through the time
//! embedding.
//!
//! Paper: "MeshFlow: Efficient Artistic Mesh Generation via MeshVAE and Flow-based Diffusion
//! Transformer" (CVPR 2026). Conventions: docs/design.md section 2; parameter names are the
//! reference's (golden `dit_small`). The reference's image cross-attention (`attn2`, `norm2`)
//! is not built; its tensors are ignored when loading.
//!
//! Optionally (this project's extension, [`DitConfig::point_tokens`] > 0) every block also
//! cross-attends to a random subset of the input points, gated by the block's seventh AdaLN
//! chunk (the reference's `gate_cross`). The paper's DiT sees the input only through its
//! tokens' voxel positions, one surface point per token at 1/32 of the box; the extension
//! lets a token read the surface near it at full precision, with RoPE-3D on the queries
//! (token voxels) and keys (the points' continuous voxel coordinates), so attention is local
//! by relative position as in self-attention.
//!
//! ```text
//! temb = MLP(sinusoid(1000 t) + cond_proj(vertex_count / num_latents))
//! h = x_embedder(x)
//! block i: [i > depth/2: h = RMSNorm(skip_linear([skip | h]) + skip_gate h)]
//!          h += gate_msa  attn(modulate(RMSNorm1 h), RoPE-3D)
//!          [points: h += gate_cross point_attn(RMSNorm h, point_embedder(Fourier(p)))]
//!          h += gate_mlp  MLP(modulate(RMSNorm3 h))
//!          [i < depth/2: push h]
//! out = final_layer(final_norm h)
//! ```

use burn::module::{Module, Param};
use burn::nn::{Linear, RmsNorm, RmsNormConfig};
use burn::tensor::activation::{gelu, silu};
use burn::tensor::{Device, Tensor, TensorData};
use serde::{Deserialize, Serialize};

use glam::Vec3;

use super::layers::{Attention, KeysValues, linear};
use super::tokens::fourier_embed;

/// RMSNorm epsilon of the DiT.
pub const DIT_NORM_EPS: f64 = 1e-6;
/// Voxel grid of the RoPE positions.
pub const ROPE_GRID: usize = 32;
/// Most input points a DiT may cross-attend to (attention grows with their number).
pub const MAX_POINT_TOKENS: usize = 4096;
/// Fourier frequencies of the input points' features (`3 + 6 POINT_FREQS` channels).
pub const POINT_FREQS: usize = 8;

/// Size of a DiT. Stored as JSON beside the weights.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DitConfig {
    /// Latent tokens per mesh (the VAE's N / r).
    pub num_latents: usize,
    /// Channels per latent token.
    pub latent_dim: usize,
    pub width: usize,
    pub depth: usize,
    pub num_heads: usize,
    /// Input points every block cross-attends to (see the module doc); 0, the paper's
    /// layout, attends to none.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub point_tokens: usize,
    /// What the vertex-count condition divides by when it is not `num_latents` (0, left out
    /// of the JSON: `num_latents`, the reference's). A model whose capacity was raised after
    /// training keeps the divisor it was trained with, so a count means what it meant.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub count_divisor: usize,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

impl DitConfig {
    /// The divisor of the vertex-count condition ([`crate::model::condition::vertex_condition`]).
    pub fn count_scale(&self) -> usize {
        if self.count_divisor == 0 {
            self.num_latents
        } else {
            self.count_divisor
        }
    }

    /// Whether `other`'s weights load into this configuration and mean the same: equal but
    /// for `num_latents`, which no weight depends on (no positional embedding), as long as
    /// the count condition divides by the same number.
    pub fn same_shapes(&self, other: &DitConfig) -> bool {
        let capacity_free = |c: &DitConfig| DitConfig {
            num_latents: 0,
            count_divisor: c.count_scale(),
            ..c.clone()
        };
        capacity_free(self) == capacity_free(other)
    }

    /// The golden `dit_small` configuration.
    pub fn dit_small() -> Self {
        Self {
            num_latents: 16,
            latent_dim: 8,
            width: 96,
            depth: 4,
            num_heads: 4,
            point_tokens: 0,
            count_divisor: 0,
        }
    }

    /// Checks the sizes fit together.
    pub fn validate(&self) -> Result<(), String> {
        if self.width == 0 || self.num_heads == 0 || self.latent_dim == 0 || self.depth == 0 {
            return Err("width, num_heads, latent_dim and depth must be positive".into());
        }
        if !self.width.is_multiple_of(self.num_heads) {
            return Err("width must be a multiple of num_heads".into());
        }
        let head_dim = self.width / self.num_heads;
        if !head_dim.is_multiple_of(6) {
            return Err("head_dim must be a multiple of 6 (three axes of RoPE pairs)".into());
        }
        if !self.width.is_multiple_of(2) {
            return Err("width must be even (sin | cos time features)".into());
        }
        if self.point_tokens > MAX_POINT_TOKENS {
            return Err(format!(
                "point_tokens must be at most {MAX_POINT_TOKENS}, got {}",
                self.point_tokens
            ));
        }
        Ok(())
    }
}

fn rms_norm(width: usize, device: &Device) -> RmsNorm {
    RmsNormConfig::new(width)
        .with_epsilon(DIT_NORM_EPS)
        .init(device)
}

/// RoPE-3D angles for one batch: `cos` and `sin` `[B, 1, L, head_dim]`, each pair's angle
/// repeated for its two channels.
pub struct Rope {
    cos: Tensor<4>,
    sin: Tensor<4>,
    /// `[head_dim, head_dim]`: `x P` is `x` with each pair `(a, b)` turned to `(-b, a)`.
    turn: Tensor<2>,
}

impl Rope {
    /// Angles for voxel indices `positions` (`B x L` rows of 3 values in `0..32`).
    pub fn new(positions: &[[f32; 3]], batch: usize, head_dim: usize, device: &Device) -> Self {
        let chunk = head_dim / 3;
        let len = positions.len() / batch;
        let mut cos = Vec::with_capacity(positions.len() * head_dim);
        let mut sin = Vec::with_capacity(positions.len() * head_dim);
        for p in positions {
            for &coord in p {
                for j in 0..chunk / 2 {
                    let inv_freq = 10000f64.powf(-((2 * j) as f64) / chunk as f64);
                    let angle = coord as f64 * inv_freq;
                    let (s, c) = (angle.sin() as f32, angle.cos() as f32);
                    cos.extend([c, c]);
                    sin.extend([s, s]);
                }
            }
        }
        let t = |v: Vec<f32>| {
            Tensor::<4>::from_data(TensorData::new(v, [batch, 1, len, head_dim]), device)
        };
        let mut turn = vec![0f32; head_dim * head_dim];
        for pair in (0..head_dim).step_by(2) {
            turn[(pair + 1) * head_dim + pair] = -1.0; // out[2i] = -x[2i + 1]
            turn[pair * head_dim + pair + 1] = 1.0; // out[2i + 1] = x[2i]
        }
        Self {
            cos: t(cos),
            sin: t(sin),
            turn: Tensor::from_data(TensorData::new(turn, [head_dim, head_dim]), device),
        }
    }

    /// Rotates adjacent channel pairs of `x` `[B, H, L, head_dim]`.
    pub fn apply(&self, x: Tensor<4>) -> Tensor<4> {
        // One small matrix product turns every pair: exact (each output is one input times
        // +-1, plus zeros), and several times faster on the CPU than slicing the pairs apart
        // and concatenating them, which copied strided views three times per call.
        let [b, h, l, d] = x.dims();
        let turned = x
            .clone()
            .reshape([b * h * l, d])
            .matmul(self.turn.clone())
            .reshape([b, h, l, d]);
        x * self.cos.clone() + turned * self.sin.clone()
    }
}

/// What the DiT is conditioned on besides time and vertex count: its tokens' RoPE-3D
/// positions and, for a DiT with [`DitConfig::point_tokens`], the input points its tokens
/// cross-attend to.
pub struct Condition {
    pub rope: Rope,
    points: Option<PointContext>,
    /// Every block's keys and values of the embedded points, once [`Dit::cache_points`] has
    /// computed them.
    cached: Option<Vec<Option<KeysValues>>>,
}

/// Input points: their Fourier features `[B, P, 3 + 6 POINT_FREQS]` and RoPE angles.
struct PointContext {
    features: Tensor<3>,
    rope: Rope,
}

impl Condition {
    /// `positions`: `batch x L` token voxels ([`Rope::new`]); `points`: one row of
    /// `cfg.point_tokens` model-frame points per batch row
    /// ([`crate::model::condition::context_points`]), unused when the config has none.
    pub fn new(
        cfg: &DitConfig,
        positions: &[[f32; 3]],
        points: &[Vec<Vec3>],
        batch: usize,
        device: &Device,
    ) -> Self {
        let head_dim = cfg.width / cfg.num_heads;
        let points = (cfg.point_tokens > 0).then(|| {
            let p = cfg.point_tokens;
            assert!(
                points.len() == batch && points.iter().all(|r| r.len() == p),
                "one row of {p} points per batch row"
            );
            let mut features = Vec::with_capacity(batch * p * (3 + 6 * POINT_FREQS));
            let mut cells = Vec::with_capacity(batch * p);
            for &q in points.iter().flatten() {
                fourier_embed(q, POINT_FREQS, &mut features);
                // Continuous voxel coordinates: a point at a voxel's centre gets its index.
                cells.push(
                    ((q + 1.0) * 0.5 * ROPE_GRID as f32 - 0.5)
                        .clamp(Vec3::splat(-0.5), Vec3::splat(ROPE_GRID as f32 - 0.5))
                        .to_array(),
                );
            }
            let width = 3 + 6 * POINT_FREQS;
            PointContext {
                features: Tensor::from_data(TensorData::new(features, [batch, p, width]), device),
                rope: Rope::new(&cells, batch, head_dim, device),
            }
        });
        Self {
            rope: Rope::new(positions, batch, head_dim, device),
            points,
            cached: None,
        }
    }
}

/// fc1 . GELU . fc2.
#[derive(Module, Debug)]
pub struct DitMlp {
    pub fc1: Linear,
    pub fc2: Linear,
}

/// One DiT block; blocks in the second half also merge a long skip.
#[derive(Module, Debug)]
pub struct DitBlock {
    pub norm1: RmsNorm,
    /// Self-attention with RoPE (the reference calls its norms `q_norm`, `k_norm` and its
    /// output `out_proj`: [`crate::model::weights::reference_component`]).
    pub attn1: Attention,
    pub norm3: RmsNorm,
    /// Reference name `adaLN_modulation.1`: SiLU(temb) -> 7 chunks.
    pub adaln: Linear,
    pub mlp: DitMlp,
    pub skip: Option<LongSkip>,
    pub point_attn: Option<PointAttention>,
}

/// Cross-attention from the tokens to the embedded input points.
#[derive(Module, Debug)]
pub struct PointAttention {
    pub norm: RmsNorm,
    pub attn: Attention,
}

/// Fourier features of a point -> width: hidden . GELU . output.
#[derive(Module, Debug)]
pub struct PointEmbedder {
    pub hidden: Linear,
    pub output: Linear,
}

/// `h = RMSNorm(skip_linear([skip | h]) + skip_gate h)`.
#[derive(Module, Debug)]
pub struct LongSkip {
    pub skip_linear: Linear,
    pub skip_norm: RmsNorm,
    pub skip_gate: Param<Tensor<1>>,
}

/// `x (1 + scale) + shift` with `[B, W]` modulation broadcast over tokens.
fn modulate(x: Tensor<3>, shift: Tensor<3>, scale: Tensor<3>) -> Tensor<3> {
    x * (scale + 1.0) + shift
}

impl DitBlock {
    fn new(width: usize, heads: usize, with_skip: bool, points: bool, device: &Device) -> Self {
        Self {
            norm1: rms_norm(width, device),
            attn1: Attention::new(width, heads, DIT_NORM_EPS, device),
            norm3: rms_norm(width, device),
            adaln: linear(width, 7 * width, true, device),
            mlp: DitMlp {
                fc1: linear(width, 4 * width, true, device),
                fc2: linear(4 * width, width, true, device),
            },
            skip: with_skip.then(|| LongSkip {
                skip_linear: linear(2 * width, width, true, device),
                skip_norm: rms_norm(width, device),
                skip_gate: Param::from_tensor(Tensor::full([1], 0.5, device)),
            }),
            point_attn: points.then(|| PointAttention {
                norm: rms_norm(width, device),
                attn: Attention::new(width, heads, DIT_NORM_EPS, device),
            }),
        }
    }

    fn forward(
        &self,
        h: Tensor<3>,
        temb: Tensor<2>,
        rope: &Rope,
        points: Option<&KeysValues>,
        skip: Option<Tensor<3>>,
    ) -> Tensor<3> {
        let h = match (&self.skip, skip) {
            (Some(s), Some(skip)) => {
                let merged = s.skip_linear.forward(Tensor::cat(vec![skip, h.clone()], 2));
                s.skip_norm
                    .forward(merged + h * s.skip_gate.val().unsqueeze::<3>())
            }
            _ => h,
        };
        let [b, w] = temb.dims();
        let m = self.adaln.forward(silu(temb)).reshape([b, 7, w]);
        let chunk = |i: usize| m.clone().narrow(1, i, 1); // [B, 1, W]
        let x = modulate(self.norm1.forward(h.clone()), chunk(0), chunk(1));
        let h = h + chunk(2) * self.attn1.forward(x.clone(), x, Some(&|t| rope.apply(t)));
        let h = match (&self.point_attn, points) {
            (Some(p), Some(kv)) => {
                let read = p
                    .attn
                    .attend(p.norm.forward(h.clone()), kv, Some(&|t| rope.apply(t)));
                h + chunk(6) * read
            }
            _ => h,
        };
        let x = modulate(self.norm3.forward(h.clone()), chunk(3), chunk(4));
        let mlp = self.mlp.fc2.forward(gelu(self.mlp.fc1.forward(x)));
        h + chunk(5) * mlp
    }
}

/// Timestep embedding with the vertex-count condition.
#[derive(Module, Debug)]
pub struct TimestepEmbedder {
    pub mlp: TimeMlp,
    pub cond_proj: Linear,
}

/// Reference names `mlp.0` and `mlp.2`.
#[derive(Module, Debug)]
pub struct TimeMlp {
    pub hidden: Linear,
    pub output: Linear,
}

/// Sinusoidal features of `t` (in [0, 1]): `width` channels `[sin | cos]`,
/// `freq_k = exp(-ln(1e4) k / (width / 2))`, argument `(t freq_k) 1000`.
pub fn time_features(t: &[f32], width: usize, device: &Device) -> Tensor<2> {
    let half = width / 2;
    let mut v = Vec::with_capacity(t.len() * width);
    for &ti in t {
        let args: Vec<f32> = (0..half)
            .map(|k| {
                let freq = (-(10000f32.ln()) * k as f32 / half as f32).exp();
                ti * freq * 1000.0
            })
            .collect();
        v.extend(args.iter().map(|a| a.sin()));
        v.extend(args.iter().map(|a| a.cos()));
    }
    Tensor::from_data(TensorData::new(v, [t.len(), width]), device)
}

/// The DiT. Build with [`Dit::new`], load reference weights with
/// [`crate::model::weights::load_module`] ignoring [`is_image_path`] names.
#[derive(Module, Debug)]
pub struct Dit {
    pub x_embedder: Linear,
    pub t_embedder: TimestepEmbedder,
    pub point_embedder: Option<PointEmbedder>,
    pub blocks: Vec<DitBlock>,
    pub final_norm: RmsNorm,
    pub final_layer: FinalLayer,
}

/// Reference name `final_layer.linear`.
#[derive(Module, Debug)]
pub struct FinalLayer {
    pub linear: Linear,
}

/// The reference's image-conditioning tensors, unused for point clouds.
pub fn is_image_path(name: &str) -> bool {
    name.contains(".attn2.") || name.ends_with(".norm2.weight")
}

impl Dit {
    pub fn new(cfg: &DitConfig, device: &Device) -> Self {
        let w = cfg.width;
        Self {
            x_embedder: linear(cfg.latent_dim, w, true, device),
            t_embedder: TimestepEmbedder {
                mlp: TimeMlp {
                    hidden: linear(w, 4 * w, true, device),
                    output: linear(4 * w, w, true, device),
                },
                cond_proj: linear(1, w, false, device),
            },
            point_embedder: (cfg.point_tokens > 0).then(|| PointEmbedder {
                hidden: linear(3 + 6 * POINT_FREQS, w, true, device),
                output: linear(w, w, true, device),
            }),
            blocks: (0..cfg.depth)
                .map(|i| {
                    let skip = i > cfg.depth / 2;
                    DitBlock::new(w, cfg.num_heads, skip, cfg.point_tokens > 0, device)
                })
                .collect(),
            final_norm: rms_norm(w, device),
            final_layer: FinalLayer {
                linear: linear(w, cfg.latent_dim, true, device),
            },
        }
    }

    /// Time embedding `[B, W]` from model times `t` and the vertex-count condition
    /// `cond` (`[B, 1]`, vertex_count / num_latents).
    pub fn time_embedding(&self, t: &[f32], cond: Tensor<2>) -> Tensor<2> {
        let w = self.x_embedder.weight.dims()[1];
        let device = cond.device();
        let x = time_features(t, w, &device) + self.t_embedder.cond_proj.forward(cond);
        let mlp = &self.t_embedder.mlp;
        mlp.output.forward(gelu(mlp.hidden.forward(x)))
    }

    /// Every block's keys and values of the embedded input points (empty without points).
    fn point_keys_values(&self, condition: &Condition) -> Vec<Option<KeysValues>> {
        let (Some(embedder), Some(ctx)) = (&self.point_embedder, &condition.points) else {
            return Vec::new();
        };
        let embedded = embedder
            .output
            .forward(gelu(embedder.hidden.forward(ctx.features.clone())));
        let rope = |t| ctx.rope.apply(t);
        self.blocks
            .iter()
            .map(|b| {
                let p = b.point_attn.as_ref()?;
                Some(p.attn.keys_values(embedded.clone(), Some(&rope)))
            })
            .collect()
    }

    /// Computes once what every sampling step shares: the input points' keys and values in
    /// every block (they depend on neither `x` nor `t`). Sampling calls it; training does
    /// not, so that gradients reach the point path.
    pub fn cache_points(&self, condition: &mut Condition) {
        condition.cached = Some(self.point_keys_values(condition));
    }

    /// Velocity for latents `x` `[B, L, D]` at model times `t` (one per batch row).
    pub fn forward(
        &self,
        x: Tensor<3>,
        t: &[f32],
        cond: Tensor<2>,
        condition: &Condition,
        trace: &mut super::vae::Trace,
    ) -> Tensor<3> {
        let temb = self.time_embedding(t, cond);
        let points = match &condition.cached {
            Some(cached) => cached.clone(),
            None => self.point_keys_values(condition),
        };
        let mut h = self.x_embedder.forward(x);
        trace.record("x_embedder", &h);
        let depth = self.blocks.len();
        let mut skips = Vec::new();
        for (i, block) in self.blocks.iter().enumerate() {
            let skip = if i > depth / 2 { skips.pop() } else { None };
            let kv = points.get(i).and_then(Option::as_ref);
            h = block.forward(h, temb.clone(), &condition.rope, kv, skip);
            if i < depth / 2 {
                skips.push(h.clone());
            }
            trace.record(&format!("blocks.{i}"), &h);
        }
        let h = self.final_norm.forward(h);
        trace.record("final_norm", &h);
        self.final_layer.linear.forward(h)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A DiT raised from 128 to 512 latents with the count divisor kept conditions a vertex
    /// count as before and loads the same weights; without the divisor the condition would
    /// change, and the field stays out of a file that does not need it.
    #[test]
    fn raising_the_capacity_keeps_the_count_condition() {
        let shipped = DitConfig {
            num_latents: 128,
            ..DitConfig::dit_small()
        };
        let raised = DitConfig {
            num_latents: 512,
            count_divisor: 128,
            ..shipped.clone()
        };
        assert_eq!(raised.count_scale(), shipped.count_scale());
        assert!(raised.same_shapes(&shipped) && shipped.same_shapes(&raised));
        let divisor_lost = DitConfig {
            num_latents: 512,
            ..shipped.clone()
        };
        assert!(!divisor_lost.same_shapes(&shipped));
        assert!(
            !serde_json::to_string(&shipped)
                .unwrap()
                .contains("count_divisor")
        );
        let round: DitConfig =
            serde_json::from_str(&serde_json::to_string(&raised).unwrap()).unwrap();
        assert_eq!(round, raised);
    }

    #[test]
    fn point_tokens_default_to_none_and_are_bounded() {
        // Configs from before the point path load unchanged and save without the field.
        let old = r#"{"num_latents":16,"latent_dim":8,"width":96,"depth":4,"num_heads":4}"#;
        let cfg: DitConfig = serde_json::from_str(old).unwrap();
        assert_eq!(cfg, DitConfig::dit_small());
        assert_eq!(serde_json::to_string(&cfg).unwrap(), old);
        let reading = DitConfig {
            point_tokens: 256,
            ..DitConfig::dit_small()
        };
        assert!(reading.validate().is_ok());
        let too_many = DitConfig {
            point_tokens: MAX_POINT_TOKENS + 1,
            ..DitConfig::dit_small()
        };
        let err = too_many.validate().unwrap_err();
        assert!(err.contains("point_tokens"), "{err}");
    }

    #[test]
    fn points_sit_at_their_continuous_voxel_coordinates() {
        // A point at a voxel's centre rotates like a token in that voxel; the point path adds
        // features of every point to the condition.
        let device = Device::flex();
        let cfg = DitConfig {
            point_tokens: 2,
            ..DitConfig::dit_small()
        };
        let centre = |i: f32| (i + 0.5) / ROPE_GRID as f32 * 2.0 - 1.0;
        let points = vec![vec![
            Vec3::new(centre(3.0), centre(0.0), centre(31.0)),
            Vec3::ZERO,
        ]];
        let c = Condition::new(&cfg, &[[3.0, 0.0, 31.0]; 16], &points, 1, &device);
        let ctx = c.points.as_ref().unwrap();
        assert_eq!(ctx.features.dims(), [1, 2, 3 + 6 * POINT_FREQS]);
        let head_dim = cfg.width / cfg.num_heads;
        let angles = |r: &Rope, row: usize| {
            let v = r.cos.clone().into_data().try_into_vec::<f32>().unwrap();
            v[row * head_dim..(row + 1) * head_dim].to_vec()
        };
        for (a, b) in angles(&ctx.rope, 0).iter().zip(angles(&c.rope, 0)) {
            assert!((a - b).abs() < 1e-4, "{a} vs {b}");
        }
        let blind = Condition::new(&DitConfig::dit_small(), &[[0.0; 3]; 16], &[], 1, &device);
        assert!(blind.points.is_none());
    }

    #[test]
    fn cached_point_keys_give_the_uncached_velocity() {
        let device = Device::flex();
        let cfg = DitConfig {
            point_tokens: 8,
            ..DitConfig::dit_small()
        };
        let dit = crate::model::seeded_init(Dit::new(&cfg, &device), 4);
        let mut rng = crate::rng::Rng::new(2);
        let points: Vec<Vec<Vec3>> = (0..2)
            .map(|_| {
                (0..8)
                    .map(|_| Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - 1.0)
                    .collect()
            })
            .collect();
        let positions: Vec<[f32; 3]> = (0..32).map(|i| [(i % 32) as f32, 3.0, 7.0]).collect();
        let x = crate::model::sampler::normal_noise(&mut rng, [2, 16, 8], &device);
        let cond = Tensor::<2>::ones([2, 1], &device);
        let velocity = |c: &Condition| {
            let v = dit.forward(
                x.clone(),
                &[0.3, 0.7],
                cond.clone(),
                c,
                &mut Default::default(),
            );
            v.into_data().try_into_vec::<f32>().unwrap()
        };
        let mut condition = Condition::new(&cfg, &positions, &points, 2, &device);
        let uncached = velocity(&condition);
        dit.cache_points(&mut condition);
        let cached = velocity(&condition);
        let diff = uncached
            .iter()
            .zip(&cached)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f32::max);
        assert!(diff < 1e-6, "{diff}");
        // The points matter: other points, other velocity.
        let mut moved = points.clone();
        moved[0][0] = -moved[0][0];
        let other = velocity(&Condition::new(&cfg, &positions, &moved, 2, &device));
        assert!(
            uncached
                .iter()
                .zip(&other)
                .any(|(a, b)| (a - b).abs() > 1e-5)
        );
    }

    #[test]
    fn rope_turns_each_channel_pair_by_its_angle() {
        // One token at voxel (1, 2, 3): pair j of axis a turns by coord_a * 10000^(-2j/chunk).
        let device = Device::flex();
        let head_dim = 12;
        let rope = Rope::new(&[[1.0, 2.0, 3.0]], 1, head_dim, &device);
        let x: Vec<f32> = (0..head_dim).map(|i| 0.5 + i as f32).collect();
        let turned = rope
            .apply(Tensor::from_data(
                TensorData::new(x.clone(), [1, 1, 1, head_dim]),
                &device,
            ))
            .into_data()
            .try_into_vec::<f32>()
            .unwrap();
        let chunk = head_dim / 3;
        for pair in 0..head_dim / 2 {
            let (axis, j) = (2 * pair / chunk, pair % (chunk / 2));
            let angle = (axis + 1) as f64 * 10000f64.powf(-((2 * j) as f64) / chunk as f64);
            let (s, c) = (angle.sin() as f32, angle.cos() as f32);
            let (a, b) = (x[2 * pair], x[2 * pair + 1]);
            let want = [a * c - b * s, b * c + a * s];
            for (got, want) in turned[2 * pair..2 * pair + 2].iter().zip(want) {
                assert!((got - want).abs() < 1e-5, "pair {pair}: {got} vs {want}");
            }
        }
    }
}
