//! Evaluation: the paper's metrics (docs/design.md section 3), and the evaluations the CLI
//! runs over sets of meshes (`eval vae`, `eval generate`, `eval budget`).

#[cfg(not(target_arch = "wasm32"))]
pub mod budget;
pub mod edge_errors;
#[cfg(not(target_arch = "wasm32"))]
pub mod generation;
pub mod metrics;
/// Stage 4 with and without a pair head's distances (`meshflow bench pair-head`).
#[cfg(not(target_arch = "wasm32"))]
pub mod pair_head_extraction;
#[cfg(not(target_arch = "wasm32"))]
pub mod reconstruction;
#[cfg(not(target_arch = "wasm32"))]
pub mod sets;
pub mod summary;
/// Extraction and threshold timings beside the reference's figures (`meshflow bench extract`).
#[cfg(not(target_arch = "wasm32"))]
pub mod timing;
