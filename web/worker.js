// Runs the model off the main thread so the page stays responsive during a generation.
import { loadModel, readInput, wasmMemoryBytes, wasmModule } from './lib/index.js';

let model = null;
let abort = null;
// The wgpu viewer (on the model's WebGPU device, or on WebGL2 for the CPU path) and what it
// shows, kept so a viewer created later shows it.
let viewer = null;
let scene = { points: null, mesh: null };

const post = (msg, transfer = []) => self.postMessage(msg, transfer);

self.onmessage = async ({ data }) => {
  try {
    if (data.type === 'load') {
      model = await loadModel({
        // The shipped weights (f16), the files the CLI runs.
        weights: new URL('../weights/', self.location.href),
        backend: data.backend ?? 'auto',
        // For tests and the curious: `?workers=1` draws every candidate in this worker.
        ...(data.workers ? { workers: data.workers } : {}),
        // `?threads=0` keeps a cross-origin isolated page on the single-threaded modules.
        ...(data.threads !== undefined ? { threads: data.threads } : {}),
        onProgress: (got, total) => post({ type: 'weights', got, total }),
      });
      post({
        type: 'ready',
        backend: model.backend,
        reason: model.backendReport.reason,
        workers: model.backendReport.workers,
        threads: model.backendReport.threads,
        workersReason: model.backendReport.workersReason,
        asked: model.backendReport.asked,
        fromCache: model.weightsFromCache,
        maxVertices: model.maxVertices,
        // Which wasm module was downloaded: 'cpu' (meshflow_cpu) or 'webgpu' (meshflow).
        module: wasmModule(),
      });
    } else if (data.type === 'read') {
      const { points, sourcePoints, fromMesh } = await readInput(new Uint8Array(data.bytes), data.name);
      scene = { points: points.slice(), mesh: null };
      viewer?.setPoints(scene.points);
      post({ type: 'points', name: data.name, points, sourcePoints, fromMesh }, [points.buffer]);
    } else if (data.type === 'generate') {
      abort = new AbortController();
      const mesh = await model.generate(new Float32Array(data.points), {
        vertices: data.vertices,
        faces: data.faces,
        fit: data.fit,
        closeHoles: data.closeHoles,
        sharpen: data.sharpen,
        steps: data.steps,
        solver: data.solver,
        samples: data.samples,
        seed: data.seed,
        extraction: data.extraction,
        signal: abort.signal,
        onStep: (i, n) => post({ type: 'step', i, n }),
      });
      scene.mesh = { positions: mesh.positions.slice(), indices: mesh.indices.slice() };
      viewer?.setMesh(scene.mesh.positions, scene.mesh.indices);
      const glb = mesh.toGlb();
      post(
        {
          type: 'done', positions: mesh.positions, normals: mesh.normals, indices: mesh.indices, report: mesh.report, glb, obj: mesh.toObj(),
          workers: model.backendReport.workers, workersReason: model.backendReport.workersReason,
        },
        [mesh.positions.buffer, mesh.normals.buffer, mesh.indices.buffer, glb.buffer],
      );
    } else if (data.type === 'viewer') {
      try {
        viewer = await model.createViewer(data.canvas);
        if (scene.points) viewer.setPoints(scene.points);
        if (scene.mesh) viewer.setMesh(scene.mesh.positions, scene.mesh.indices);
        post({ type: 'viewer-ready', api: viewer.api });
      } catch (e) {
        viewer = null;
        post({ type: 'viewer-error', message: e?.message ?? String(e) });
      }
    } else if (data.type === 'view') {
      viewer?.[data.op](...data.args);
    } else if (data.type === 'memory') {
      // For tests: the wasm memory and (where the browser has it) this worker's JS heap.
      post({ type: 'memory', wasm: await wasmMemoryBytes(), heap: self.performance?.memory?.usedJSHeapSize ?? null });
    } else if (data.type === 'destroy-device') {
      // For tests: a GPU reset, as the page would meet it.
      model.destroyDevice();
      post({ type: 'device-destroyed' });
    } else if (data.type === 'cancel') {
      abort?.abort();
    }
  } catch (e) {
    post({ type: 'error', during: data.type, message: e?.message ?? String(e) });
  }
};
