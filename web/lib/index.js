// MeshFlow in the browser: load the shipped weights, generate a mesh from a point cloud on
// WebGPU (or the CPU inside wasm when there is no adapter), export GLB / OBJ.
//
//   import { loadModel, readPoints } from 'meshflow';
//   const model = await loadModel({ onProgress: (got, total) => {} });
//   const points = await readPoints(bytes, 'scan.ply');
//   const mesh = await model.generate(points, { steps: 28, onStep: (i, n) => {} });
//   const glb = mesh.toGlb();
import init, { MeshFlow, readPoints as readPointsWasm } from '../pkg/meshflow.js';

const FILES = ['vae.manifest.json', 'vae.safetensors', 'dit.manifest.json', 'dit.safetensors'];
const CACHE = 'meshflow-weights-v1';

let wasmReady;

/** Instantiates the wasm module once (from `wasmUrl`, default: beside the JS glue). */
export function initWasm(wasmUrl) {
  wasmReady ??= init(wasmUrl ? { module_or_path: wasmUrl } : undefined);
  return wasmReady;
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
  constructor(inner) {
    this.#inner = inner;
  }
  #inner;
  /** `'webgpu'` or `'cpu'`. */
  get backend() {
    return this.#inner.backend;
  }
  /** The most vertices one generation makes. */
  get maxVertices() {
    return this.#inner.maxVertices;
  }
  /**
   * A wgpu viewer drawing into `canvas` (an OffscreenCanvas, e.g. from
   * `canvas.transferControlToOffscreen()`) on this model's WebGPU device: `setPoints`,
   * `setMesh`, `orbit`, `pan`, `zoom`, `fit`, `render`. Throws on the CPU backend.
   */
  createViewer(canvas) {
    return this.#inner.createViewer(canvas);
  }
  /**
   * Generates a mesh from `points` (Float32Array of x, y, z). Options: `vertices` or `faces`
   * (a face count to aim for; not both), `steps` (default 28), `seed`, `extraction`
   * (`'manifold'`, the default: no edge with a third face, consistent winding; or `'paper'`:
   * the paper's Algorithm 1), `dropNonManifold` (with `'paper'` only: keep at most two faces
   * per edge), `fit` (default true: vertices moved onto the points and the surface completed
   * between them), `onStep(step, steps)`, `signal` (an AbortSignal: aborting cancels between
   * steps and rejects).
   */
  async generate(points, { vertices, faces, steps, seed, extraction, dropNonManifold, fit = true, onStep, signal } = {}) {
    if (vertices !== undefined && faces !== undefined) {
      throw new TypeError('ask for vertices or for faces, not both');
    }
    if (typeof fit !== 'boolean') {
      throw new TypeError(`fit must be true or false, got ${JSON.stringify(fit)}`);
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
      seed,
      extract,
      ...(fit ? {} : { fit: { iterations: 0 }, complete: { enabled: false } }),
    });
    const inner = await this.#inner.generate(points, options, (i, n) => {
      onStep?.(i, n);
      return !signal?.aborted;
    });
    return new GeneratedMesh(inner);
  }
}

/**
 * Loads the shipped models. `weights`: the folder URL holding vae.* and dit.* (default: the
 * package's `weights/`); `backend`: `'auto'` (WebGPU, else CPU), `'webgpu'` or `'cpu'`;
 * `onProgress(bytes, total)` during the download.
 */
export async function loadModel({
  weights = new URL('../../weights/', import.meta.url),
  backend = 'auto',
  onProgress,
  useCache = true,
  wasmUrl,
} = {}) {
  await initWasm(wasmUrl);
  const { files, fromCache } = await fetchWeights(weights, { onProgress, useCache });
  const text = new TextDecoder();
  try {
    const inner = await MeshFlow.load(text.decode(files[0]), files[1], text.decode(files[2]), files[3], backend);
    const model = new Model(inner);
    model.weightsFromCache = fromCache;
    return model;
  } catch (e) {
    // A stale or damaged cache entry fails the checksum: drop it so the next load refetches.
    if (fromCache) await clearWeightsCache();
    throw e;
  }
}

/**
 * Reads a point cloud or mesh file (PLY, OBJ, STL, GLB/glTF, XYZ, ...) into the points to
 * condition on (a mesh is surface-sampled). Throws an Error with a message for bad files.
 */
export async function readPoints(bytes, fileName) {
  await initWasm();
  return new Float32Array(readPointsWasm(bytes, fileName));
}
