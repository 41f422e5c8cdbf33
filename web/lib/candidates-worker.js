// A helper worker of web/lib/candidates.js: its own CPU module and copy of the models, drawing
// the runs of candidates it is sent.
import { initWasm } from './index.js';

let model = null;
let cancelled = false;

self.onmessage = async ({ data }) => {
  try {
    if (data.type === 'load') {
      const { glue } = await initWasm('cpu', data.wasmUrl);
      const text = new TextDecoder();
      const [vaeManifest, vae, ditManifest, dit] = data.files;
      model = await glue.MeshFlow.load(text.decode(vaeManifest), vae, text.decode(ditManifest), dit, 'cpu');
      self.postMessage({ type: 'ready' });
    } else if (data.type === 'draw') {
      cancelled = false;
      const bytes = await model.generateCandidates(data.points, data.options, data.first, data.count, () => !cancelled);
      self.postMessage({ type: 'drawn', id: data.id, bytes }, [bytes.buffer]);
    } else if (data.type === 'cancel') {
      cancelled = true;
    }
  } catch (e) {
    self.postMessage({ type: 'error', id: data.id, message: e?.message ?? String(e) });
  }
};
