//! The browser side: the viewer's orbit camera, and on wasm32 with feature `web` the
//! wasm-bindgen API (`api`) and, with feature `wgpu` (WebGPU) or `webgl` (the CPU module's
//! WebGL2), the wgpu mesh viewer (`viewer`).

#[cfg(all(target_arch = "wasm32", feature = "web"))]
pub mod api;
pub mod camera;
#[cfg(all(
    target_arch = "wasm32",
    feature = "web",
    any(feature = "wgpu", feature = "webgl")
))]
pub mod viewer;
