// The page: file input, controls, progress, stats and downloads. The model runs in a worker.
// On WebGPU the worker also draws the mesh (the wgpu viewer in Rust, on the model's device,
// into the canvas handed over as an OffscreenCanvas); on the CPU backend the 2D viewer draws
// here.
import { bindControls } from './controls.js';
import { Viewer2D } from './viewer2d.js';

const $ = (id) => document.getElementById(id);
const worker = new Worker(new URL('./worker.js', import.meta.url), { type: 'module' });

// Forwards camera operations to the wgpu viewer in the worker. The worker shows the points
// and meshes itself, as it reads and generates them.
class WorkerViewer {
  setPoints() {}
  setMesh() {}
  orbit(dx, dy) { worker.postMessage({ type: 'view', op: 'orbit', args: [dx, dy] }); }
  pan(dx, dy) { worker.postMessage({ type: 'view', op: 'pan', args: [dx, dy] }); }
  zoom(factor) { worker.postMessage({ type: 'view', op: 'zoom', args: [factor] }); }
  fit() { worker.postMessage({ type: 'view', op: 'fit', args: [] }); }
}

// Until the backend is known, nothing draws; the scene is kept for whichever viewer comes.
let viewer = null;
let scene = { points: null, mesh: null };

function useViewer(v, canvas) {
  viewer = v;
  bindControls(canvas, v);
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
    ['vertices / faces', `${topo.vertices} / ${topo.faces}`],
    ['components', topo.components],
    ['boundary edges / holes', `${topo.boundary_edges} / ${topo.holes}`],
    ['non-manifold edges', topo.non_manifold_edges],
    ['inconsistent winding', topo.inconsistent_winding_edges],
    ['degenerate faces', topo.degenerate_faces],
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

worker.onmessage = ({ data }) => {
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
      if (data.backend === 'webgpu' && 'transferControlToOffscreen' in HTMLCanvasElement.prototype) {
        const offscreen = $('canvas').transferControlToOffscreen();
        worker.postMessage({ type: 'viewer', canvas: offscreen }, [offscreen]);
        useViewer(new WorkerViewer(), $('canvas'));
      } else {
        useViewer(new Viewer2D($('canvas')), $('canvas'));
      }
      document.body.dataset.backend = data.backend;
      document.body.dataset.weightsFromCache = String(data.fromCache);
      $('backend').textContent =
        data.backend === 'webgpu'
          ? 'Running on your GPU (WebGPU).'
          : 'No WebGPU adapter: running on the CPU inside WebAssembly (slower).';
      $('vertices').max = data.maxVertices;
      setRunning(false);
      break;
    case 'points':
      points = data.points;
      result = null;
      $('downloads').hidden = true;
      $('input-info').textContent = `${data.name}: ${points.length / 3} points`;
      scene = { points, mesh: null };
      viewer?.setMesh(null);
      viewer?.setPoints(points);
      setRunning(false);
      break;
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
      // For scripts driving the page (bench/browser.mjs).
      window.__meshflowReport = data.report;
      $('downloads').hidden = false;
      document.body.dataset.generated = String((Number(document.body.dataset.generated) || 0) + 1);
      setRunning(false);
      break;
    case 'viewer-error':
      // The wgpu viewer could not start: draw with the 2D one on a new canvas, and say so.
      console.warn(`wgpu viewer: ${data.message}; using the 2D viewer`);
      useViewer(new Viewer2D(replaceCanvas($('canvas'))), $('canvas'));
      break;
    case 'error':
      showError(data.during === 'load' ? `Could not load the model: ${data.message}` : data.message);
      setRunning(false);
      break;
  }
};

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
$('example').addEventListener('change', async (e) => {
  if (!e.target.value) return;
  const response = await fetch(e.target.value);
  if (!response.ok) return showError(`Could not fetch the example (${response.status}).`);
  readFile(e.target.value.split('/').pop(), await response.arrayBuffer());
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
      steps: num('steps'),
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

worker.postMessage({ type: 'load', backend: params.get('backend') ?? 'auto' });
