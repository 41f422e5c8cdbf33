// Browser end-to-end tests: the page and the npm package in Debian's headless Chromium
// (WebGPU through SwiftShader), driven by playwright-core. Run by scripts/test.sh after
// scripts/build-web.sh: `node tests/e2e/browser.test.mjs`. Prints one line per check and a
// `browser: N passed, N failed` summary; exits non-zero on a failure.
import { chromium } from 'playwright-core';
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, writeFileSync, mkdirSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { serve } from '../../web/serve.mjs';

const ROOT = resolve(fileURLToPath(new URL('../..', import.meta.url)));
const FIXTURE = join(ROOT, 'tests/fixtures/points/stone_lantern_2048.ply');
const WEBGPU_FLAGS = [
  '--enable-unsafe-webgpu',
  '--use-angle=swiftshader',
  '--use-vulkan=swiftshader',
  '--enable-features=Vulkan',
];
const GENERATION_TIMEOUT = 300_000;
const results = [];

async function check(name, fn) {
  const started = Date.now();
  try {
    await fn();
    results.push([name, true]);
    console.log(`ok   ${name} (${((Date.now() - started) / 1000).toFixed(1)} s)`);
  } catch (e) {
    results.push([name, false]);
    console.log(`FAIL ${name}: ${e?.stack ?? e}`);
  }
}

function assert(cond, message) {
  if (!cond) throw new Error(message);
}

async function launch(webgpu) {
  return chromium.launch({
    executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
    headless: true,
    args: ['--no-sandbox', ...(webgpu ? WEBGPU_FLAGS : [])],
  });
}

// Long tasks on the main thread, recorded from the start of the page.
const LONGTASK_SCRIPT = `
  window.__longTasks = [];
  new PerformanceObserver((list) => {
    for (const e of list.getEntries()) window.__longTasks.push({ start: e.startTime, duration: e.duration });
  }).observe({ type: 'longtask', buffered: true });
`;

// 4 steps and 160 vertices: the fewest for which the shipped models give faces on the
// fixture (2 steps or 64 vertices can give none), and SwiftShader is slow.
async function generate(page, { vertices = 160, steps = 4 } = {}) {
  const before = Number(await page.evaluate(() => document.body.dataset.generated ?? 0));
  await page.fill('#vertices', String(vertices));
  await page.fill('#steps', String(steps));
  const t0 = await page.evaluate(() => performance.now());
  await page.click('#generate');
  await page.waitForFunction((n) => Number(document.body.dataset.generated ?? 0) > n, before, {
    timeout: GENERATION_TIMEOUT,
  });
  const t1 = await page.evaluate(() => performance.now());
  return { t0, t1 };
}

async function canvasInkPixels(page) {
  const png = await page.locator('#canvas').screenshot();
  // Count pixels that are not the white background, decoding the PNG in the page.
  return page.evaluate(async (b64) => {
    const img = new Image();
    img.src = `data:image/png;base64,${b64}`;
    await img.decode();
    const c = new OffscreenCanvas(img.width, img.height);
    const ctx = c.getContext('2d');
    ctx.drawImage(img, 0, 0);
    const d = ctx.getImageData(0, 0, img.width, img.height).data;
    let ink = 0;
    for (let i = 0; i < d.length; i += 4) if (d[i] < 235 || d[i + 1] < 235 || d[i + 2] < 235) ink++;
    return ink;
  }, png.toString('base64'));
}

const server = await serve(0);
const base = `http://127.0.0.1:${server.address().port}`;
const out = mkdtempSync(join(tmpdir(), 'meshflow-e2e-'));

const browser = await launch(true);
const context = await browser.newContext({ acceptDownloads: true, viewport: { width: 1100, height: 800 } });
await context.addInitScript(LONGTASK_SCRIPT);
const page = await context.newPage();
const weightRequests = [];
context.on('request', (r) => r.method() === 'GET' && r.url().endsWith('.safetensors') && weightRequests.push(r.url()));
page.on('console', (m) => m.type() === 'error' && console.log(`  console: ${m.text()}`));

await check('the page loads the model on WebGPU and says so', async () => {
  await page.goto(`${base}/web/`);
  await page.screenshot({ path: join(out, 'before.png') });
  await page.waitForFunction(() => document.body.dataset.backend, null, { timeout: 120_000 });
  const backend = await page.evaluate(() => document.body.dataset.backend);
  assert(backend === 'webgpu', `backend ${backend}`);
  assert((await page.textContent('#backend')).includes('WebGPU'), 'backend not announced');
  // The mesh is drawn by the wgpu viewer on the model's device, in the worker.
  await page.waitForFunction(() => document.body.dataset.viewer);
  assert((await page.evaluate(() => document.body.dataset.viewer)) === 'wgpu', 'not the wgpu viewer');
  assert(weightRequests.length === 2, `weight downloads: ${weightRequests.length}`);
});

let timing = null;
await check('a fixture point cloud generates a visible mesh with stats', async () => {
  await page.setInputFiles('#file', FIXTURE);
  await page.waitForFunction(() => document.getElementById('input-info').textContent.includes('points'));
  timing = await generate(page);
  const faces = await page.textContent('#stats tr[data-key="vertices / faces"] td:last-child');
  assert(Number(faces.split('/')[1]) > 0, `faces: ${faces}`);
  const ink = await canvasInkPixels(page);
  assert(ink > 2000, `only ${ink} non-background pixels on the canvas`);
  await page.screenshot({ path: join(out, 'after.png') });
});

await check('no main-thread task longer than 50 ms during the generation', async () => {
  const tasks = await page.evaluate(() => window.__longTasks);
  const during = tasks.filter((t) => t.start + t.duration >= timing.t0 && t.start <= timing.t1);
  const events = await page.evaluate(() => window.__meshflowEvents);
  const near = events.filter((e) => during.some((t) => Math.abs(e.at - t.start) < 500));
  assert(
    during.length === 0,
    `long tasks during generation: ${JSON.stringify(during)}; worker messages near them: ${JSON.stringify(near)}`,
  );
});

await check('the GLB download passes the Khronos glTF validator', async () => {
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#download-glb')]);
  const file = join(out, 'download.glb');
  await download.saveAs(file);
  execFileSync('node', [join(ROOT, 'tests/validate-gltf.mjs'), file], { cwd: ROOT, stdio: 'pipe' });
});

await check('a malformed file shows an error and the page still works', async () => {
  await page.setInputFiles('#file', {
    name: 'broken.ply',
    mimeType: 'application/octet-stream',
    buffer: Buffer.from('ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1\n'),
  });
  await page.waitForSelector('#error:not([hidden])');
  const message = await page.textContent('#error');
  assert(message.includes('broken.ply'), `error text: ${message}`);
  await page.setInputFiles('#file', FIXTURE);
  await page.waitForFunction(() => document.getElementById('input-info').textContent.includes('stone_lantern'));
  await generate(page, { steps: 1 });
});

await check('a reload takes the weights from the cache', async () => {
  weightRequests.length = 0;
  await page.reload();
  await page.waitForFunction(() => document.body.dataset.backend, null, { timeout: 120_000 });
  assert(weightRequests.length === 0, `downloaded again: ${weightRequests}`);
  assert((await page.evaluate(() => document.body.dataset.weightsFromCache)) === 'true', 'not from cache');
});

await check('the page fits a phone-sized viewport', async () => {
  await page.setViewportSize({ width: 390, height: 844 });
  const width = await page.evaluate(() => document.documentElement.scrollWidth);
  assert(width <= 390, `horizontal overflow: ${width}px`);
});
await browser.close();

await check('without WebGPU the CPU fallback runs and is announced', async () => {
  const cpu = await launch(false);
  const p = await cpu.newPage();
  await p.goto(`${base}/web/`);
  await p.waitForFunction(() => document.body.dataset.backend, null, { timeout: 120_000 });
  assert((await p.evaluate(() => document.body.dataset.backend)) === 'cpu', 'not cpu');
  assert((await p.textContent('#backend')).includes('CPU'), 'fallback not announced');
  assert((await p.evaluate(() => document.body.dataset.viewer)) === '2d', 'no WebGPU, yet not the 2D viewer');
  await p.setInputFiles('#file', FIXTURE);
  await p.waitForFunction(() => document.getElementById('input-info').textContent.includes('points'));
  const ink = await canvasInkPixels(p);
  assert(ink > 500, `the 2D viewer drew only ${ink} pixels of the input points`);
  await generate(p, { steps: 1 });
  await cpu.close();
});

// The vertex positions and triangle indices of a GLB's first primitive.
function glbMesh(bytes) {
  const buf = Buffer.from(bytes);
  const jsonLength = buf.readUInt32LE(12);
  const gltf = JSON.parse(buf.subarray(20, 20 + jsonLength).toString('utf8'));
  const bin = buf.subarray(28 + jsonLength);
  const read = (index) => {
    const accessor = gltf.accessors[index];
    const view = gltf.bufferViews[accessor.bufferView];
    const offset = (view.byteOffset ?? 0) + (accessor.byteOffset ?? 0);
    const width = { SCALAR: 1, VEC3: 3 }[accessor.type];
    const Kind = { 5126: Float32Array, 5125: Uint32Array, 5123: Uint16Array }[accessor.componentType];
    const bytes = bin.subarray(offset, offset + accessor.count * width * Kind.BYTES_PER_ELEMENT);
    return Array.from(new Kind(bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.length)));
  };
  const primitive = gltf.meshes[0].primitives[0];
  return { positions: read(primitive.attributes.POSITION), indices: read(primitive.indices) };
}

// The native CLI from the cargo build scripts/test.sh ran before this file.
const NATIVE_CLI = join(
  process.env.CARGO_TARGET_DIR ?? join(process.env.HOME, '.cache/meshflow/target'),
  'release/meshflow',
);
const SAME_AS_NATIVE = { steps: 4, vertices: 160, seed: 7 };
let wasmMeshes = null;

await check('the npm package imports and generates the way a user would', async () => {
  // Pack the package, unpack it into node_modules of a plain ESM page, serve that.
  const app = join(out, 'app');
  mkdirSync(join(app, 'node_modules'), { recursive: true });
  const tgz = execFileSync('npm', ['pack', '--silent', '--pack-destination', out], { cwd: ROOT }).toString().trim();
  mkdirSync(join(app, 'node_modules/meshflow'));
  execFileSync('tar', ['-xzf', join(out, tgz), '-C', join(app, 'node_modules/meshflow'), '--strip-components=1']);
  writeFileSync(join(app, 'index.html'), '<!doctype html><script type="module" src="main.js"></script>');
  writeFileSync(
    join(app, 'main.js'),
    `import { loadModel, readPoints } from './node_modules/meshflow/web/lib/index.js';
     const bytes = new Uint8Array(await (await fetch('lantern.ply')).arrayBuffer());
     const points = await readPoints(bytes, 'lantern.ply');
     const options = ${JSON.stringify(SAME_AS_NATIVE)};
     // Both backends, for the comparison with the native CLI below.
     window.__glbs = {};
     try {
       for (const backend of ['webgpu', 'cpu']) {
         const model = await loadModel({ backend });
         const mesh = await model.generate(points, options);
         window.__glbs[backend] = Array.from(mesh.toGlb());
         if (backend === 'cpu') {
           const paper = await model.generate(points, { ...options, extraction: 'paper' });
           const filtered = await model.generate(points, { ...options, extraction: 'paper', dropNonManifold: true });
           let refused = '';
           try { await model.generate(points, { ...options, dropNonManifold: true }); } catch (e) { refused = e.message; }
           let both = '';
           try { await model.generate(points, { ...options, faces: 100 }); } catch (e) { both = e.message; }
           let tooFew = '';
           try { await model.generate(points.slice(0, 30), { steps: 1 }); } catch (e) { tooFew = e.message; }
           const raw = await model.generate(points, { ...options, fit: false });
           const byFaces = await model.generate(points, { steps: 2, faces: 120 });
           window.__options = { both, tooFew, rawFaces: raw.indices.length / 3, fitS: mesh.report.times.fit_s,
             byFaces: { budget: byFaces.report.vertexBudget, faces: byFaces.indices.length / 3 } };
           window.__filtered = { faces: filtered.indices.length / 3, paper: paper.indices.length / 3,
             nonManifold: filtered.report.topology.non_manifold_edges, refused,
             manifold: { faces: mesh.indices.length / 3, nonManifold: mesh.report.topology.non_manifold_edges,
               inconsistent: mesh.report.topology.inconsistent_winding_edges },
             paperNonManifold: paper.report.topology.non_manifold_edges };
         }
       }
       document.body.dataset.done = 'ok';
     } catch (e) {
       document.body.dataset.done = String(e?.message ?? e);
     }`,
  );
  writeFileSync(join(app, 'lantern.ply'), readFileSync(FIXTURE));
  const { createServer } = await import('node:http');
  const appServer = createServer((req, res) => {
    const path = join(app, decodeURIComponent(new URL(req.url, 'http://x').pathname));
    try {
      const body = readFileSync(path.endsWith('/') ? join(path, 'index.html') : path);
      const type = path.endsWith('.js') ? 'text/javascript' : path.endsWith('.wasm') ? 'application/wasm' : path.endsWith('.html') || path.endsWith('/') ? 'text/html' : 'application/octet-stream';
      res.writeHead(200, { 'content-type': type, 'content-length': body.length });
      res.end(req.method === 'HEAD' ? undefined : body);
    } catch {
      res.writeHead(404);
      res.end();
    }
  });
  await new Promise((ok) => appServer.listen(0, '127.0.0.1', ok));
  const b = await launch(true);
  const p = await b.newPage();
  p.on('pageerror', (e) => console.log(`  pageerror: ${e.message}`));
  await p.goto(`http://127.0.0.1:${appServer.address().port}/`);
  await p.waitForFunction(() => document.body?.dataset.done, null, { timeout: GENERATION_TIMEOUT });
  const done = await p.evaluate(() => document.body.dataset.done);
  assert(done === 'ok', `the package threw: ${done}`);
  const glbs = await p.evaluate(() => window.__glbs);
  const filtered = await p.evaluate(() => window.__filtered);
  const optionChecks = await p.evaluate(() => window.__options);
  await b.close();
  appServer.close();
  wasmMeshes = Object.fromEntries(Object.entries(glbs).map(([k, v]) => [k, glbMesh(Uint8Array.from(v))]));
  assert(wasmMeshes.webgpu.indices.length > 0, 'the WebGPU mesh has no faces');
  // The default extraction is manifold and consistently wound; 'paper' reaches Algorithm 1,
  // and its optional filter leaves no edge with a third face.
  const f = filtered;
  assert(f.manifold.faces > 0 && f.manifold.nonManifold === 0 && f.manifold.inconsistent === 0, `default extraction: ${JSON.stringify(f)}`);
  assert(f.paper > 0, `extraction: 'paper': ${JSON.stringify(f)}`);
  assert(f.nonManifold === 0 && f.faces > 0, `dropNonManifold: ${JSON.stringify(f)}`);
  assert(/applies to extraction: 'paper' only/.test(f.refused), `dropNonManifold without 'paper' was not refused: ${f.refused}`);
  // Face counts, fitting and bad input across the wasm boundary.
  const o = optionChecks;
  assert(/vertices or for faces, not both/.test(o.both), `vertices with faces was not refused: ${o.both}`);
  assert(/has 10 points; at least 16/.test(o.tooFew), `10 points were not refused: ${o.tooFew}`);
  assert(o.rawFaces > 0 && o.fitS >= 0, `fit: false: ${JSON.stringify(o)}`);
  assert(o.byFaces.budget === Math.round(120 / 1.05) && o.byFaces.faces > 0, `faces: 120: ${JSON.stringify(o)}`);
});

await check('wasm and native give the same mesh for the same seed and input', async () => {
  assert(wasmMeshes, 'the npm-package check produced no meshes');
  // Within 1e-4 in the model's frame, where the input's bounding box spans [-1, 1] (input
  // coordinates reach about 50 here, so that is 1e-4 * extent / 2 in the input's units).
  const fixture = readFileSync(FIXTURE, 'utf8').split('end_header')[1].trim().split(/\s+/).map(Number);
  const extent = Math.max(...[0, 1, 2].map((a) => {
    const axis = fixture.filter((_, i) => i % 3 === a);
    return Math.max(...axis) - Math.min(...axis);
  }));
  const report = [];
  for (const [wasmBackend, nativeBackend] of [['webgpu', 'wgpu'], ['cpu', 'cpu']]) {
    const file = join(out, `native-${nativeBackend}.glb`);
    const { steps, vertices, seed } = SAME_AS_NATIVE;
    execFileSync(NATIVE_CLI, ['generate', FIXTURE, '-o', file, '--steps', String(steps), '--vertices',
      String(vertices), '--seed', String(seed), '--backend', nativeBackend], { cwd: ROOT, stdio: 'pipe' });
    const native = glbMesh(readFileSync(file));
    const wasm = wasmMeshes[wasmBackend];
    assert(
      JSON.stringify(native.indices) === JSON.stringify(wasm.indices),
      `${wasmBackend}: faces differ (${wasm.indices.length / 3} in wasm, ${native.indices.length / 3} native)`,
    );
    assert(native.positions.length === wasm.positions.length, `${wasmBackend}: vertex counts differ`);
    let worst = 0;
    native.positions.forEach((v, i) => { worst = Math.max(worst, Math.abs(v - wasm.positions[i])); });
    const modelFrame = (worst * 2) / extent;
    report.push(`${wasmBackend} vs native ${nativeBackend}: ${wasm.indices.length / 3} faces, max |dv| ${worst.toExponential(2)} (${modelFrame.toExponential(2)} in the model frame)`);
    assert(modelFrame <= 1e-4, report.at(-1));
  }
  console.log(`  ${report.join('\n  ')}`);
});

server.close();
const failed = results.filter(([, ok]) => !ok).length;
console.log(`browser: ${results.length - failed} passed, ${failed} failed (screenshots in ${out})`);
process.exit(failed ? 1 : 0);
