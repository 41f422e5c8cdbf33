/** Seconds per stage of one generation. */
export interface StageTimes {
  condition_s: number;
  sample_s: number;
  decode_s: number;
  extract_s: number;
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
  /** Euler steps, default 28. */
  steps?: number;
  seed?: number;
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

export class Model {
  readonly backend: 'webgpu' | 'cpu';
  readonly maxVertices: number;
  weightsFromCache: boolean;
  generate(points: Float32Array, options?: GenerateOptions): Promise<GeneratedMesh>;
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
