//! Layers shared by the MeshVAE and the DiT (docs/design.md section 2): multi-head attention with
//! per-head RMS q/k norm, the GELU feed-forward, and the pre-norm self- and cross-attention
//! blocks of the VAE.
//!
//! Field names are the reference's state-dict names wherever Rust allows; the few that are not
//! valid identifiers (`to_out.0`, `ff.net.0.proj`, ...) are renamed in one table,
//! [`crate::model::weights::reference_component`].

use burn::module::Module;
use burn::nn::{LayerNorm, LayerNormConfig, Linear, LinearConfig, RmsNorm, RmsNormConfig};
use burn::tensor::activation::gelu;
use burn::tensor::module::attention;
use burn::tensor::{Device, Tensor};

/// LayerNorm epsilon of the reference blocks.
pub const LAYER_NORM_EPS: f64 = 1e-5;

/// A Linear layer (weight `[in, out]`; `weights.rs` transposes to and from PyTorch's
/// `[out, in]` on the host).
pub fn linear(d_in: usize, d_out: usize, bias: bool, device: &Device) -> Linear {
    LinearConfig::new(d_in, d_out).with_bias(bias).init(device)
}

/// LayerNorm with weight and bias (eps 1e-5).
pub fn layer_norm(width: usize, device: &Device) -> LayerNorm {
    LayerNormConfig::new(width)
        .with_epsilon(LAYER_NORM_EPS)
        .init(device)
}

/// Multi-head attention: q/k/v without bias, heads as contiguous channel slices, RMSNorm per
/// head on q and k, scale 1/sqrt(head_dim), output projection with bias.
#[derive(Module, Debug)]
pub struct Attention {
    pub to_q: Linear,
    pub to_k: Linear,
    pub to_v: Linear,
    pub norm_q: RmsNorm,
    pub norm_k: RmsNorm,
    /// Reference name `to_out.0`.
    pub to_out: Linear,
    pub heads: usize,
}

impl Attention {
    /// `width` channels in `heads` heads; `qk_eps` is the q/k RMSNorm epsilon.
    pub fn new(width: usize, heads: usize, qk_eps: f64, device: &Device) -> Self {
        assert!(
            heads > 0 && width.is_multiple_of(heads),
            "width must divide into heads"
        );
        let head_dim = width / heads;
        let qk_norm = || {
            RmsNormConfig::new(head_dim)
                .with_epsilon(qk_eps)
                .init(device)
        };
        Self {
            to_q: linear(width, width, false, device),
            to_k: linear(width, width, false, device),
            to_v: linear(width, width, false, device),
            norm_q: qk_norm(),
            norm_k: qk_norm(),
            to_out: linear(width, width, true, device),
            heads,
        }
    }

    /// `[B, Lq, W]` queries attend to `[B, Lk, W]` context. `rope` rotates the normalised
    /// q and k (`[B, heads, L, head_dim]`) before the dot product; the VAE passes `None`.
    pub fn forward(
        &self,
        x: Tensor<3>,
        context: Tensor<3>,
        rope: Option<&dyn Fn(Tensor<4>) -> Tensor<4>>,
    ) -> Tensor<3> {
        let kv = self.keys_values(context, rope);
        self.attend(x, &kv, rope)
    }

    /// Keys (normalised, then rotated by `rope`) and values of `[B, Lk, W]` context, each
    /// `[B, heads, Lk, head_dim]`: computed once, they serve every query that attends to the
    /// same context ([`Self::attend`]).
    pub fn keys_values(
        &self,
        context: Tensor<3>,
        rope: Option<&dyn Fn(Tensor<4>) -> Tensor<4>>,
    ) -> KeysValues {
        let [b, lk, w] = context.dims();
        let hd = w / self.heads;
        let split = |t: Tensor<3>| t.reshape([b, lk, self.heads, hd]).swap_dims(1, 2);
        let mut k = self
            .norm_k
            .forward(split(self.to_k.forward(context.clone())));
        if let Some(rope) = rope {
            k = rope(k);
        }
        KeysValues {
            k,
            v: split(self.to_v.forward(context)),
        }
    }

    /// `[B, Lq, W]` queries (rotated by `rope`) attend to keys and values from
    /// [`Self::keys_values`].
    pub fn attend(
        &self,
        x: Tensor<3>,
        kv: &KeysValues,
        rope: Option<&dyn Fn(Tensor<4>) -> Tensor<4>>,
    ) -> Tensor<3> {
        let [b, lq, w] = x.dims();
        let hd = w / self.heads;
        let mut q = self.norm_q.forward(
            self.to_q
                .forward(x)
                .reshape([b, lq, self.heads, hd])
                .swap_dims(1, 2),
        );
        if let Some(rope) = rope {
            q = rope(q);
        }
        let out = attention(
            q,
            kv.k.clone(),
            kv.v.clone(),
            None,
            None,
            Default::default(),
        );
        self.to_out.forward(out.swap_dims(1, 2).reshape([b, lq, w]))
    }
}

/// Keys and values of one attention's context ([`Attention::keys_values`]).
#[derive(Clone, Debug)]
pub struct KeysValues {
    pub k: Tensor<4>,
    pub v: Tensor<4>,
}

/// Linear(w, 4w) . exact-erf GELU . Linear(4w, w).
#[derive(Module, Debug)]
pub struct FeedForward {
    /// Reference name `net.0.proj`.
    pub linear_in: Linear,
    /// Reference name `net.2`.
    pub linear_out: Linear,
}

impl FeedForward {
    pub fn new(width: usize, device: &Device) -> Self {
        Self {
            linear_in: linear(width, 4 * width, true, device),
            linear_out: linear(4 * width, width, true, device),
        }
    }

    pub fn forward(&self, x: Tensor<3>) -> Tensor<3> {
        self.linear_out.forward(gelu(self.linear_in.forward(x)))
    }
}

/// Pre-norm self-attention block: `h += attn1(norm1 h); h += ff(norm3 h)`.
#[derive(Module, Debug)]
pub struct SelfAttentionBlock {
    pub norm1: LayerNorm,
    pub attn1: Attention,
    pub norm3: LayerNorm,
    pub ff: FeedForward,
}

impl SelfAttentionBlock {
    pub fn new(width: usize, heads: usize, device: &Device) -> Self {
        Self {
            norm1: layer_norm(width, device),
            attn1: Attention::new(width, heads, LAYER_NORM_EPS, device),
            norm3: layer_norm(width, device),
            ff: FeedForward::new(width, device),
        }
    }

    pub fn forward(&self, h: Tensor<3>) -> Tensor<3> {
        let x = self.norm1.forward(h.clone());
        let h = h + self.attn1.forward(x.clone(), x, None);
        h.clone() + self.ff.forward(self.norm3.forward(h))
    }
}

/// Pre-norm cross-attention block: `h += attn2(norm2 h, context); h += ff(norm3 h)`. Only the
/// queries are normalised; the context enters as it is.
#[derive(Module, Debug)]
pub struct CrossAttentionBlock {
    pub norm2: LayerNorm,
    pub attn2: Attention,
    pub norm3: LayerNorm,
    pub ff: FeedForward,
}

impl CrossAttentionBlock {
    pub fn new(width: usize, heads: usize, device: &Device) -> Self {
        Self {
            norm2: layer_norm(width, device),
            attn2: Attention::new(width, heads, LAYER_NORM_EPS, device),
            norm3: layer_norm(width, device),
            ff: FeedForward::new(width, device),
        }
    }

    pub fn forward(&self, h: Tensor<3>, context: Tensor<3>) -> Tensor<3> {
        let h = h.clone() + self.attn2.forward(self.norm2.forward(h), context, None);
        h.clone() + self.ff.forward(self.norm3.forward(h))
    }
}
