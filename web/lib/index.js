// MeshFlow in the browser: load the shipped weights, generate a mesh from a point cloud on
// WebGPU (or the CPU inside wasm where that is faster: no adapter, or a software one), export
// GLB / OBJ.
//
//   import { loadModel, readPoints } from 'meshflow';
//   const model = await loadModel({ onProgress: (got, total) => {} });
//   const points = await readPoints(bytes, 'scan.ply');
//   const mesh = await model.generate(points, { samples: 12, onStep: (i, n) => {} });
//   const glb = mesh.toGlb();
//
// Three wasm modules: meshflow_cpu (the CPU path, about a fifth of the bytes), the same with
// threads, meshflow_cpu_threads (for cross-origin isolated pages: rayon on Web Workers sharing
// its memory), and meshflow (WebGPU alone). Only the one the chosen backend needs is
// downloaded; a CPU one also where WebGPU fails to start.

import { MAX_HELPERS, generateSideBySide, startHelpers } from './candidates.js';

const FILES = ['vae.manifest.json', 'vae.safetensors', 'dit.manifest.json', 'dit.safetensors'];
const CACHE = 'meshflow-weights-v1';

const MODULES = {
  cpu: () => import('../pkg/meshflow_cpu.js'),
  'cpu-threads': () => import('../pkg/meshflow_cpu_threads.js'),
  webgpu: () => import('../pkg/meshflow.js'),
};
const loaded = {};
// The module readInput and wasmMemoryBytes use: the last one initialised.
let current = null;

/**
 * Instantiates one of the wasm modules once and returns its exports: `'cpu'` (meshflow_cpu,
 * the CPU path), `'cpu-threads'` (meshflow_cpu_threads: the CPU path on threads, in a
 * cross-origin isolated context only; start its pool with `glue.initThreadPool(n)`) or
 * `'webgpu'` (meshflow: WebGPU only). `wasmUrl`: where its `_bg.wasm` is (default: beside the
 * JS glue).
 */
export function initWasm(which = 'cpu', wasmUrl) {
  if (!MODULES[which]) throw new TypeError(`initWasm: which must be 'cpu', 'cpu-threads' or 'webgpu', got ${JSON.stringify(which)}`);
  loaded[which] ??= MODULES[which]().then(async (glue) => {
    const instance = await glue.default(wasmUrl ? { module_or_path: wasmUrl } : undefined);
    return { glue, memory: instance.memory };
  });
  current = loaded[which];
  return loaded[which];
}

/** The module already in use, else the small CPU one. */
function anyWasm() {
  return current ?? initWasm('cpu');
}

async function fetchBytes(url, onBytes) {
  const response = await fetch(url);
  if (!response.ok) throw new Error(`${url}: HTTP ${response.status}`);
  const reader = response.body.getReader();
  const chunks = [];
  let got = 0;
  for (;;) {
    const { done, value } = await reader.read();
    if (done) break;
    chunks.push(value);
    got += value.length;
    onBytes(value.length);
  }
  const bytes = new Uint8Array(got);
  let at = 0;
  for (const c of chunks) {
    bytes.set(c, at);
    at += c.length;
  }
  return bytes;
}

/**
 * Fetches the four weight files from `baseUrl`, reporting `onProgress(bytesSoFar, totalBytes)`
 * and keeping them in Cache Storage (when the page may use it) so a reload does not download
 * again. Returns `{ files, fromCache }`.
 */
export async function fetchWeights(baseUrl, { onProgress = () => {}, useCache = true } = {}) {
  const urls = FILES.map((f) => new URL(f, baseUrl).href);
  const cache = useCache && globalThis.caches ? await caches.open(CACHE) : null;
  const cached = cache ? await Promise.all(urls.map((u) => cache.match(u))) : urls.map(() => undefined);
  if (cached.every(Boolean)) {
    const files = await Promise.all(cached.map(async (r) => new Uint8Array(await r.arrayBuffer())));
    const total = files.reduce((s, f) => s + f.length, 0);
    onProgress(total, total);
    return { files, fromCache: true };
  }
  const sizes = await Promise.all(
    urls.map(async (u) => Number((await fetch(u, { method: 'HEAD' })).headers.get('content-length')) || 0),
  );
  const total = sizes.reduce((a, b) => a + b, 0);
  let got = 0;
  const files = [];
  for (const url of urls) {
    files.push(await fetchBytes(url, (n) => onProgress((got += n), total)));
  }
  if (cache) await Promise.all(urls.map((u, i) => cache.put(u, new Response(files[i]))));
  return { files, fromCache: false };
}

/** Forgets the cached weights (e.g. after a checksum failure). */
export async function clearWeightsCache() {
  if (globalThis.caches) await caches.delete(CACHE);
}

// Adapters that are software renderers: on them the CPU path inside wasm is far faster (a
// generation took 166 s on SwiftShader against 6.5 s on the CPU path,
// docs/experiments/2026-11-22-browser-first-timing.md).
const SOFTWARE_ADAPTER = /swiftshader|llvmpipe|lavapipe|softpipe|software|basic render|\bwarp\b/i;
// Vendors whose adapters are real GPUs.
const GPU_VENDOR = /nvidia|\bamd\b|\bati\b|intel|apple|qualcomm|\barm\b|imagination|broadcom|samsung|mesa|microsoft|vivante/i;
// A 256^3 matrix product (16.8 M multiply-adds) after one warm-up dispatch: a few
// milliseconds on a GPU, about 150 ms on SwiftShader.
const PROBE_SIZE = 256;
const PROBE_LIMIT_MS = 40;

/** Times one dispatch of a PROBE_SIZE^3 matrix product on `adapter`, in milliseconds. */
export async function probeAdapter(adapter) {
  const device = await adapter.requestDevice();
  try {
    const n = PROBE_SIZE;
    const code = `
      @group(0) @binding(0) var<storage, read> a: array<f32>;
      @group(0) @binding(1) var<storage, read_write> c: array<f32>;
      @compute @workgroup_size(8, 8)
      fn main(@builtin(global_invocation_id) id: vec3<u32>) {
        var acc = 0.0;
        for (var k = 0u; k < ${n}u; k++) { acc += a[id.y * ${n}u + k] * a[k * ${n}u + id.x]; }
        c[id.y * ${n}u + id.x] = acc;
      }`;
    const bytes = n * n * 4;
    const a = device.createBuffer({ size: bytes, usage: GPUBufferUsage.STORAGE });
    const c = device.createBuffer({ size: bytes, usage: GPUBufferUsage.STORAGE });
    const pipeline = await device.createComputePipelineAsync({
      layout: 'auto',
      compute: { module: device.createShaderModule({ code }), entryPoint: 'main' },
    });
    const bindGroup = device.createBindGroup({
      layout: pipeline.getBindGroupLayout(0),
      entries: [{ binding: 0, resource: { buffer: a } }, { binding: 1, resource: { buffer: c } }],
    });
    const run = async () => {
      const encoder = device.createCommandEncoder();
      const pass = encoder.beginComputePass();
      pass.setPipeline(pipeline);
      pass.setBindGroup(0, bindGroup);
      pass.dispatchWorkgroups(n / 8, n / 8);
      pass.end();
      device.queue.submit([encoder.finish()]);
      await device.queue.onSubmittedWorkDone();
    };
    await run();
    const started = performance.now();
    await run();
    return performance.now() - started;
  } finally {
    device.destroy();
  }
}

/**
 * Which backend `'auto'` should use here, and why: `{ backend: 'webgpu' | 'cpu', reason,
 * adapter }`. No WebGPU or no adapter: the CPU. A fallback or software adapter (SwiftShader,
 * llvmpipe, lavapipe, WARP): the CPU, which is faster there. A known GPU vendor: WebGPU.
 * Otherwise a short timed probe ([`probeAdapter`]) decides. `gpu` (default `navigator.gpu`)
 * and `probe` can be replaced, e.g. in tests.
 */
export async function chooseBackend({ gpu = globalThis.navigator?.gpu, probe = probeAdapter } = {}) {
  if (!gpu) return { backend: 'cpu', reason: 'this browser has no WebGPU', adapter: null };
  let adapter = null;
  try {
    // Chromium on Linux can answer null to 'high-performance' and still give its one GPU to a
    // plain request (seen with an NVIDIA H200, bench/page_gpu): ask again without a preference.
    adapter = (await gpu.requestAdapter({ powerPreference: 'high-performance' })) ?? (await gpu.requestAdapter());
  } catch {
    adapter = null;
  }
  if (!adapter) return { backend: 'cpu', reason: 'no WebGPU adapter', adapter: null };
  const info = adapter.info ?? {};
  const name = [info.vendor, info.architecture, info.device, info.description].filter(Boolean).join(' ') || 'unnamed adapter';
  const described = { vendor: info.vendor ?? '', architecture: info.architecture ?? '', description: info.description ?? '' };
  if (info.isFallbackAdapter || adapter.isFallbackAdapter) {
    return { backend: 'cpu', reason: `the WebGPU adapter is a fallback adapter (${name}); the CPU path is faster`, adapter: described };
  }
  if (SOFTWARE_ADAPTER.test(name)) {
    return { backend: 'cpu', reason: `the WebGPU adapter is a software renderer (${name}); the CPU path is faster`, adapter: described };
  }
  if (GPU_VENDOR.test(info.vendor ?? '')) {
    return { backend: 'webgpu', reason: `GPU adapter (${name})`, adapter: described };
  }
  let ms;
  try {
    ms = await probe(adapter);
  } catch (e) {
    return { backend: 'cpu', reason: `the WebGPU probe failed on ${name} (${e?.message ?? e})`, adapter: described };
  }
  const timing = `${ms.toFixed(0)} ms for a ${PROBE_SIZE}^3 matrix product`;
  return ms > PROBE_LIMIT_MS
    ? { backend: 'cpu', reason: `the WebGPU adapter (${name}) is slow: ${timing}; the CPU path is faster`, adapter: described }
    : { backend: 'webgpu', reason: `the WebGPU adapter (${name}) is fast: ${timing}`, adapter: described };
}

/** A generated mesh: typed arrays, the report and exporters. */
export class GeneratedMesh {
  constructor(inner) {
    this.positions = new Float32Array(inner.positions);
    this.normals = new Float32Array(inner.normals);
    this.indices = new Uint32Array(inner.indices);
    this.report = JSON.parse(inner.report);
    this.#inner = inner;
  }
  #inner;
  /** Binary glTF bytes. */
  toGlb() {
    return this.#inner.toGlb();
  }
  /** Wavefront OBJ text. */
  toObj() {
    return this.#inner.toObj();
  }
}

/** Loaded models on a device. */
export class Model {
  constructor(inner, helpers = []) {
    this.#inner = inner;
    this.#helpers = helpers;
  }
  #inner;
  // Helper workers drawing candidates beside this module (web/lib/candidates.js).
  #helpers;
  /** Modules drawing a generation's candidates side by side: 1, or 1 + the helper workers. */
  get workers() {
    return 1 + this.#helpers.length;
  }
  /** Stops the helper workers (the model still generates, in this module alone). */
  terminate() {
    this.#helpers.forEach((h) => h.terminate());
    this.#helpers = [];
  }
  /** `'webgpu'` or `'cpu'`. */
  get backend() {
    return this.#inner.backend;
  }
  /**
   * Why this backend: `{ asked, reason, adapter }` (`asked` is the `backend` option; with
   * `'auto'`, `reason` is [`chooseBackend`]'s).
   */
  backendReport = null;
  /** The most vertices one generation makes. */
  get maxVertices() {
    return this.#inner.maxVertices;
  }
  /**
   * Destroys the WebGPU device, as a GPU reset would (every later generation fails). For
   * testing a page's fallback; nothing on the CPU backend.
   */
  destroyDevice() {
    this.#inner.destroyDevice();
  }
  /**
   * A promise of a wgpu viewer drawing into `canvas` (an OffscreenCanvas, e.g. from
   * `canvas.transferControlToOffscreen()`): on this model's WebGPU device, or on the CPU
   * backend through a WebGL2 context of its own (the same renderer). `setPoints`, `setMesh`,
   * `setPointsOverlay`, `orbit`, `pan`, `zoom`, `fit`, `render`; `api` says which draws.
   * Rejects where the canvas gives neither.
   */
  async createViewer(canvas) {
    return this.#inner.createViewer(canvas);
  }
  /**
   * Generates a mesh from `points` (Float32Array of x, y, z). Options: `vertices` or `faces`
   * (a face count to aim for; not both), `steps` (default 4), `solver` (`'midpoint'`, the
   * default, or `'heun'`: second order, two evaluations of the model a step; `'euler'`: one,
   * as the paper), `seed`, `extraction`
   * (`'manifold'`, the default: no edge with a third face, consistent winding; or `'paper'`:
   * the paper's Algorithm 1), `dropNonManifold` (with `'paper'` only: keep at most two faces
   * per edge), `fit` (default true: vertices moved onto the points and the surface completed
   * between them), `closeHoles` (default true: each hole left where the points go on is
   * closed by a patch that does not fold; with `fit` only), `sharpen` (default true: the kept
   * mesh made flat where the points are flat and creased where they crease, flat regions
   * merged into few faces; with the default extraction only), `samples` (default 12: candidates
   * drawn from different noise, in one batch or, on the CPU, in runs on the model's
   * [`workers`] side by side, the one kept lying closest to the points with each hole
   * counting against it; the same mesh either way; 1 to 16, each costs a generation), `onStep(step, steps)`,
   * `signal` (an AbortSignal: aborting cancels between steps and rejects).
   */
  async generate(points, { vertices, faces, steps, solver, seed, samples, extraction, dropNonManifold, fit = true, closeHoles = true, sharpen = true, onStep, signal } = {}) {
    if (vertices !== undefined && faces !== undefined) {
      throw new TypeError('ask for vertices or for faces, not both');
    }
    if (samples !== undefined && !(Number.isInteger(samples) && samples >= 1 && samples <= 16)) {
      throw new TypeError(`samples must be an integer from 1 to 16, got ${JSON.stringify(samples)}`);
    }
    if (typeof fit !== 'boolean') {
      throw new TypeError(`fit must be true or false, got ${JSON.stringify(fit)}`);
    }
    if (typeof closeHoles !== 'boolean') {
      throw new TypeError(`closeHoles must be true or false, got ${JSON.stringify(closeHoles)}`);
    }
    if (typeof sharpen !== 'boolean') {
      throw new TypeError(`sharpen must be true or false, got ${JSON.stringify(sharpen)}`);
    }
    if (solver !== undefined && !['euler', 'heun', 'midpoint'].includes(solver)) {
      throw new TypeError(`solver must be 'euler', 'heun' or 'midpoint', got ${JSON.stringify(solver)}`);
    }
    if (extraction !== undefined && extraction !== 'manifold' && extraction !== 'paper') {
      throw new TypeError(`extraction must be 'manifold' or 'paper', got ${JSON.stringify(extraction)}`);
    }
    if (dropNonManifold && extraction !== 'paper') {
      throw new TypeError("dropNonManifold applies to extraction: 'paper' only (the default 'manifold' output never has a non-manifold edge)");
    }
    const extract = { method: extraction ?? 'manifold', drop_non_manifold: !!dropNonManifold };
    const options = JSON.stringify({
      vertices,
      faces,
      steps,
      solver,
      seed,
      samples,
      extract,
      ...(fit ? {} : { fit: { iterations: 0 }, complete: { enabled: false } }),
      ...(closeHoles ? {} : { close: { enabled: false } }),
      ...(sharpen ? {} : { sharpen: { enabled: false } }),
    });
    const step = (i, n) => {
      onStep?.(i, n);
      return !signal?.aborted;
    };
    const candidates = samples ?? this.#inner.defaultSamples;
    if (this.#helpers.length === 0 || candidates === 1) {
      return new GeneratedMesh(await this.#inner.generate(points, options, step));
    }
    const lost = (helper, e) => {
      this.#helpers = this.#helpers.filter((h) => h !== helper);
      helper.terminate();
      this.backendReport.workers = this.workers;
      this.backendReport.workersReason = `a candidate worker failed (${e?.message ?? e}); ${describeWorkers(this.workers)}`;
    };
    return new GeneratedMesh(
      await generateSideBySide(this.#inner, this.#helpers, points, options, candidates, step, signal, lost),
    );
  }
}

// Threads the threaded module may start at most (rayon's pool; each a Web Worker sharing the
// module's memory, no copy of the models).
const MAX_THREADS = 64;
// The threaded module's pool: started once per page, as rayon's global pool cannot be rebuilt.
let threadPool = null;

/**
 * The threaded CPU module with its pool of `threads` workers started (once; a later call gets
 * the first call's pool): `{ glue, threads }`. Rejects where the context has no shared memory
 * or the pool will not start.
 */
async function startThreaded(threads, wasmUrl) {
  const { glue } = await initWasm('cpu-threads', wasmUrl);
  threadPool ??= glue.initThreadPool(threads).then(() => threads);
  return { glue, threads: await threadPool };
}

/**
 * The CPU module to run: the threaded one where the context is cross-origin isolated (shared
 * memory) and `threads` is above 0, else, or where it fails to start, the single-threaded one
 * (whose candidates helper workers then draw beside it). `{ glue, threads, why }`: `threads`
 * 0 and `why` saying why not, for the second.
 */
async function cpuModule(threads, wasmUrls) {
  let why;
  if (threads === 0) {
    why = 'threads: 0';
  } else if (!globalThis.crossOriginIsolated) {
    why = 'no threads: the page is not cross-origin isolated';
  } else {
    try {
      return { ...(await startThreaded(threads, wasmUrls['cpu-threads'])), why: null };
    } catch (e) {
      why = `the threaded module did not start (${e?.message ?? e})`;
    }
  }
  const { glue } = await initWasm('cpu', wasmUrls.cpu);
  return { glue, threads: 0, why };
}

/**
 * Loads the shipped models. `weights`: the folder URL holding vae.* and dit.* (default: the
 * package's `weights/`, the f16 files the CLI runs too, so the same input, options and seed give
 * the same mesh); `backend`: `'auto'` (the faster one here, see [`chooseBackend`]),
 * `'webgpu'` or `'cpu'`; `onProgress(bytes, total)` during the download. On the CPU path:
 * `threads`, the threads of the threaded module where the page is cross-origin isolated
 * (COOP `same-origin` and COEP `require-corp`; default one per core, at most 16; 0: never);
 * elsewhere (or with `threads: 0`) `workers`, how many single-threaded wasm modules draw a
 * generation's candidates side by side (default: one per core, at most 4; each beyond the
 * first is a worker with its own copy of the models, about 60 MB). The model's
 * `backendReport` says which backend runs and why, on how many threads or workers, and why.
 * `wasmUrls`: `{ cpu, 'cpu-threads', webgpu }`, where each module's `_bg.wasm` is.
 */
export async function loadModel({
  weights = new URL('../../weights/', import.meta.url),
  backend = 'auto',
  onProgress,
  useCache = true,
  wasmUrls = {},
  workers = defaultWorkers(),
  threads = defaultThreads(),
} = {}) {
  if (!['auto', 'webgpu', 'cpu'].includes(backend)) {
    throw new TypeError(`backend must be 'auto', 'webgpu' or 'cpu', got ${JSON.stringify(backend)}`);
  }
  if (!(Number.isInteger(workers) && workers >= 1 && workers <= 1 + MAX_HELPERS)) {
    throw new TypeError(`workers must be an integer from 1 to ${1 + MAX_HELPERS}, got ${JSON.stringify(workers)}`);
  }
  if (!(Number.isInteger(threads) && threads >= 0 && threads <= MAX_THREADS)) {
    throw new TypeError(`threads must be an integer from 0 to ${MAX_THREADS}, got ${JSON.stringify(threads)}`);
  }
  const choice = backend === 'auto' ? await chooseBackend() : { backend, reason: `asked for ${backend}`, adapter: null };
  const [chosen, { files, fromCache }] = await Promise.all([
    choice.backend === 'cpu' ? cpuModule(threads, wasmUrls) : initWasm('webgpu', wasmUrls.webgpu),
    fetchWeights(weights, { onProgress, useCache }),
  ]);
  const text = new TextDecoder();
  const load = (module, which) =>
    module.MeshFlow.load(text.decode(files[0]), files[1], text.decode(files[2]), files[3], which);
  // Without threads the CPU path draws candidates on helper workers too (one GPU serves a
  // WebGPU model); they load their copies while this module loads its own.
  const helpersFor = (cpu) => (cpu.threads ? null : startHelpers(workers - 1, files, wasmUrls.cpu));
  let cpu = choice.backend === 'cpu' ? chosen : null;
  let starting = cpu ? helpersFor(cpu) : null;
  try {
    let inner;
    let { reason } = choice;
    try {
      inner = await load(chosen.glue, choice.backend);
    } catch (e) {
      // 'auto' chose WebGPU but the device would not start: the CPU path still works. The
      // WebGPU module has no CPU backend (it would cost 7% of its bytes gzipped), so this
      // fetches a CPU module.
      if (backend !== 'auto' || choice.backend !== 'webgpu') throw e;
      cpu = await cpuModule(threads, wasmUrls);
      inner = await load(cpu.glue, 'cpu');
      reason = `WebGPU failed to start (${e?.message ?? e})`;
      starting = helpersFor(cpu);
    }
    let helpers = [];
    let workersReason = 'one module drives the GPU';
    if (cpu?.threads) {
      workersReason = `on ${cpu.threads} threads (the page is cross-origin isolated)`;
    } else if (starting) {
      const started = await starting;
      helpers = started.helpers;
      const drawing = describeWorkers(1 + helpers.length);
      workersReason = workers === 1
        ? `${drawing} (workers: 1)`
        : started.failed.length
          ? `${started.failed.length} of ${workers - 1} candidate workers did not start (${started.failed[0]}); ${drawing}`
          : drawing;
      workersReason += `; ${cpu.why}`;
    }
    const model = new Model(inner, helpers);
    model.backendReport = {
      asked: backend, reason, adapter: choice.adapter, workers: model.workers, threads: cpu?.threads ?? 0, workersReason,
    };
    model.weightsFromCache = fromCache;
    return model;
  } catch (e) {
    starting?.then(({ helpers }) => helpers.forEach((h) => h.terminate()));
    // A stale or damaged cache entry fails the checksum: drop it so the next load refetches.
    if (fromCache) await clearWeightsCache();
    throw e;
  }
}

/** Threads for the threaded module by default: one per core the browser reports, at most 16. */
function defaultThreads() {
  const cores = Number(globalThis.navigator?.hardwareConcurrency) || 1;
  return Math.max(1, Math.min(cores, 16));
}

/** Modules to draw candidates on by default: one per core the browser reports, at most 1 + MAX_HELPERS. */
function defaultWorkers() {
  const cores = Number(globalThis.navigator?.hardwareConcurrency) || 1;
  return Math.max(1, Math.min(cores, 1 + MAX_HELPERS));
}

/** What the backend report says of `n` modules drawing candidates. */
function describeWorkers(n) {
  return n === 1 ? 'one module draws every candidate' : `candidates drawn on ${n} workers side by side`;
}

/**
 * Reads a point cloud or mesh file (PLY, OBJ, STL, GLB/glTF, XYZ, ...) into the points to
 * condition on: `{ points, sourcePoints, fromMesh }`. A mesh is surface-sampled; a point cloud
 * larger than 4,096 points is evenly subsampled to 4,096 (`sourcePoints` is the file's count).
 * Throws an Error with a message for bad files.
 */
export async function readInput(bytes, fileName) {
  const { glue } = await anyWasm();
  const read = glue.readInput(bytes, fileName);
  try {
    return { points: new Float32Array(read.points), sourcePoints: read.sourcePoints, fromMesh: read.fromMesh };
  } finally {
    read.free();
  }
}

/** The points of [`readInput`] alone (a Float32Array of x, y, z). */
export async function readPoints(bytes, fileName) {
  return (await readInput(bytes, fileName)).points;
}

/** Bytes of the wasm module's memory (it grows and never shrinks; for diagnostics and tests). */
export async function wasmMemoryBytes() {
  return (await anyWasm()).memory.buffer.byteLength;
}

/**
 * Which wasm module is in use: `'cpu'` (meshflow_cpu), `'cpu-threads'`
 * (meshflow_cpu_threads), `'webgpu'` (meshflow) or `null`.
 */
export function wasmModule() {
  return Object.keys(loaded).find((k) => loaded[k] === current) ?? null;
}
