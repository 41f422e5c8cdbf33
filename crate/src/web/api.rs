//! The browser API (wasm-bindgen, feature `web` on wasm32): load the shipped weights from
//! bytes, generate a mesh from points on WebGPU (or Burn's CPU backend inside wasm, said
//! plainly through [`MeshFlow::backend`]), and write GLB / OBJ. Every failure is a JS
//! exception with a message; a panic hook reports the unexpected in the console.
//!
//! Three modules are built from this file (scripts/build-web.sh): with feature `wgpu` (WebGPU
//! and the wgpu viewer), without it (the CPU alone, for the machines where the CPU path is the
//! faster one anyway), and the CPU alone with feature `threads` (rayon's pool on Web Workers,
//! for cross-origin isolated pages: `initThreadPool` below).
//!
//! Generation drives the same stages as the CLI ([`crate::pipeline::generate::Generator`]) but reads
//! back asynchronously, and waits for the GPU after every Euler step, so the page can show
//! real progress and cancel between steps. On the CPU, several workers (each its own module)
//! can draw runs of the candidates side by side ([`MeshFlow::generate_candidates`]) and one
//! keeps the best ([`MeshFlow::keep_candidates`]): wasm has no threads without cross-origin
//! isolation, and the candidates need no shared memory. With it, the threaded module runs
//! them all on its pool instead.

/// Burn's WebGPU instance, adapter, device and queue, shared with the viewer; nothing in the
/// CPU-only module.
#[cfg(feature = "wgpu")]
type GpuSetup = burn::tensor::wgpu::WgpuSetup;
#[cfg(not(feature = "wgpu"))]
type GpuSetup = ();
use burn::tensor::{Device, Tensor, TensorData};
use glam::Vec3;
use wasm_bindgen::prelude::*;
use web_time::Instant;

use crate::io::{Format, Limits, read_bytes, write_glb, write_obj};
use crate::model::sampler::step;
use crate::model::schedule::step_times;
#[cfg(not(feature = "threads"))]
use crate::model::{add_pair_corrections, spacetime_distances};
#[cfg(feature = "cpu")]
use crate::pipeline::generate::check_samples;
#[cfg(feature = "threads")]
use crate::pipeline::generate::runs_side_by_side;
#[cfg(not(feature = "threads"))]
use crate::pipeline::generate::{DecodedHost, DeviceEdges, HostEdges, kept_slots, read_bits};
use crate::pipeline::generate::{
    GenerateOptions, Generated, Generator, Prepared, input_points, keep_sharpened,
};
use crate::pipeline::shipped::ShippedModels;
#[cfg(any(feature = "wgpu", feature = "webgl"))]
use crate::web::viewer::Viewer;

/// Starts rayon's pool on `n` Web Workers sharing this module's memory (the threaded CPU
/// module only, in a cross-origin isolated page): `await initThreadPool(n)` once after the
/// module is initialised, before the first generation. wasm-bindgen-rayon's, re-exported
/// rather than a pool of our own: it is what the ecosystem uses for rayon on the web.
#[cfg(feature = "threads")]
pub use wasm_bindgen_rayon::init_thread_pool;

#[wasm_bindgen(start)]
fn start() {
    console_error_panic_hook::set_once();
}

fn js_error(e: impl std::fmt::Display) -> JsError {
    JsError::new(&e.to_string())
}

/// What a thrown JS value says: an Error's message, a string itself, else its type.
fn js_message(e: &JsValue) -> String {
    if let Some(error) = e.dyn_ref::<js_sys::Error>() {
        return error.message().into();
    }
    e.as_string()
        .unwrap_or_else(|| format!("a thrown {}", e.js_typeof().as_string().unwrap_or_default()))
}

/// The loaded models and the device they run on.
#[wasm_bindgen]
pub struct MeshFlow {
    models: ShippedModels,
    device: Device,
    backend: String,
    /// Set on WebGPU.
    #[cfg_attr(not(feature = "wgpu"), allow(dead_code))]
    setup: Option<GpuSetup>,
}

/// The WebGPU device and its wgpu handles, or why there is none.
#[cfg(feature = "wgpu")]
async fn webgpu() -> Result<(Device, GpuSetup), String> {
    Device::wgpu_options()
        .init_with_setup_async()
        .await
        .map_err(|e| format!("no WebGPU adapter: {e}"))
}

/// The CPU-only module has no WebGPU to open.
#[cfg(not(feature = "wgpu"))]
async fn webgpu() -> Result<(Device, GpuSetup), String> {
    Err("this is the CPU-only module (meshflow_cpu.js); WebGPU is in meshflow.js".into())
}

#[wasm_bindgen]
impl MeshFlow {
    /// Loads the VAE and DiT from their manifests (JSON text) and safetensors bytes, checking
    /// sha256, that the DiT belongs to this VAE, and every tensor's name and shape.
    /// `backend`: `"webgpu"` (fails without an adapter, and always in the CPU-only module),
    /// `"cpu"` (fails in the WebGPU module, which leaves the CPU path to meshflow_cpu), or
    /// `"auto"` (WebGPU when this module has it and an adapter exists, else the CPU where this
    /// module has it; read [`Self::backend`] to say which).
    pub async fn load(
        vae_manifest: String,
        vae_weights: Vec<u8>,
        dit_manifest: String,
        dit_weights: Vec<u8>,
        backend: String,
    ) -> Result<MeshFlow, JsError> {
        let ((device, setup), backend) = match backend.as_str() {
            "webgpu" => {
                let (d, s) = webgpu().await.map_err(js_error)?;
                ((d, Some(s)), "webgpu")
            }
            "cpu" => ((crate::device::cpu().map_err(js_error)?, None), "cpu"),
            "auto" => match webgpu().await {
                Ok((d, s)) => ((d, Some(s)), "webgpu"),
                Err(gpu) => {
                    let cpu = crate::device::cpu()
                        .map_err(|cpu| js_error(format!("{gpu}; and {cpu}")))?;
                    ((cpu, None), "cpu")
                }
            },
            other => {
                return Err(js_error(format!(
                    "unknown backend \"{other}\": expected \"webgpu\", \"cpu\" or \"auto\""
                )));
            }
        };
        let models = ShippedModels::from_bytes(
            vae_manifest.as_bytes(),
            &vae_weights,
            dit_manifest.as_bytes(),
            &dit_weights,
            &device,
        )
        .map_err(js_error)?;
        Ok(MeshFlow {
            models,
            device,
            backend: backend.into(),
            setup,
        })
    }

    /// A wgpu viewer drawing into `canvas` (an `OffscreenCanvas`) on this model's WebGPU
    /// device: a promise of the [`Viewer`], as in the CPU module.
    #[cfg(feature = "wgpu")]
    #[wasm_bindgen(js_name = createViewer)]
    pub fn create_viewer(&self, canvas: web_sys::OffscreenCanvas) -> js_sys::Promise {
        let viewer = self
            .setup
            .as_ref()
            .ok_or_else(|| String::from("the wgpu viewer needs the WebGPU backend"))
            .and_then(|setup| Viewer::on_webgpu(setup, canvas));
        match viewer {
            Ok(v) => js_sys::Promise::resolve(&JsValue::from(v)),
            Err(e) => js_sys::Promise::reject(&js_error(e).into()),
        }
    }

    /// The CPU module's viewer: wgpu on a WebGL2 context of its own in `canvas` (an
    /// `OffscreenCanvas`), the same renderer as on WebGPU. A promise of the [`Viewer`],
    /// rejected where the browser gives no WebGL2 context (the page then draws in 2D).
    #[cfg(all(feature = "webgl", not(feature = "wgpu")))]
    #[wasm_bindgen(js_name = createViewer)]
    pub fn create_viewer(&self, canvas: web_sys::OffscreenCanvas) -> js_sys::Promise {
        wasm_bindgen_futures::future_to_promise(async move {
            Viewer::on_webgl2(canvas)
                .await
                .map(JsValue::from)
                .map_err(|e| js_error(e).into())
        })
    }

    /// A CPU module built without feature `webgl` has no viewer: a rejected promise (the
    /// page draws with its 2D-canvas viewer instead).
    #[cfg(not(any(feature = "wgpu", feature = "webgl")))]
    #[wasm_bindgen(js_name = createViewer)]
    pub fn create_viewer(&self, _canvas: web_sys::OffscreenCanvas) -> js_sys::Promise {
        js_sys::Promise::reject(
            &js_error("this CPU module was built without its WebGL2 viewer (feature `webgl`)")
                .into(),
        )
    }

    /// Destroys the WebGPU device, as a GPU reset or driver crash would: every later use
    /// fails. For testing the page's fallback to the CPU path; nothing on the CPU backend.
    #[wasm_bindgen(js_name = destroyDevice)]
    pub fn destroy_device(&self) {
        #[cfg(feature = "wgpu")]
        if let Some(setup) = &self.setup {
            setup.device.destroy();
        }
    }

    /// `"webgpu"` or `"cpu"`.
    #[wasm_bindgen(getter)]
    pub fn backend(&self) -> String {
        self.backend.clone()
    }

    /// The most vertices one generation can make (the VAE's N).
    #[wasm_bindgen(getter, js_name = maxVertices)]
    pub fn max_vertices(&self) -> usize {
        self.models.vae_manifest.model.num_vertices
    }

    /// Candidates drawn when the options do not say how many ([`GenerateOptions::samples`]).
    #[wasm_bindgen(getter, js_name = defaultSamples)]
    pub fn default_samples(&self) -> usize {
        GenerateOptions::default().samples
    }

    fn generator(&self) -> Generator<'_> {
        self.models.generator(&self.device)
    }

    /// Generates a mesh from `points` (x, y, z, ... in any frame). `options` is JSON:
    /// `{"vertices": 300, "steps": 4, "samples": 12, "seed": 0, "schedule": "to-zero",
    /// "solver": "midpoint"}`, each optional (the defaults of [`GenerateOptions`]).
    /// `on_step(step, steps)` is called after every step once the GPU has finished it;
    /// returning `false` cancels (the promise rejects with a "cancelled" message).
    pub async fn generate(
        &self,
        points: Vec<f32>,
        options: String,
        on_step: Option<js_sys::Function>,
    ) -> Result<GeneratedMesh, JsError> {
        let points = xyz(&points)?;
        let opts = parse_options(&options)?;
        let candidates = self
            .candidates(&points, &opts, 0, opts.samples, on_step)
            .await?;
        Ok(GeneratedMesh::kept(candidates, &points, &opts))
    }

    /// Candidates `first..first + count` of [`Self::generate`]'s `options.samples` for
    /// `points`, unsharpened, as bytes for [`Self::keep_candidates`]: several workers, each
    /// with its own module, draw runs of them side by side. Candidate `j` is seeded by
    /// `candidate_seed(seed, j)` in whichever run it is drawn, and a batch's rows do not
    /// depend on each other (crate/tests/candidate_split.rs), so the runs together are the
    /// candidates that [`Self::generate`] draws at once.
    ///
    /// In the CPU module only (the WebGPU module's one device draws every candidate).
    #[cfg(feature = "cpu")]
    #[wasm_bindgen(js_name = generateCandidates)]
    pub async fn generate_candidates(
        &self,
        points: Vec<f32>,
        options: String,
        first: usize,
        count: usize,
        on_step: Option<js_sys::Function>,
    ) -> Result<Vec<u8>, JsError> {
        let points = xyz(&points)?;
        let opts = parse_options(&options)?;
        check_samples(opts.samples).map_err(js_error)?;
        if count == 0 || first + count > opts.samples {
            return Err(js_error(format!(
                "candidates {first}..{} are not among the {} asked for",
                first + count,
                opts.samples
            )));
        }
        let candidates = self
            .candidates(&points, &opts, first, count, on_step)
            .await?;
        postcard::to_allocvec(&candidates).map_err(js_error)
    }

    /// The mesh [`Self::generate`] makes, from its candidates drawn in runs by
    /// [`Self::generate_candidates`] (`parts`: their bytes in the order of `first`, together
    /// all `options.samples` of them): the one kept, sharpened.
    /// In the CPU module only.
    #[cfg(feature = "cpu")]
    #[wasm_bindgen(js_name = keepCandidates)]
    pub fn keep_candidates(
        &self,
        points: Vec<f32>,
        options: String,
        parts: Vec<js_sys::Uint8Array>,
    ) -> Result<GeneratedMesh, JsError> {
        let points = xyz(&points)?;
        let opts = parse_options(&options)?;
        check_samples(opts.samples).map_err(js_error)?;
        let mut candidates: Vec<Generated> = Vec::with_capacity(opts.samples);
        for part in parts {
            let run: Vec<Generated> = postcard::from_bytes(&part.to_vec())
                .map_err(|e| js_error(format!("not the bytes of generateCandidates: {e}")))?;
            candidates.extend(run);
        }
        if candidates.len() != opts.samples {
            return Err(js_error(format!(
                "{} candidates were given where {} were asked for",
                candidates.len(),
                opts.samples
            )));
        }
        Ok(GeneratedMesh::kept(candidates, &points, &opts))
    }

    /// Candidates `first..first + count` of `opts.samples`, one batch row each, seeded as
    /// [`Generator::generate`] seeds them (`candidate_seed(opts.seed, first + row)`): stages 1
    /// to 5 with asynchronous readback. In the threaded module the rows are drawn in one run
    /// per thread, the runs' sampler steps side by side (as `meshflow generate` draws them
    /// natively); rows do not depend on their batch, so the candidates are the same.
    async fn candidates(
        &self,
        points: &[Vec3],
        opts: &GenerateOptions,
        first: usize,
        count: usize,
        on_step: Option<js_sys::Function>,
    ) -> Result<Vec<Generated>, JsError> {
        let generator = self.generator();
        // Each run as a batch of its own: its rows seeded by their candidate index.
        let first_counts = candidate_runs(first, count);
        let runs: Vec<GenerateOptions> = (first_counts.iter())
            .map(|&(_, run_count)| GenerateOptions {
                samples: run_count,
                ..opts.clone()
            })
            .collect();
        let prepared = generator
            .prepare_runs(points, opts, &first_counts)
            .map_err(js_error)?;

        let started = Instant::now();
        let times = step_times(opts.steps, opts.schedule);
        let mut xs: Vec<Tensor<3>> = prepared.iter().map(|p| p.noise.clone()).collect();
        for i in 0..opts.steps {
            xs = self.step_runs(xs, &prepared, opts, times[i], times[i + 1]);
            // Wait for this step on the device (one value back), then let the event loop run.
            read(xs[0].clone().slice([0..1, 0..1, 0..1])).await?;
            yield_to_event_loop().await;
            if let Some(f) = &on_step {
                let go = f
                    .call2(&JsValue::NULL, &(i + 1).into(), &opts.steps.into())
                    .map_err(|e| js_error(format!("on_step threw: {}", js_message(&e))))?;
                if go == JsValue::FALSE {
                    return Err(js_error(format!(
                        "sampling was cancelled after {} of {} steps",
                        i + 1,
                        opts.steps
                    )));
                }
            }
        }
        let sample_s = started.elapsed().as_secs_f64();

        self.decode_runs(&generator, prepared, xs, &runs, sample_s)
            .await
    }

    /// Stages 3 to 5 of the runs sampled to `xs` (their sampler's time `sample_s`), in the
    /// threaded module side by side on rayon's threads, as natively: the CPU backend's
    /// readback needs no waiting.
    #[cfg(feature = "threads")]
    async fn decode_runs(
        &self,
        generator: &Generator<'_>,
        prepared: Vec<Prepared>,
        xs: Vec<Tensor<3>>,
        runs: &[GenerateOptions],
        sample_s: f64,
    ) -> Result<Vec<Generated>, JsError> {
        let items: Vec<_> = prepared.into_iter().zip(xs).zip(runs).collect();
        let outs = crate::parallel::map_in_parallel(items, |_, ((mut prepared, x), run)| {
            prepared.times.sample_s = sample_s;
            generator.decode_and_extract(prepared, x, run)
        });
        runs_side_by_side(outs).map_err(js_error)
    }

    /// Stages 3 to 5 of the runs sampled to `xs` (their sampler's time `sample_s`), one run
    /// after the other, with asynchronous readback (which the WebGPU module's device needs).
    #[cfg(not(feature = "threads"))]
    async fn decode_runs(
        &self,
        generator: &Generator<'_>,
        prepared: Vec<Prepared>,
        xs: Vec<Tensor<3>>,
        runs: &[GenerateOptions],
        sample_s: f64,
    ) -> Result<Vec<Generated>, JsError> {
        let mut candidates = Vec::new();
        for ((mut prepared, x), run) in prepared.into_iter().zip(xs).zip(runs) {
            prepared.times.sample_s = sample_s;
            candidates.extend(self.decode_run(generator, prepared, x, run).await?);
        }
        Ok(candidates)
    }

    /// One sampler step of every run: side by side on rayon's threads in the threaded module,
    /// in turn elsewhere (where there is one run).
    fn step_runs(
        &self,
        xs: Vec<Tensor<3>>,
        prepared: &[Prepared],
        opts: &GenerateOptions,
        t: f32,
        t_next: f32,
    ) -> Vec<Tensor<3>> {
        let dit = &self.models.dit;
        let one = |(r, x): (usize, Tensor<3>)| {
            let p = &prepared[r];
            step(dit, opts.solver, x, t, t_next, p.cond.clone(), &p.condition)
        };
        // Every run on the pool's threads, none on this one, which is outside the pool.
        #[cfg(feature = "threads")]
        return crate::parallel::map_in_parallel(xs.into_iter().enumerate().collect(), |_, x| {
            one(x)
        });
        #[cfg(not(feature = "threads"))]
        xs.into_iter().enumerate().map(one).collect()
    }

    /// Stages 3 to 5 of one run of candidates sampled to `x`, with asynchronous readback.
    #[cfg(not(feature = "threads"))]
    async fn decode_run(
        &self,
        generator: &Generator<'_>,
        mut prepared: Prepared,
        x: Tensor<3>,
        opts: &GenerateOptions,
    ) -> Result<Vec<Generated>, JsError> {
        let started = Instant::now();
        let out = generator.decode(x, &opts.extract);
        let mask_logits = read(out.mask_logits).await?;
        let edges = match out.edges {
            DeviceEdges::Embeddings(t) => HostEdges::Embeddings(read(t).await?),
            DeviceEdges::Bits(t) => {
                HostEdges::Bits(read_bits(t.into_data_async().await).map_err(js_error)?)
            }
            DeviceEdges::PairHead {
                embeddings,
                features,
            } => {
                // MeshVae::edge_distances with asynchronous readbacks, refined on the host.
                let distances = spacetime_distances(embeddings);
                let mut host = read(distances.clone()).await?;
                let kept = kept_slots(&mask_logits, prepared.slots);
                if let Some(pairs) = self
                    .models
                    .vae
                    .pair_corrections(distances, &host, features, &kept)
                {
                    let corrections = read(pairs.corrections.unsqueeze()).await?;
                    add_pair_corrections(&mut host, prepared.slots, &pairs.pairs, &corrections);
                }
                HostEdges::Distances(host)
            }
        };
        let host = DecodedHost {
            mask_logits,
            positions: read(out.positions).await?,
            normals: read(out.normals).await?,
            edges,
        };
        prepared.times.decode_s = started.elapsed().as_secs_f64();
        generator.extract(prepared, &host, opts).map_err(js_error)
    }
}

/// The runs `(first, count)` that candidates `first..first + count` are drawn in: one per
/// thread of the threaded module's pool (contiguous, the first ones one longer), one
/// elsewhere.
fn candidate_runs(first: usize, count: usize) -> Vec<(usize, usize)> {
    #[cfg(feature = "threads")]
    let parts = crate::parallel::threads();
    #[cfg(not(feature = "threads"))]
    let parts = 1;
    let mut next = first;
    (crate::parallel::run_lengths(count, parts).into_iter())
        .map(|n| {
            next += n;
            (next - n, n)
        })
        .collect()
}

/// `points` as x, y, z triples.
fn xyz(points: &[f32]) -> Result<Vec<Vec3>, JsError> {
    if !points.len().is_multiple_of(3) {
        return Err(js_error(format!(
            "points must be x, y, z triples; got {} numbers",
            points.len()
        )));
    }
    Ok(points.chunks_exact(3).map(Vec3::from_slice).collect())
}

/// [`GenerateOptions`] from JSON (empty: the defaults).
fn parse_options(options: &str) -> Result<GenerateOptions, JsError> {
    if options.trim().is_empty() {
        return Ok(GenerateOptions::default());
    }
    serde_json::from_str(options).map_err(|e| js_error(format!("options: {e}")))
}

async fn read(t: Tensor<3>) -> Result<Vec<f32>, JsError> {
    let data: TensorData = t
        .into_data_async()
        .await
        .map_err(|e| js_error(format!("reading back from the device failed: {e}")))?;
    data.convert::<f32>()
        .try_into_vec::<f32>()
        .map_err(|e| js_error(format!("reading back from the device failed: {e}")))
}

/// Resolves on a later macrotask (`setTimeout(0)`), so input and messages are handled
/// between sampling steps even on the CPU backend.
async fn yield_to_event_loop() {
    let promise = js_sys::Promise::new(&mut |resolve, _| {
        let global = js_sys::global();
        if let Ok(set_timeout) = js_sys::Reflect::get(&global, &"setTimeout".into())
            && let Ok(set_timeout) = set_timeout.dyn_into::<js_sys::Function>()
            && set_timeout.call2(&global, &resolve, &0.into()).is_ok()
        {
            return;
        }
        let _ = resolve.call0(&JsValue::NULL);
    });
    let _ = wasm_bindgen_futures::JsFuture::from(promise).await;
}

/// One generated mesh (in the input's frame) and its report.
#[wasm_bindgen]
pub struct GeneratedMesh {
    generated: Generated,
    /// Candidates drawn; this is the one kept.
    samples: usize,
}

impl GeneratedMesh {
    /// The candidate kept from all `opts.samples` of them, sharpened against `points`.
    fn kept(candidates: Vec<Generated>, points: &[Vec3], opts: &GenerateOptions) -> Self {
        let keep = || keep_sharpened(candidates, points, opts);
        // Sharpening's parallel steps shared on the pool, not handed to it one by one.
        #[cfg(feature = "threads")]
        let generated = crate::parallel::on_pool(keep);
        #[cfg(not(feature = "threads"))]
        let generated = keep();
        Self {
            generated,
            samples: opts.samples,
        }
    }
}

#[wasm_bindgen]
impl GeneratedMesh {
    /// x, y, z per vertex.
    #[wasm_bindgen(getter)]
    pub fn positions(&self) -> Vec<f32> {
        self.generated
            .mesh
            .positions
            .iter()
            .flat_map(|p| p.to_array())
            .collect()
    }

    /// Area-weighted unit vertex normals, x, y, z per vertex.
    #[wasm_bindgen(getter)]
    pub fn normals(&self) -> Vec<f32> {
        let m = &self.generated.mesh;
        crate::geometry::normals::vertex_normals(&m.positions, &m.faces)
            .iter()
            .flat_map(|n| n.to_array())
            .collect()
    }

    /// Three vertex indices per triangle.
    #[wasm_bindgen(getter)]
    pub fn indices(&self) -> Vec<u32> {
        self.generated
            .mesh
            .faces
            .iter()
            .flatten()
            .copied()
            .collect()
    }

    /// JSON: `vertexBudget`, `samples` (candidates drawn, one kept), `times` (seconds per
    /// stage), `topology`, `extract`, `close` (the holes closed and left open), `sharpen` (what
    /// sharpening did).
    #[wasm_bindgen(getter)]
    pub fn report(&self) -> String {
        let g = &self.generated;
        serde_json::json!({
            "vertexBudget": g.vertex_budget,
            "samples": self.samples,
            "features": g.features,
            "times": g.times,
            "topology": g.topology,
            "extract": g.extract,
            "close": g.close,
            "sharpen": g.sharpen,
        })
        .to_string()
    }

    /// The mesh as binary glTF.
    #[wasm_bindgen(js_name = toGlb)]
    pub fn to_glb(&self) -> Vec<u8> {
        write_glb(&self.generated.mesh)
    }

    /// The mesh as Wavefront OBJ text.
    #[wasm_bindgen(js_name = toObj)]
    pub fn to_obj(&self) -> String {
        write_obj(&self.generated.mesh)
    }
}

/// The points [`read_input`] found in a file, and what they stand for.
#[wasm_bindgen]
pub struct InputPoints {
    points: Vec<f32>,
    source_points: usize,
    from_mesh: bool,
}

#[wasm_bindgen]
impl InputPoints {
    /// x, y, z of the points to condition on.
    #[wasm_bindgen(getter)]
    pub fn points(&self) -> Vec<f32> {
        self.points.clone()
    }

    /// The file's own point (vertex) count: more than [`Self::points`] holds when a large
    /// point cloud was subsampled.
    #[wasm_bindgen(getter, js_name = sourcePoints)]
    pub fn source_points(&self) -> usize {
        self.source_points
    }

    /// Whether the file was a mesh (its surface sampled) rather than a point cloud.
    #[wasm_bindgen(getter, js_name = fromMesh)]
    pub fn from_mesh(&self) -> bool {
        self.from_mesh
    }
}

/// Reads a point cloud or mesh file (PLY, OBJ, STL, GLB/glTF, XYZ and the CLI's other
/// formats; the format comes from `file_name`'s extension, else from the bytes) into the
/// points to condition on: a mesh's surface samples, or a point cloud's points (an even random
/// subsample of [`crate::pipeline::generate::CONDITION_POINTS`] when there are more, as the CLI does).
#[wasm_bindgen(js_name = readInput)]
pub fn read_input(bytes: &[u8], file_name: &str) -> Result<InputPoints, JsError> {
    let format = Format::from_path(std::path::Path::new(file_name))
        .or_else(|| Format::sniff(bytes))
        .ok_or_else(|| {
            js_error(format!(
                "{file_name}: not a supported mesh or point-cloud format"
            ))
        })?;
    let mesh = read_bytes(bytes, format, &Limits::default())
        .map_err(|e| js_error(format!("{file_name}: {e}")))?;
    let points = input_points(&mesh, 0).map_err(|e| js_error(format!("{file_name}: {e}")))?;
    Ok(InputPoints {
        points: points.iter().flat_map(|p| p.to_array()).collect(),
        source_points: mesh.positions.len(),
        from_mesh: !mesh.faces.is_empty(),
    })
}
