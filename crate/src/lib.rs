//! MeshFlow: artist-like triangle meshes from point clouds.
//!
//! The method is "MeshFlow: Efficient Artistic Mesh Generation via MeshVAE and Flow-based
//! Diffusion Transformer" (CVPR 2026). This crate holds everything that runs the same natively
//! and in the browser: mesh I/O, the geometry core, the per-vertex tokens the MeshVAE reads,
//! the models, mesh extraction, fitting to the input, and the evaluation metrics. The
//! conventions it follows are in `docs/design.md` (cited as "docs/design.md section N").
//!
//! Module map (one algorithm per file):
//! - [`mesh`]: the [`Mesh`] type (positions, optional normals, triangles) and bounding boxes.
//! - [`io`]: readers (OBJ, PLY, STL, glTF/GLB, XYZ/PTS/CSV) and writers (GLB, OBJ, PLY).
//! - [`dataset`]: the training shard format (safetensors), the manifest, filter and split rules.
//! - [`cards`]: the billboard-card measure the dataset filter uses.
//! - `shards` (not wasm32): reading a shard build from disk (manifest, meshes by entry or
//!   split), the one reader training, evaluation and `meshflow data` use.
//! - [`augment`]: training-time augmentation (rotation about Y, scale jitter, surface points).
//! - [`disjoint_sets`]: union-find, for welding classes and components.
//! - [`clean`]: welding and removal of degenerate, duplicate and back-to-back faces.
//! - [`normalize`]: bounding-box normalisation to [-1,1] (model) or [-0.5,0.5] (metrics), and
//!   the rotation of a source's up axis to the model frame's Y-up.
//! - [`normals`]: area-weighted vertex normals.
//! - [`topology`]: edges, adjacency, boundary loops, components, the topology report.
//! - [`sample`]: seeded area-uniform surface sampling.
//! - [`voxel`]: voxel indices at resolution 32 for the DiT's RoPE-3D.
//! - [`tokens`]: vertex order, padding, Fourier features and neighbour block for the MeshVAE.
//! - [`extract`]: spacetime edge threshold, then edges -> faces by the manifold method
//!   (default) or the paper's Algorithm 1.
//! - [`manifold`]: the manifold method: candidate faces accepted best-first by edge margin,
//!   manifold and consistently wound by construction, small holes filled, tiny pieces dropped.
//! - [`overlap`]: the "no face lies on another it shares no edge with" test.
//! - [`fit`]: generated vertices moved onto the input points without folding faces.
//! - [`complete`]: the surface completed between generated vertices, on the input points.
//! - [`degrade`]: noisy and partial versions of a point cloud, for robustness figures.
//! - [`condition`]: where the DiT's latent tokens sit (farthest points of the input).
//! - [`model`]: the MeshVAE, the DiT, their layers, sampler and weight loading.
//! - [`reconstruct`]: a mesh through the MeshVAE and back.
//! - [`device`]: the CPU (flex) and wgpu devices.
//! - `train` (feature `train`): the training loop both models share, and each one's step.
//! - [`camera`]: the viewer's orbit camera.
//! - `viewer` (wasm32, feature `web`): the page's wgpu mesh viewer on Burn's WebGPU device.
//! - [`budget`]: the default vertex budget from a point cloud's occupancy and curvature.
//! - [`generate`]: the inference path, point cloud -> DiT sampling -> VAE decode -> mesh.
//! - [`shipped`]: the shipped weights' manifests, and loading them from bytes with checks.
//! - [`metrics`]: Chamfer / Hausdorff distance, normal consistency, edge F1, vertex distances.
//! - [`primitives`]: octahedron, icosphere and grid meshes for tests and benchmarks.
//! - `threshold_gpu` (feature `wgpu`): Algorithm 1's spacetime threshold as a WGSL kernel on
//!   Burn's wgpu device, so only an edge bit matrix is read back.
//! - [`rng`]: a small seeded generator so results are reproducible on every platform.
//! - `web` (wasm32, feature `web`): the browser API, wasm-bindgen.
//! - [`workloads`]: the inputs the extraction benchmarks time.

pub mod augment;
pub mod budget;
pub mod camera;
pub mod cards;
pub mod clean;
pub mod complete;
pub mod condition;
pub mod dataset;
pub mod degrade;
pub mod device;
pub mod disjoint_sets;
pub mod extract;
pub mod fit;
pub mod generate;
pub mod io;
pub mod manifold;
pub mod mesh;
pub mod metrics;
pub mod model;
pub mod normalize;
pub mod normals;
pub mod overlap;
pub mod primitives;
pub mod reconstruct;
pub mod rng;
pub mod sample;
#[cfg(not(target_arch = "wasm32"))]
pub mod shards;
pub mod shipped;
#[cfg(feature = "wgpu")]
pub mod threshold_gpu;
pub mod tokens;
pub mod topology;
#[cfg(feature = "train")]
pub mod train;
#[cfg(all(target_arch = "wasm32", feature = "web"))]
pub mod viewer;
pub mod voxel;
#[cfg(all(target_arch = "wasm32", feature = "web"))]
pub mod web;
pub mod workloads;

/// The Burn version the models are written against, for callers that build tensors.
pub use burn;
pub use mesh::{Aabb, Mesh};
