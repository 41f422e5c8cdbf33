// The page: file input, controls, progress, stats and downloads. The model runs in a worker,
// which also draws the mesh: the wgpu viewer in Rust, into the canvas handed over as an
// OffscreenCanvas, on the model's WebGPU device or, on the CPU backend, on WebGL2. Where
// neither can draw (no OffscreenCanvas, no WebGL2) the 2D viewer draws here.
import { bindControls } from './controls.js';
import { clearWeightsCache } from './lib/index.js';
import { Viewer2D } from './viewer2d.js';

const $ = (id) => document.getElementById(id);
// The model's worker; replaced by a CPU one when the GPU fails (see fallBackToCpu).
let worker = null;

// Forwards camera operations to the wgpu viewer in the worker. The worker shows the points
// and meshes itself, as it reads and generates them.
class WorkerViewer {
  setPoints() {}
  setMesh() {}
  orbit(dx, dy) { worker.postMessage({ type: 'view', op: 'orbit', args: [dx, dy] }); }
  pan(dx, dy) { worker.postMessage({ type: 'view', op: 'pan', args: [dx, dy] }); }
  setPointsOverlay(on) { worker.postMessage({ type: 'view', op: 'setPointsOverlay', args: [on] }); }
  zoom(factor) { worker.postMessage({ type: 'view', op: 'zoom', args: [factor] }); }
  fit() { worker.postMessage({ type: 'view', op: 'fit', args: [] }); }
}

// Until the backend is known, nothing draws; the scene is kept for whichever viewer comes.
let viewer = null;
let scene = { points: null, mesh: null };

function useViewer(v, canvas) {
  viewer = v;
  bindControls(canvas, v);
  v.setPointsOverlay($('show-points').checked);
  if (scene.points) v.setPoints(scene.points);
  if (scene.mesh) v.setMesh(scene.mesh.positions, scene.mesh.indices);
  document.body.dataset.viewer = v instanceof WorkerViewer ? 'wgpu' : '2d';
}

// A fresh canvas in place of `old` (one handed to the worker cannot take a 2D context).
function replaceCanvas(old) {
  const c = document.createElement('canvas');
  for (const a of ['id', 'width', 'height', 'aria-label']) c.setAttribute(a, old.getAttribute(a));
  old.replaceWith(c);
  return c;
}
const params = new URLSearchParams(location.search);

let points = null;
let result = null;
let running = false;
let ready = false;

function showError(message) {
  $('error').textContent = message;
  $('error').hidden = false;
}

function clearError() {
  $('error').hidden = true;
}

function setRunning(on) {
  running = on;
  $('generate').textContent = on ? 'Cancel' : 'Generate';
  $('generate').disabled = !ready || (!on && !points);
}

const fmt = (s) => (s < 1 ? `${(s * 1000).toFixed(0)} ms` : `${s.toFixed(2)} s`);

function showStats(report) {
  const t = report.times;
  const topo = report.topology;
  const rows = [
    ['vertex budget', report.vertexBudget],
    ['candidates drawn', report.samples],
    ['vertices / faces', `${topo.vertices} / ${topo.faces}`],
    ['components', topo.components],
    ['boundary edges / holes', `${topo.boundary_edges} / ${topo.holes}`],
    ['non-manifold edges', topo.non_manifold_edges],
    ['inconsistent winding', topo.inconsistent_winding_edges],
    ['degenerate faces', topo.degenerate_faces],
    ['folded edges', topo.folded_edges],
    ['condition', fmt(t.condition_s)],
    ['sample', fmt(t.sample_s)],
    ['decode', fmt(t.decode_s)],
    ['extract', fmt(t.extract_s)],
    ['fit', fmt(t.fit_s)],
  ];
  $('stats').replaceChildren(
    ...rows.map(([k, v]) => {
      const tr = document.createElement('tr');
      tr.dataset.key = k;
      for (const text of [k, String(v)]) {
        const td = document.createElement('td');
        td.textContent = text;
        tr.append(td);
      }
      return tr;
    }),
  );
}

// Recent worker messages with their arrival times, for diagnosing slow main-thread work.
const events = (window.__meshflowEvents = []);
// Why the page left WebGPU, once it has.
let fallbackReason = null;
let backend = null;

function startWorker(asked) {
  worker = new Worker(new URL('./worker.js', import.meta.url), { type: 'module' });
  worker.onmessage = onWorkerMessage;
  // `?workers=N`: how many wasm modules draw the candidates on the CPU path (default: one per core).
  const workers = Number(params.get('workers')) || undefined;
  // `?threads=N`: the threaded module's threads where the page is cross-origin isolated (0: none).
  const threads = params.has('threads') ? Number(params.get('threads')) : undefined;
  worker.postMessage({ type: 'load', backend: asked, workers, threads });
}

// The GPU device was lost (a reset, a driver crash) or failed mid-generation: a fresh worker
// on the CPU path takes over (the old one's wasm may be unusable), the user is told, and the
// next generation runs there.
function fallBackToCpu(message) {
  worker.terminate();
  ready = false;
  setRunning(false);
  fallbackReason = `the GPU failed (${message}), so the page switched to the CPU path`;
  // The canvas was handed to the old worker; the 2D viewer needs a fresh one.
  if (document.body.dataset.viewer === 'wgpu') replaceCanvas($('canvas'));
  viewer = null;
  $('backend').textContent = 'Switching to the CPU…';
  startWorker('cpu');
}

// How many wasm modules draw the candidates, and why (for the user and the tests).
function showWorkers({ workers, threads, workersReason }) {
  document.body.dataset.workers = String(workers);
  if (threads !== undefined) document.body.dataset.threads = String(threads);
  document.body.dataset.workersReason = workersReason;
}

function onWorkerMessage({ data }) {
  events.push({ type: data.type, at: performance.now() });
  if (events.length > 200) events.shift();
  switch (data.type) {
    case 'weights':
      $('weights-progress').max = data.total || 1;
      $('weights-progress').value = data.got;
      $('weights-text').textContent = `${(data.got / 1048576).toFixed(1)} / ${(data.total / 1048576).toFixed(1)} MiB`;
      break;
    case 'ready':
      ready = true;
      backend = data.backend;
      if ('transferControlToOffscreen' in HTMLCanvasElement.prototype) {
        const offscreen = $('canvas').transferControlToOffscreen();
        worker.postMessage({ type: 'viewer', canvas: offscreen }, [offscreen]);
        useViewer(new WorkerViewer(), $('canvas'));
      } else {
        useViewer(new Viewer2D($('canvas')), $('canvas'));
      }
      document.body.dataset.backend = data.backend;
      document.body.dataset.wasmModule = data.module;
      document.body.dataset.weightsFromCache = String(data.fromCache);
      document.body.dataset.backendReason = fallbackReason ?? data.reason;
      showWorkers(data);
      $('backend').textContent =
        (data.backend === 'webgpu' ? 'Running on your GPU (WebGPU)' : `Running on the CPU inside WebAssembly, ${data.workersReason}`) +
        (fallbackReason ? `: ${fallbackReason}.` : data.asked === 'auto' ? `: ${data.reason}.` : ' (chosen in the Backend menu).');
      if (!fallbackReason) $('backend-choice').value = data.asked;
      $('vertices').max = data.maxVertices;
      setRunning(false);
      break;
    case 'points': {
      points = data.points;
      result = null;
      $('downloads').hidden = true;
      const n = points.length / 3;
      const count = (k) => k.toLocaleString('en');
      $('input-info').textContent = data.fromMesh
        ? `${data.name}: a mesh of ${count(data.sourcePoints)} vertices, ${count(n)} points sampled from its surface`
        : n < data.sourcePoints
          ? `${data.name}: ${count(data.sourcePoints)} points, conditioning on an even subsample of ${count(n)}`
          : `${data.name}: ${count(n)} points`;
      scene = { points, mesh: null };
      viewer?.setMesh(null);
      viewer?.setPoints(points);
      setRunning(false);
      break;
    }
    case 'step':
      $('step-progress').max = data.n;
      $('step-progress').value = data.i;
      $('step-text').textContent = `${data.i} / ${data.n}`;
      break;
    case 'done':
      result = data;
      scene.mesh = { positions: data.positions, indices: data.indices };
      viewer?.setMesh(data.positions, data.indices);
      showStats(data.report);
      // A candidate worker that died was dropped: say so where the backend is shown.
      if (data.workersReason !== document.body.dataset.workersReason) {
        showWorkers(data);
        $('backend').textContent = `Running on the CPU inside WebAssembly, ${data.workersReason}.`;
      }
      // For scripts driving the page (bench/browser.mjs).
      window.__meshflowReport = data.report;
      $('downloads').hidden = false;
      document.body.dataset.generated = String((Number(document.body.dataset.generated) || 0) + 1);
      setRunning(false);
      break;
    case 'viewer-ready':
      // Which API the wgpu viewer draws with: 'webgpu' or 'webgl2'.
      document.body.dataset.viewerApi = data.api;
      break;
    case 'viewer-error':
      // The wgpu viewer could not start: draw with the 2D one on a new canvas, and say so.
      console.warn(`wgpu viewer: ${data.message}; using the 2D viewer`);
      useViewer(new Viewer2D(replaceCanvas($('canvas'))), $('canvas'));
      break;
    case 'error':
      if (data.during === 'generate' && backend === 'webgpu' && !/cancelled|points|faces|vertices|options/.test(data.message)) {
        // The first line: wgpu appends its error chain and a backtrace note.
        const reason = data.message.split('\n')[0];
        showError(`The GPU failed during the generation (${reason}). The page switched to the CPU path: generate again.`);
        fallBackToCpu(reason);
        break;
      }
      showError(data.during === 'load' ? `Could not load the model: ${data.message}` : data.message);
      setRunning(false);
      break;
    case 'memory':
    case 'device-destroyed':
      // For tests driving the page.
      window.__meshflowLast = data;
      break;
  }
}

async function readFile(name, bytes) {
  clearError();
  worker.postMessage({ type: 'read', name, bytes }, [bytes]);
}

$('file').addEventListener('change', async (e) => {
  const f = e.target.files[0];
  if (f) readFile(f.name, await f.arrayBuffer());
});
const drop = $('drop');
drop.addEventListener('dragover', (e) => {
  e.preventDefault();
  drop.classList.add('over');
});
drop.addEventListener('dragleave', () => drop.classList.remove('over'));
drop.addEventListener('drop', async (e) => {
  e.preventDefault();
  drop.classList.remove('over');
  const f = e.dataTransfer.files[0];
  if (f) readFile(f.name, await f.arrayBuffer());
});
// The bundled examples (web/examples/: licenses and sources in SOURCES.md there).
const examples = fetch('examples/examples.json').then((r) => (r.ok ? r.json() : []));
examples.then((list) => {
  for (const ex of list) {
    const option = document.createElement('option');
    option.value = ex.file;
    option.textContent = `${ex.label}, ${ex.kind}`;
    $('example').append(option);
  }
});
$('example').addEventListener('change', async (e) => {
  $('example-source').textContent = '';
  if (!e.target.value) return;
  const ex = (await examples).find((x) => x.file === e.target.value);
  $('example-source').textContent = `${ex.source}; ${ex.license}.`;
  const response = await fetch(`examples/${ex.file}`);
  if (!response.ok) return showError(`Could not fetch the example (${response.status}).`);
  readFile(ex.file, await response.arrayBuffer());
});

$('generate').addEventListener('click', () => {
  if (running) {
    worker.postMessage({ type: 'cancel' });
    return;
  }
  clearError();
  const num = (id) => ($(id).value === '' ? undefined : Number($(id).value));
  $('step-progress').value = 0;
  setRunning(true);
  const copy = points.slice();
  worker.postMessage(
    {
      type: 'generate',
      points: copy,
      vertices: num('vertices'),
      faces: num('faces'),
      fit: $('fit').checked,
      closeHoles: $('close-holes').checked,
      sharpen: $('sharpen').checked,
      steps: num('steps'),
      solver: $('solver').value,
      samples: num('samples'),
      seed: num('seed'),
      extraction: $('extraction').value,
    },
    [copy.buffer],
  );
});

function download(bytes, name, type) {
  const url = URL.createObjectURL(new Blob([bytes], { type }));
  const a = document.createElement('a');
  a.href = url;
  a.download = name;
  a.click();
  setTimeout(() => URL.revokeObjectURL(url), 1000);
}
$('download-glb').addEventListener('click', () => download(result.glb, 'meshflow.glb', 'model/gltf-binary'));
$('download-obj').addEventListener('click', () => download(result.obj, 'meshflow.obj', 'text/plain'));

// Another backend reloads the page with it in the address (so a bookmark keeps it).
$('backend-choice').addEventListener('change', (e) => {
  const url = new URL(location.href);
  if (e.target.value === 'auto') url.searchParams.delete('backend');
  else url.searchParams.set('backend', e.target.value);
  location.assign(url);
});

$('show-points').addEventListener('change', (e) => viewer?.setPointsOverlay(e.target.checked));

$('clear-cache').addEventListener('click', async () => {
  await clearWeightsCache();
  $('weights-text').textContent = 'cache cleared: the next visit downloads the weights again';
});

startWorker(params.get('backend') ?? 'auto');
// For tests and diagnostics: post a message to the model's worker.
window.__meshflowPost = (message) => worker.postMessage(message);
