/** Seconds per stage of one generation. */
export interface StageTimes {
  condition_s: number;
  sample_s: number;
  decode_s: number;
  extract_s: number;
  /** Fitting the vertices to the input points and completing the surface. */
  fit_s: number;
}

/** docs/design.md section 3's topology figures. */
export interface TopologyReport {
  vertices: number;
  faces: number;
  edges: number;
  non_manifold_edges: number;
  boundary_edges: number;
  holes: number;
  inconsistent_winding_edges: number;
  degenerate_faces: number;
  /** Edges whose two faces fold back onto each other (normals over about 143 degrees apart). */
  folded_edges: number;
  components: number;
  isolated_vertices: number;
}

export interface GenerateReport {
  vertexBudget: number;
  /** Candidates drawn (`samples`); the mesh is the one kept. */
  samples: number;
  /** What the default vertex budget was computed from (README.md, "Vertex budget"). */
  features: { occupied_voxels: number; surface_variation: number; planar_share: number };
  times: StageTimes;
  topology: TopologyReport;
  extract: Record<string, number>;
  /** Holes closed by `closeHoles`, the faces and vertices that added, holes left open as its walk counts them (`topology.holes` is the figure to report), and faces cut where a patch would have folded onto them. */
  close: { holes_closed: number; faces_added: number; vertices_added: number; holes_left: number; faces_cut: number };
  /** What sharpening did: faces in and out, splits, flips, collapses, crease and corner vertices. */
  sharpen: Record<string, number>;
}

export interface GenerateOptions {
  /** Vertices to ask for (1..maxVertices); default: a rule on the input's shape. */
  vertices?: number;
  /**
   * Faces to aim for instead of a vertex count (a TypeError with `vertices`); the result
   * lands near it (`report.topology.faces` says what came out; calibrated with the default
   * `fit` and `closeHoles`, it lands lower without them). Outside what the model can make, the
   * promise rejects with the range.
   */
  faces?: number;
  /**
   * Default true: move the vertices onto the input points and complete the surface between
   * them with faces that lie on the points. False keeps the model's own vertices and faces.
   */
  fit?: boolean;
  /**
   * Default true: close each hole that the surface completion left, where the input points
   * say the surface goes on, with a patch that does not fold (a fan around one new vertex, or
   * a triangulation of the hole's border); with `fit` only. False leaves them open.
   */
  closeHoles?: boolean;
  /**
   * Default true: make the kept mesh exact against the input points (flat where they are
   * flat, creases snapped, flat regions merged into few faces; manifold kept; with the
   * default extraction only). False returns the fitted, completed mesh as it was.
   */
  sharpen?: boolean;
  /** Sampler steps per candidate, default 4 (the paper uses 28 Euler steps). */
  steps?: number;
  /**
   * How each step follows the flow. `'midpoint'` (default) or `'heun'`: second order, two
   * evaluations of the model a step (Heun's last step, to t = 0, is an Euler step).
   * `'euler'`: one a step, as the paper. A TypeError for anything else.
   */
  solver?: 'euler' | 'heun' | 'midpoint';
  seed?: number;
  /**
   * Candidates drawn from different noise in one batch (1 to 16, default 12); the one kept
   * lies closest to the points, each hole counting against it. Each costs a generation; on
   * the test split 12 give 1.3 holes a mesh against 3.8 for one
   * (docs/experiments/2026-11-26-candidates-and-steps.md).
   */
  samples?: number;
  /**
   * How edges become faces. `'manifold'` (default): faces accepted best-first by the model's
   * edge scores, so no edge has a third face and the winding is consistent; small holes are
   * filled and tiny pieces dropped. `'paper'`: the paper's Algorithm 1 (every 3-clique).
   */
  extraction?: 'manifold' | 'paper';
  /**
   * With `extraction: 'paper'` only (a TypeError otherwise): drop faces that would give an
   * edge a third face, keeping the ones the model is surest of. Default false.
   */
  dropNonManifold?: boolean;
  /** Called after each step has finished on the device. */
  onStep?: (step: number, steps: number) => void;
  /** Aborting cancels between steps; the promise then rejects. */
  signal?: AbortSignal;
}

export class GeneratedMesh {
  readonly positions: Float32Array;
  readonly normals: Float32Array;
  readonly indices: Uint32Array;
  readonly report: GenerateReport;
  toGlb(): Uint8Array;
  toObj(): string;
}

/**
 * The wgpu mesh viewer: lit, depth-tested, flat-shaded mesh, wireframe, input points, an
 * orbit camera; on WebGPU or (the CPU backend) WebGL2.
 */
export interface Viewer {
  /** What draws: the model's WebGPU device, or the CPU path's own WebGL2 context. */
  readonly api: 'webgpu' | 'webgl2';
  /** x, y, z per vertex and three indices per face; fits the view. */
  setMesh(positions: Float32Array, indices: Uint32Array): void;
  /** The input points (clears the mesh); shown over the next mesh unless turned off. */
  setPoints(points: Float32Array): void;
  /** Whether the points are drawn over the mesh too (default true). */
  setPointsOverlay(on: boolean): void;
  /** Turns the view, radians. */
  orbit(dx: number, dy: number): void;
  /** Pans, canvas pixels. */
  pan(dx: number, dy: number): void;
  /** Zooms in by factor > 1, out by factor < 1. */
  zoom(factor: number): void;
  fit(): void;
  render(): void;
  free(): void;
}

/** Which backend runs and why. */
export interface BackendChoice {
  backend: 'webgpu' | 'cpu';
  /** A sentence for the user, e.g. "the WebGPU adapter is a software renderer (google swiftshader); the CPU path is faster". */
  reason: string;
  /** The WebGPU adapter's info, when there was one. */
  adapter: { vendor: string; architecture: string; description: string } | null;
}

export interface BackendReport {
  /** The `backend` option given to `loadModel`. */
  asked: 'auto' | 'webgpu' | 'cpu';
  reason: string;
  adapter: BackendChoice['adapter'];
  /** Modules drawing a generation's candidates side by side (1 on WebGPU and with threads). */
  workers: number;
  /** Threads of the threaded CPU module (0: it does not run: WebGPU, or no cross-origin isolation). */
  threads: number;
  /**
   * A sentence for the user, e.g. "on 4 threads (the page is cross-origin isolated)" or
   * "candidates drawn on 2 workers side by side; no threads: the page is not cross-origin
   * isolated", or why fewer workers run than asked.
   */
  workersReason: string;
}

export class Model {
  readonly backend: 'webgpu' | 'cpu';
  /** Which backend runs and why. */
  readonly backendReport: BackendReport;
  readonly maxVertices: number;
  /** Modules drawing a generation's candidates side by side: 1, or 1 + the helper workers on the CPU path. */
  readonly workers: number;
  weightsFromCache: boolean;
  /** Stops the helper workers; the model still generates, in its own module alone. */
  terminate(): void;
  generate(points: Float32Array, options?: GenerateOptions): Promise<GeneratedMesh>;
  /** Destroys the WebGPU device as a GPU reset would (for testing fallbacks). */
  destroyDevice(): void;
  /**
   * A viewer drawing into `canvas`: on this model's WebGPU device, or on the CPU backend
   * through WebGL2. Rejects where the canvas gives neither.
   */
  createViewer(canvas: OffscreenCanvas): Promise<Viewer>;
}

export interface LoadOptions {
  /**
   * Folder URL with vae.* and dit.* (default: the package's weights/, the f16 files the CLI
   * runs too; f32 files load as well).
   */
  weights?: string | URL;
  /**
   * `'auto'` (default): the faster one here (see `chooseBackend`); `'webgpu'` or `'cpu'`
   * to override.
   */
  backend?: 'auto' | 'webgpu' | 'cpu';
  onProgress?: (bytes: number, total: number) => void;
  /** Keep the weights in Cache Storage (default true). */
  useCache?: boolean;
  /**
   * Where the wasm files are, if not beside the glue in pkg/: `cpu` for meshflow_cpu_bg.wasm
   * (the CPU path, loaded when the CPU is chosen or WebGPU fails to start), `'cpu-threads'`
   * for meshflow_cpu_threads_bg.wasm (the same on threads, where the page is cross-origin
   * isolated) and `webgpu` for meshflow_bg.wasm (WebGPU alone).
   */
  wasmUrls?: { cpu?: string | URL; 'cpu-threads'?: string | URL; webgpu?: string | URL };
  /**
   * On the CPU path where the page is cross-origin isolated (served with
   * `Cross-Origin-Opener-Policy: same-origin` and `Cross-Origin-Embedder-Policy:
   * require-corp`): threads of the threaded module, 0 to 64 (default: one per core the
   * browser reports, at most 16; 0: never use it). It runs the models and the per-candidate
   * stages on every core from one copy of the models, and makes the same mesh. Elsewhere, or
   * where it fails to start, `workers` applies and `backendReport.workersReason` says why.
   * The pool is started once a page: a later `loadModel` gets the first one's threads.
   */
  threads?: number;
  /**
   * On the CPU path without threads: wasm modules drawing a generation's candidates side by side, 1 to 4
   * (default: one per core the browser reports, at most 4). Each beyond the first is a worker
   * with its own copy of the models (about 60 MB); the mesh is the same for any number. A
   * worker that fails to start or dies is dropped, `backendReport.workersReason` says so.
   */
  workers?: number;
}

/**
 * Instantiates a wasm module once: `'cpu'` (meshflow_cpu: the CPU path, the smaller
 * download), `'cpu-threads'` (meshflow_cpu_threads: the CPU path on threads; cross-origin
 * isolated contexts only, its pool started by `glue.initThreadPool(n)`) or `'webgpu'`
 * (meshflow: WebGPU alone). Resolves to its glue and memory.
 */
export function initWasm(which?: 'cpu' | 'cpu-threads' | 'webgpu', wasmUrl?: string | URL): Promise<{ glue: unknown; memory: WebAssembly.Memory }>;
/** Which wasm module is in use (`null` before any is loaded). */
export function wasmModule(): 'cpu' | 'cpu-threads' | 'webgpu' | null;
export function loadModel(options?: LoadOptions): Promise<Model>;
export function fetchWeights(
  baseUrl: string | URL,
  options?: { onProgress?: (bytes: number, total: number) => void; useCache?: boolean },
): Promise<{ files: Uint8Array[]; fromCache: boolean }>;
export function clearWeightsCache(): Promise<void>;
/** The points to condition on, read from a file. */
export interface InputPoints {
  /** x, y, z per point. */
  points: Float32Array;
  /** The file's own point count (more than `points` holds when a large cloud was subsampled). */
  sourcePoints: number;
  /** Whether the file was a mesh, its surface sampled. */
  fromMesh: boolean;
}
/**
 * Reads a point cloud or mesh file. A mesh is surface-sampled; a cloud of more than 4,096
 * points is evenly subsampled to 4,096. Rejects with an Error naming the problem.
 */
export function readInput(bytes: Uint8Array, fileName: string): Promise<InputPoints>;
/** `readInput(...).points`. */
export function readPoints(bytes: Uint8Array, fileName: string): Promise<Float32Array>;
/** Bytes of the wasm module's memory (it never shrinks). */
export function wasmMemoryBytes(): Promise<number>;
/**
 * What `backend: 'auto'` picks: the CPU without WebGPU, without an adapter, or on a fallback
 * or software adapter (SwiftShader, llvmpipe, lavapipe, WARP); WebGPU on a known GPU vendor;
 * otherwise a short timed probe (`probeAdapter`) decides. `gpu` and `probe` can be replaced
 * (tests).
 */
export function chooseBackend(options?: {
  gpu?: { requestAdapter(options?: unknown): Promise<unknown> } | null;
  probe?: (adapter: unknown) => Promise<number>;
}): Promise<BackendChoice>;
/** Milliseconds for one 256^3 matrix-product dispatch on `adapter` (after a warm-up). */
export function probeAdapter(adapter: unknown): Promise<number>;
