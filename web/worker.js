// Runs the model off the main thread so the page stays responsive during a generation.
import { loadModel, readPoints } from './lib/index.js';

let model = null;
let abort = null;

const post = (msg, transfer = []) => self.postMessage(msg, transfer);

self.onmessage = async ({ data }) => {
  try {
    if (data.type === 'load') {
      model = await loadModel({
        weights: new URL('../weights/', self.location.href),
        backend: data.backend ?? 'auto',
        onProgress: (got, total) => post({ type: 'weights', got, total }),
      });
      post({ type: 'ready', backend: model.backend, fromCache: model.weightsFromCache, maxVertices: model.maxVertices });
    } else if (data.type === 'read') {
      const points = await readPoints(new Uint8Array(data.bytes), data.name);
      post({ type: 'points', name: data.name, points }, [points.buffer]);
    } else if (data.type === 'generate') {
      abort = new AbortController();
      const mesh = await model.generate(new Float32Array(data.points), {
        vertices: data.vertices,
        steps: data.steps,
        seed: data.seed,
        signal: abort.signal,
        onStep: (i, n) => post({ type: 'step', i, n }),
      });
      const glb = mesh.toGlb();
      post(
        { type: 'done', positions: mesh.positions, normals: mesh.normals, indices: mesh.indices, report: mesh.report, glb, obj: mesh.toObj() },
        [mesh.positions.buffer, mesh.normals.buffer, mesh.indices.buffer, glb.buffer],
      );
    } else if (data.type === 'cancel') {
      abort?.abort();
    }
  } catch (e) {
    post({ type: 'error', during: data.type, message: e?.message ?? String(e) });
  }
};
