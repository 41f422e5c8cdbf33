// Time to first mesh and per-stage times of the web page in Debian's headless Chromium,
// written to bench/browser.json. Not a test: run it by hand after scripts/build-web.sh,
//   node bench/browser.mjs [--steps 4] [--samples 12] [--no-sharpen] [--no-isolation] [--cpu-only [--runs N] -o FILE]
// Three runs of the lantern scan at the page's defaults (vertex budget from the shape, 4
// midpoint steps, 12 candidates, seed 0, sharpened):
//   cold:  a fresh browser profile, so the weights are downloaded and nothing is cached;
//   warm:  the same profile reloaded, weights from Cache Storage;
//   cpu:   WebGPU off, the CPU fallback inside wasm (warm, from its own first load).
// WebGPU here is SwiftShader, a CPU implementation of Vulkan: these are the figures of a
// machine without a GPU, not of a visitor's GPU. --cpu-only skips the (slow) WebGPU runs and
// times N warm CPU runs (default 3) into FILE, for comparing two builds side by side. The page
// is served cross-origin isolated, as web/serve.mjs serves it (the CPU path on the threaded
// module); --no-isolation serves it as a host without COOP/COEP would (single-threaded modules
// on workers).
import { chromium } from 'playwright-core';
import { existsSync, mkdtempSync, rmSync, statSync, writeFileSync } from 'node:fs';
import { execSync } from 'node:child_process';
import { cpus, tmpdir } from 'node:os';
import { join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { serve } from '../web/serve.mjs';

const ROOT = resolve(fileURLToPath(new URL('..', import.meta.url)));
const arg = (name, fallback) => (process.argv.includes(name) ? process.argv[process.argv.indexOf(name) + 1] : fallback);
const steps = Number(arg('--steps', 4)) || 4;
// The page's Sharpen box unticked: the pipeline before sharpening, to time it side by side.
const sharpen = !process.argv.includes('--no-sharpen');
const samples = Number(arg('--samples', 12)) || 12;
const cpuOnly = process.argv.includes('--cpu-only');
const WEBGPU_FLAGS = ['--enable-unsafe-webgpu', '--use-angle=swiftshader', '--use-vulkan=swiftshader', '--enable-features=Vulkan'];
// The lantern scan the earlier figures used (the page's own examples are not from the training
// data; this fixture is kept for comparability).
const INPUT = join(ROOT, 'tests/fixtures/points/stone_lantern_2048.ply');

const isolated = !process.argv.includes('--no-isolation');
const server = await serve(0, { isolated });
// WebGPU is asked for explicitly: 'auto' would pick the CPU on SwiftShader.
const url = (webgpu) => `http://127.0.0.1:${server.address().port}/web/?backend=${webgpu ? 'webgpu' : 'cpu'}`;

// Opens the page (navigation start = 0), waits for the model, picks the example, generates.
async function firstMesh(page, reload, webgpu) {
  await (reload ? page.reload() : page.goto(url(webgpu)));
  await page.waitForFunction(() => document.body.dataset.backend, null, { timeout: 600_000 });
  const ready = await page.evaluate(() => performance.now());
  await page.setInputFiles('#file', INPUT);
  await page.waitForFunction(() => document.getElementById('input-info').textContent.includes('points'));
  await page.fill('#steps', String(steps));
  await page.fill('#samples', String(samples));
  await page.setChecked('#sharpen', sharpen);
  const clicked = await page.evaluate(() => performance.now());
  await page.click('#generate');
  await page.waitForFunction(() => window.__meshflowReport, null, { timeout: 1_800_000 });
  const done = await page.evaluate(() => performance.now());
  const report = await page.evaluate(() => window.__meshflowReport);
  return {
    backend: await page.evaluate(() => document.body.dataset.backend),
    wasm_module: (await page.evaluate(() => document.body.dataset.wasmModule)) ?? 'webgpu',
    weights_from_cache: (await page.evaluate(() => document.body.dataset.weightsFromCache)) === 'true',
    model_ready_s: ready / 1000,
    generate_s: (done - clicked) / 1000,
    // Navigation to mesh on screen, less the file upload and the scripted clicks.
    time_to_first_mesh_s: (ready + done - clicked) / 1000,
    stages_s: report.times,
    vertex_budget: report.vertexBudget,
    vertices: report.topology.vertices,
    faces: report.topology.faces,
  };
}

async function run(webgpu, runs) {
  const profile = mkdtempSync(join(tmpdir(), 'meshflow-bench-'));
  const context = await chromium.launchPersistentContext(profile, {
    executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
    headless: true,
    args: ['--no-sandbox', ...(webgpu ? WEBGPU_FLAGS : [])],
  });
  const page = context.pages()[0] ?? (await context.newPage());
  const results = [];
  for (const reload of runs) results.push(await firstMesh(page, reload, webgpu));
  await context.close();
  rmSync(profile, { recursive: true, force: true });
  return results;
}

// The module the CPU path loads: meshflow_cpu where it is built (since the split), else the one
// module of earlier builds.
const wasm = join(ROOT, 'web/pkg/meshflow_bg.wasm');
const cpuModule = join(ROOT, `web/pkg/${isolated ? 'meshflow_cpu_threads' : 'meshflow_cpu'}_bg.wasm`);
const cpuWasm = existsSync(cpuModule) ? cpuModule : wasm;
if (cpuOnly) {
  const runs = Number(arg('--runs', 3)) || 3;
  const [, ...warm] = await run(false, [false, ...Array(runs).fill(true)]);
  server.close();
  const result = {
    method: `node bench/browser.mjs --cpu-only: headless Chromium ${execSync('chromium --version').toString().trim()}, ` +
      `the CPU path in wasm (${isolated ? 'cross-origin isolated: the threaded module' : 'not isolated: single-threaded modules on workers'}), the lantern scan at the page defaults with ${steps} steps and ${samples} candidates${sharpen ? '' : ', not sharpened'}, ${runs} warm runs after a first load`,
    machine: `${cpus()[0].model}, ${cpus().length} threads`,
    wasm_file: cpuWasm.slice(ROOT.length + 1),
    wasm_bytes: statSync(cpuWasm).size,
    wasm_gzip_bytes: Number(execSync(`gzip -9 -c ${cpuWasm} | wc -c`).toString()),
    cpu: warm,
  };
  writeFileSync(arg('-o', join(ROOT, 'bench/browser_cpu.json')), `${JSON.stringify(result, null, 2)}\n`);
  console.log(warm.map((r) => `generate ${r.generate_s.toFixed(2)} s (sample ${r.stages_s.sample_s.toFixed(2)} s)`).join('\n'));
  process.exit(0);
}
const [cold, warm] = await run(true, [false, true]);
const [, cpu] = await run(false, [false, true]);
server.close();
const result = {
  method: `node bench/browser.mjs: headless Chromium ${execSync('chromium --version').toString().trim()} ` +
    `(WebGPU = SwiftShader), the lantern scan at the page defaults with ${steps} steps and ${samples} candidates${sharpen ? '' : ', not sharpened'}, one run each`,
  machine: `${cpus()[0].model}, ${cpus().length} threads`,
  wasm_bytes: statSync(wasm).size,
  wasm_gzip_bytes: Number(execSync(`gzip -9 -c ${wasm} | wc -c`).toString()),
  cold,
  warm,
  cpu_fallback: cpu,
};
writeFileSync(join(ROOT, 'bench/browser.json'), `${JSON.stringify(result, null, 2)}\n`);
console.log(JSON.stringify(result, null, 2));
