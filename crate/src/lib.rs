//! MeshFlow: artist-like triangle meshes from point clouds.
//!
//! The method is "MeshFlow: Efficient Artistic Mesh Generation via MeshVAE and Flow-based
//! Diffusion Transformer" (CVPR 2026). This crate holds everything that runs the same natively
//! and in the browser: mesh I/O, the geometry core, the per-vertex tokens the MeshVAE reads,
//! the models, mesh extraction, fitting to the input, and the evaluation metrics. The
//! conventions it follows are in `docs/design.md` (cited as "docs/design.md section N").
//!
//! The folders read as the method, top-down (one algorithm per file inside each):
//! input and output ([`io`]) and the geometry core ([`geometry`]); training data ([`data`]);
//! the networks and their inputs ([`model`]); edges to faces ([`extract`]); the surface
//! fitted to the input and completed ([`surface`]); the whole path, input to mesh
//! ([`pipeline`]); training (`train`), metrics ([`eval`]) and the browser side ([`web`]).
//!
//! - [`io`]: readers (OBJ, PLY, STL, glTF/GLB, XYZ/PTS/CSV, and the game formats the data
//!   build reads) and writers (GLB, OBJ, PLY).
//! - [`geometry`]: the [`Mesh`] type and bounding boxes, area-weighted normals, topology
//!   (edges, boundary loops, components, the topology report), seeded surface sampling,
//!   normalisation to the model frame, cleaning (welding, degenerate and duplicate faces),
//!   union-find, voxel indices for the DiT's RoPE-3D, test primitives.
//! - [`data`]: the shard format, manifest, filter and split rules; reading a build from disk
//!   (`shards`, not on wasm32); the billboard-card measure; training-time augmentation;
//!   noisy and partial point clouds for the robustness figures; with feature `data-build`,
//!   the data build itself (fetch the allowed packages, read, clean, filter, split, write
//!   shards, subset, statistics).
//! - [`model`]: the MeshVAE's per-vertex tokens, where the DiT's latent tokens sit, the
//!   MeshVAE, the DiT, their layers, sampler, schedule and weight loading.
//! - [`extract`]: spacetime edge threshold, then edges -> faces by the manifold method
//!   (default; `manifold`, with the `overlap` test) or the paper's Algorithm 1; the threshold
//!   as a WGSL kernel (`threshold_gpu`, feature `wgpu`).
//! - [`surface`]: generated vertices moved onto the input points without folding faces
//!   (`fit`), and the surface completed between them (`complete`).
//! - [`pipeline`]: the default vertex budget, generation (point cloud -> DiT sampling -> VAE
//!   decode -> mesh), reconstruction through the MeshVAE, the shipped weights (manifests,
//!   loading and checking the pair, finding and writing weights folders).
//! - `train` (feature `train`): the training loop both models share, each one's step, the
//!   named configurations, runs that end in shippable weights, and the step profiler.
//! - [`eval`]: Chamfer / Hausdorff distance, normal consistency, edge F1, vertex distances;
//!   natively also the evaluations over sets of meshes (`eval vae`, `eval generate`,
//!   `eval budget`) and their summaries.
//! - [`web`]: the viewer's orbit camera; on wasm32 with feature `web`, the wasm-bindgen API
//!   and the page's wgpu mesh viewer.
//! - [`device`]: the CPU (flex) and wgpu devices, the machine's description and, on glibc,
//!   the allocator policy the CPU backend runs fastest with; `parallel`:
//!   independent work on rayon's threads; [`rng`]: a small seeded generator, so
//!   results are reproducible on every platform; [`workloads`]: the inputs the extraction
//!   benchmarks time.

pub mod data;
pub mod device;
pub mod eval;
pub mod extract;
pub mod geometry;
pub mod io;
pub mod model;
mod parallel;
pub mod pipeline;
pub mod rng;
pub mod surface;
#[cfg(feature = "train")]
pub mod train;
pub mod web;
pub mod workloads;

/// The Burn version the models are written against, for callers that build tensors.
pub use burn;
pub use geometry::mesh::{Aabb, Mesh};

/// A tensor shape as error messages show it (`[2, 128, 32]`), written out rather than
/// debug-printed, as the rest of a message a user reads is.
pub(crate) fn shape_text(dims: &[usize]) -> String {
    let inner: Vec<String> = dims.iter().map(usize::to_string).collect();
    format!("[{}]", inner.join(", "))
}
