//! Training data: the shard format and the build's pure rules ([`dataset`]), reading a build
//! from disk ([`shards`]), augmentation, and the degradations the robustness figures use.

pub mod augment;
pub mod cards;
pub mod dataset;
pub mod degrade;
#[cfg(not(target_arch = "wasm32"))]
pub mod shards;
