//! The neural networks, in Burn, generic over the backend through Burn's run-time `Device`:
//! their inputs ([`tokens`]: the MeshVAE's per-vertex tokens; [`condition`]: where the DiT's
//! latent tokens sit), [`vae`] (MeshVAE), [`dit`] (rectified-flow DiT), shared [`layers`],
//! the [`sampler`] and its [`schedule`], and [`weights`] (safetensors under the reference's
//! state-dict names).

pub mod condition;
pub mod dit;
/// The reference's golden vectors and the comparison of both models with them.
#[cfg(not(target_arch = "wasm32"))]
pub mod golden;
pub mod layers;
pub mod sampler;
pub mod schedule;
pub mod tokens;
pub mod vae;
pub mod weights;

pub use vae::{
    Decoded, MeshVae, PAIR_CANDIDATES, PAIR_CONTEXT, PairCorrections, Posterior, Trace, VaeConfig,
    add_pair_corrections, pair_candidates, pair_context, spacetime_distances,
    widen_edge_embeddings,
};
pub use weights::{
    TensorMap, WeightsError, load_module, load_module_keeping, module_tensors, seeded_init,
};
