//! The page's mesh viewer (wasm32, feature `web`): a wgpu renderer drawing into an
//! `OffscreenCanvas` (so it runs in the page's worker), on the device Burn's WebGPU backend
//! already holds (feature `wgpu`), or in the CPU module on a WebGL2 context of its own
//! (feature `webgl`: wgpu's GL backend), so both paths show the same lit, depth-tested view.
//! The generated mesh is flat-shaded with its wireframe over it (topology is what this product
//! is about), the input points are small squares; an orbit camera (glam) turns, zooms, pans
//! and fits the view. Shaders: `shaders/viewer.wgsl`.

#[cfg(feature = "wgpu")]
use burn::tensor::wgpu::{WgpuSetup, wgpu};
use glam::Vec3;

use crate::web::camera::OrbitCamera;
use wasm_bindgen::prelude::*;
use wgpu::util::DeviceExt;

const SHADER: &str = include_str!("../../../shaders/viewer.wgsl");
const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Point squares and wireframe lines, in pixels.
const POINT_SIZE: f32 = 2.0;
const WIRE_WIDTH: f32 = 1.0;

/// The renderer: one surface, two pipelines (mesh, points) and the scene's buffers.
#[wasm_bindgen]
pub struct Viewer {
    surface: wgpu::Surface<'static>,
    device: wgpu::Device,
    queue: wgpu::Queue,
    config: wgpu::SurfaceConfiguration,
    depth: wgpu::TextureView,
    mesh_pipeline: wgpu::RenderPipeline,
    point_pipeline: wgpu::RenderPipeline,
    view_buffer: wgpu::Buffer,
    view_group: wgpu::BindGroup,
    /// Unindexed triangle vertices (position, face normal) and their count.
    mesh: Option<(wgpu::Buffer, u32)>,
    mesh_positions: Vec<f32>,
    points: Option<(wgpu::Buffer, u32)>,
    /// Draw the points over the mesh too (they always show while there is no mesh).
    points_over_mesh: bool,
    point_positions: Vec<f32>,
    camera: OrbitCamera,
    /// What draws: "webgpu" or "webgl2".
    api: &'static str,
}

impl Viewer {
    /// A viewer drawing into `canvas` with the device and queue of `setup` (Burn's).
    #[cfg(feature = "wgpu")]
    pub fn on_webgpu(
        setup: &WgpuSetup,
        canvas: web_sys::OffscreenCanvas,
    ) -> Result<Viewer, String> {
        let (width, height) = (canvas.width().max(1), canvas.height().max(1));
        let surface = setup
            .instance
            .create_surface(wgpu::SurfaceTarget::OffscreenCanvas(canvas))
            .map_err(|e| format!("cannot draw on the canvas with WebGPU: {e}"))?;
        Viewer::on_device(
            surface,
            &setup.adapter,
            setup.device.clone(),
            setup.queue.clone(),
            (width, height),
            "webgpu",
        )
    }

    /// A viewer drawing into `canvas` through a WebGL2 context of its own (wgpu's GL backend),
    /// for the CPU path, which has no GPU device to share.
    #[cfg(all(feature = "webgl", not(feature = "wgpu")))]
    pub async fn on_webgl2(canvas: web_sys::OffscreenCanvas) -> Result<Viewer, String> {
        let (width, height) = (canvas.width().max(1), canvas.height().max(1));
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
            backends: wgpu::Backends::GL,
            ..wgpu::InstanceDescriptor::new_without_display_handle()
        });
        // On the web the GL context comes from the canvas, so the surface comes first.
        let surface = instance
            .create_surface(wgpu::SurfaceTarget::OffscreenCanvas(canvas))
            .map_err(|e| format!("cannot draw on the canvas with WebGL2: {e}"))?;
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions {
                compatible_surface: Some(&surface),
                ..Default::default()
            })
            .await
            .map_err(|e| format!("no WebGL2 adapter for the canvas: {e}"))?;
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("viewer"),
                required_limits: wgpu::Limits::downlevel_webgl2_defaults()
                    .using_resolution(adapter.limits()),
                ..Default::default()
            })
            .await
            .map_err(|e| format!("no WebGL2 device for the canvas: {e}"))?;
        Viewer::on_device(surface, &adapter, device, queue, (width, height), "webgl2")
    }

    /// The pipelines and buffers on `device`, presenting to `surface` of `size` pixels.
    fn on_device(
        surface: wgpu::Surface<'static>,
        adapter: &wgpu::Adapter,
        device: wgpu::Device,
        queue: wgpu::Queue,
        (width, height): (u32, u32),
        api: &'static str,
    ) -> Result<Viewer, String> {
        let mut config = surface
            .get_default_config(adapter, width, height)
            .ok_or("the adapter cannot present to this canvas")?;
        // A plain (non-sRGB) format where there is one, so the colours match the 2D viewer's.
        let formats = surface.get_capabilities(adapter).formats;
        if let Some(&f) = formats.iter().find(|f| !f.is_srgb()) {
            config.format = f;
        }
        surface.configure(&device, &config);

        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("viewer.wgsl"),
            source: wgpu::ShaderSource::Wgsl(SHADER.into()),
        });
        let view_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("view"),
            size: 112,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let view_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("view"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let view_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("view"),
            layout: &view_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: view_buffer.as_entire_binding(),
            }],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("viewer"),
            bind_group_layouts: &[Some(&view_layout)],
            immediate_size: 0,
        });
        let pipeline = |label, vertex, fragment, buffer: wgpu::VertexBufferLayout| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some(vertex),
                    compilation_options: Default::default(),
                    buffers: &[Some(buffer)],
                },
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::Less),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(fragment),
                    compilation_options: Default::default(),
                    targets: &[Some(config.format.into())],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let mesh_pipeline = pipeline(
            "mesh",
            "mesh_vertex",
            "mesh_fragment",
            wgpu::VertexBufferLayout {
                array_stride: 24,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3],
            },
        );
        let point_pipeline = pipeline(
            "points",
            "point_vertex",
            "point_fragment",
            wgpu::VertexBufferLayout {
                array_stride: 12,
                step_mode: wgpu::VertexStepMode::Instance,
                attributes: &wgpu::vertex_attr_array![0 => Float32x3],
            },
        );
        let depth = depth_view(&device, width, height);
        Ok(Viewer {
            surface,
            device,
            queue,
            config,
            depth,
            mesh_pipeline,
            point_pipeline,
            view_buffer,
            view_group,
            mesh: None,
            mesh_positions: Vec::new(),
            points: None,
            points_over_mesh: true,
            point_positions: Vec::new(),
            camera: OrbitCamera::default(),
            api,
        })
    }

    fn buffer(&self, label: &str, data: &[f32]) -> wgpu::Buffer {
        self.device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: f32_bytes(data),
                usage: wgpu::BufferUsages::VERTEX,
            })
    }

    fn fit_scene(&mut self) {
        let scene = if self.mesh.is_some() {
            &self.mesh_positions
        } else {
            &self.point_positions
        };
        self.camera.fit(scene);
    }
}

#[wasm_bindgen]
impl Viewer {
    /// What draws: `"webgpu"` (the model's device) or `"webgl2"` (the CPU path's own context).
    #[wasm_bindgen(getter)]
    pub fn api(&self) -> String {
        self.api.into()
    }

    /// Shows a triangle mesh (x, y, z per vertex; three indices per face), fitted to the
    /// view; empty arrays clear it. Indices past the vertices are an error.
    #[wasm_bindgen(js_name = setMesh)]
    pub fn set_mesh(&mut self, positions: &[f32], indices: &[u32]) -> Result<(), JsError> {
        let n = positions.len() / 3;
        if let Some(&bad) = indices.iter().find(|&&i| i as usize >= n) {
            return Err(JsError::new(&format!(
                "index {bad} is past the {n} vertices"
            )));
        }
        let vertex = |i: u32| Vec3::from_slice(&positions[i as usize * 3..i as usize * 3 + 3]);
        let mut data = Vec::with_capacity(indices.len() / 3 * 18);
        for face in indices.chunks_exact(3) {
            let [a, b, c] = [vertex(face[0]), vertex(face[1]), vertex(face[2])];
            let normal = (b - a).cross(c - a).normalize_or(Vec3::Z);
            for p in [a, b, c] {
                data.extend_from_slice(&p.to_array());
                data.extend_from_slice(&normal.to_array());
            }
        }
        self.mesh =
            (!data.is_empty()).then(|| (self.buffer("mesh", &data), (data.len() / 6) as u32));
        self.mesh_positions = positions.to_vec();
        self.fit_scene();
        self.render()
    }

    /// Shows the input points (x, y, z triples), fitted to the view when there is no mesh.
    #[wasm_bindgen(js_name = setPoints)]
    pub fn set_points(&mut self, points: &[f32]) -> Result<(), JsError> {
        let n = points.len() / 3;
        self.points = (n > 0).then(|| (self.buffer("points", &points[..n * 3]), n as u32));
        self.point_positions = points[..n * 3].to_vec();
        self.mesh = None;
        self.mesh_positions.clear();
        self.fit_scene();
        self.render()
    }

    /// Whether the input points are drawn over the mesh as well (default true), so the fit
    /// to them can be judged; without a mesh they always show.
    #[wasm_bindgen(js_name = setPointsOverlay)]
    pub fn set_points_overlay(&mut self, on: bool) -> Result<(), JsError> {
        self.points_over_mesh = on;
        self.render()
    }

    /// Turns the view by `dx`, `dy` radians.
    pub fn orbit(&mut self, dx: f32, dy: f32) -> Result<(), JsError> {
        self.camera.orbit(dx, dy);
        self.render()
    }

    /// Pans by `dx`, `dy` pixels of the canvas.
    pub fn pan(&mut self, dx: f32, dy: f32) -> Result<(), JsError> {
        let h = self.config.height as f32;
        self.camera.pan(dx / h, dy / h);
        self.render()
    }

    /// Zooms in by `factor` > 1, out by `factor` < 1.
    pub fn zoom(&mut self, factor: f32) -> Result<(), JsError> {
        self.camera.zoom(factor);
        self.render()
    }

    /// Fits the mesh (or the points, before there is a mesh) to the view.
    pub fn fit(&mut self) -> Result<(), JsError> {
        self.fit_scene();
        self.render()
    }

    /// Draws a frame.
    pub fn render(&mut self) -> Result<(), JsError> {
        let frame = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(f)
            | wgpu::CurrentSurfaceTexture::Suboptimal(f) => f,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                // The canvas was resized or its context lost: configure again, draw next time.
                self.surface.configure(&self.device, &self.config);
                return Ok(());
            }
            // No frame this time (a timeout, a hidden canvas, a validation error).
            _ => {
                return Err(JsError::new(
                    "no frame to draw into: the canvas surface gave none",
                ));
            }
        };
        let (w, h) = (self.config.width as f32, self.config.height as f32);
        let view_proj = self.camera.view_proj(w / h);
        let mut uniform = view_proj.to_cols_array().to_vec();
        let key = self.camera.key_light();
        let eye = (self.camera.eye() - self.camera.target).normalize_or(Vec3::Z);
        let has_mesh = if self.mesh.is_some() { 1.0 } else { 0.0 };
        uniform.extend_from_slice(&[key.x, key.y, key.z, has_mesh]);
        uniform.extend_from_slice(&[eye.x, eye.y, eye.z, 0.0, w, h, POINT_SIZE, WIRE_WIDTH]);
        self.queue
            .write_buffer(&self.view_buffer, 0, f32_bytes(&uniform));

        let target = frame.texture.create_view(&Default::default());
        let mut encoder = self.device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("viewer"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &target,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::WHITE),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &self.depth,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, &self.view_group, &[]);
            if let Some((buffer, count)) = &self.mesh {
                pass.set_pipeline(&self.mesh_pipeline);
                pass.set_vertex_buffer(0, buffer.slice(..));
                pass.draw(0..*count, 0..1);
            }
            if let Some((buffer, count)) = &self.points
                && (self.mesh.is_none() || self.points_over_mesh)
            {
                // Depth-tested: points behind the mesh stay hidden (the 2D viewer, without a
                // depth buffer, draws them all on top).
                pass.set_pipeline(&self.point_pipeline);
                pass.set_vertex_buffer(0, buffer.slice(..));
                pass.draw(0..6, 0..*count);
            }
        }
        self.queue.submit([encoder.finish()]);
        self.queue.present(frame);
        Ok(())
    }
}

fn depth_view(device: &wgpu::Device, width: u32, height: u32) -> wgpu::TextureView {
    device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some("depth"),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        })
        .create_view(&Default::default())
}

fn f32_bytes(data: &[f32]) -> &[u8] {
    // SAFETY: f32 has no padding and any byte pattern is a valid u8.
    unsafe { std::slice::from_raw_parts(data.as_ptr().cast(), std::mem::size_of_val(data)) }
}
