// The page: file input, controls, progress, stats and downloads. The model runs in a worker.
import { Viewer } from './viewer2d.js';

const $ = (id) => document.getElementById(id);
const viewer = new Viewer($('canvas'));
const worker = new Worker(new URL('./worker.js', import.meta.url), { type: 'module' });
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
      viewer.setMesh(null);
      viewer.setPoints(points);
      setRunning(false);
      break;
    case 'step':
      $('step-progress').max = data.n;
      $('step-progress').value = data.i;
      $('step-text').textContent = `${data.i} / ${data.n}`;
      break;
    case 'done':
      result = data;
      viewer.setMesh(data.positions, data.indices);
      showStats(data.report);
      // For scripts driving the page (bench/browser.mjs).
      window.__meshflowReport = data.report;
      $('downloads').hidden = false;
      document.body.dataset.generated = String((Number(document.body.dataset.generated) || 0) + 1);
      setRunning(false);
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
    { type: 'generate', points: copy, vertices: num('vertices'), steps: num('steps'), seed: num('seed') },
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
