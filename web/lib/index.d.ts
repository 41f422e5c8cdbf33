/** Seconds per stage of one generation. */
export interface StageTimes {
  condition_s: number;
  sample_s: number;
  decode_s: number;
  extract_s: number;
  /** Fitting the vertices to the input points and completing the surface. */
  fit_s: number;
}

/** DESIGN.md section 3's topology figures. */
export interface TopologyReport {
  vertices: number;
  faces: number;
  edges: number;
  non_manifold_edges: number;
  boundary_edges: number;
  holes: number;
  inconsistent_winding_edges: number;
  degenerate_faces: number;
  components: number;
  isolated_vertices: number;
}

export interface GenerateReport {
  vertexBudget: number;
  features: { occupied_voxels: number; surface_variation: number };
  times: StageTimes;
  topology: TopologyReport;
  extract: Record<string, number>;
}

export interface GenerateOptions {
  /** Vertices to ask for (1..maxVertices); default: a rule on the input's shape. */
  vertices?: number;
  /**
   * Faces to aim for instead of a vertex count (a TypeError with `vertices`); the result
   * lands near it (`report.topology.faces` says what came out). Outside what the model can
   * make, the promise rejects with the range.
   */
  faces?: number;
  /**
   * Default true: move the vertices onto the input points and complete the surface between
   * them with faces that lie on the points. False keeps the model's own vertices and faces.
   */
  fit?: boolean;
  /** Euler steps, default 28. */
  steps?: number;
  seed?: number;
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

/** The wgpu mesh viewer: flat-shaded mesh, wireframe, input points, an orbit camera. */
export interface Viewer {
  /** x, y, z per vertex and three indices per face; fits the view. */
  setMesh(positions: Float32Array, indices: Uint32Array): void;
  /** The input points, shown until there is a mesh (clears the mesh). */
  setPoints(points: Float32Array): void;
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

export class Model {
  readonly backend: 'webgpu' | 'cpu';
  readonly maxVertices: number;
  weightsFromCache: boolean;
  generate(points: Float32Array, options?: GenerateOptions): Promise<GeneratedMesh>;
  /** A viewer on this model's WebGPU device; throws on the CPU backend. */
  createViewer(canvas: OffscreenCanvas): Viewer;
}

export interface LoadOptions {
  /** Folder URL with vae.* and dit.* (default: the package's weights/). */
  weights?: string | URL;
  backend?: 'auto' | 'webgpu' | 'cpu';
  onProgress?: (bytes: number, total: number) => void;
  /** Keep the weights in Cache Storage (default true). */
  useCache?: boolean;
  /** Where meshflow_bg.wasm is (default: beside the glue). */
  wasmUrl?: string | URL;
}

export function initWasm(wasmUrl?: string | URL): Promise<unknown>;
export function loadModel(options?: LoadOptions): Promise<Model>;
export function fetchWeights(
  baseUrl: string | URL,
  options?: { onProgress?: (bytes: number, total: number) => void; useCache?: boolean },
): Promise<{ files: Uint8Array[]; fromCache: boolean }>;
export function clearWeightsCache(): Promise<void>;
export function readPoints(bytes: Uint8Array, fileName: string): Promise<Float32Array>;
