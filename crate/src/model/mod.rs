//! The neural networks, in Burn, generic over the backend through Burn's run-time `Device`:
//! [`vae`] (MeshVAE), [`dit`] (rectified-flow DiT), shared [`layers`], and [`weights`] (safetensors under the reference's
//! state-dict names).

pub mod dit;
pub mod layers;
pub mod sampler;
pub mod schedule;
pub mod vae;
pub mod weights;

pub use vae::{Decoded, MeshVae, Posterior, Trace, VaeConfig, spacetime_distances};
pub use weights::{TensorMap, WeightsError, load_module, module_tensors, seeded_init};
