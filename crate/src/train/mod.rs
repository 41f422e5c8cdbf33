//! Training loops (feature `train`: Burn's autodiff and optimisers).

pub mod adamw;
pub mod vae;
