//! The browser side: the viewer's orbit camera, and on wasm32 with feature `web` the
//! wasm-bindgen API (`api`) and, with feature `wgpu`, the wgpu mesh viewer (`viewer`).

#[cfg(all(target_arch = "wasm32", feature = "web"))]
pub mod api;
pub mod camera;
#[cfg(all(target_arch = "wasm32", feature = "web", feature = "wgpu"))]
pub mod viewer;
