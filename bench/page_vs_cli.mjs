// The page's CPU path against `meshflow generate` on the same input and machine, side by side
// in one run, per stage; and the page's first visit with an empty and with a warm cache.
// Not a test: run it by hand on an otherwise idle machine, after building both,
//   bash scripts/build-web.sh && cargo build --release -p meshflow-cli
//   node bench/page_vs_cli.mjs [--rounds 3] [--input FILE] [-o bench/page_vs_cli.json]
// First visit: a fresh browser profile opens /web/?backend=cpu, and the time from navigation
// to the mesh on screen is taken (the weights downloaded from the local server, so the
// network is not in it), then again after a reload (weights from Cache Storage, the wasm from
// the HTTP cache). Then `--rounds` rounds alternate one warm page generation and one
// `meshflow generate INPUT --json --backend cpu` process, both at the page's defaults (the
// budget from the shape, 12 candidates of 4 midpoint steps, seed 0, sharpened): the page's
// figure is click to mesh, the CLI's the whole process (start, weights, generation, GLB
// written), and both report their stage times; a third process per round runs the CLI on one
// thread (RAYON_NUM_THREADS=1), which parts the page's threads from wasm's own cost. The page
// runs three times a round, each in its own tab of the same browser: as web/serve.mjs serves
// it (cross-origin isolated: the threaded module on one thread per core), as a host without
// COOP/COEP would (the candidates drawn on one single-threaded module per core,
// web/lib/candidates.js), and there with `?workers=1` (every candidate on one module, as
// before 2026-12-02); all three must make the same mesh. The first visit is the isolated page's.
// MESHFLOW names the CLI (default
// $CARGO_TARGET_DIR/release/meshflow); CHROMIUM the browser (default /usr/bin/chromium).
import { execSync } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { cpus, tmpdir } from 'node:os';
import { join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { serve } from '../web/serve.mjs';
import { STAGES, chromiumVersion, generateOnCli, generateOnPage, launchBrowser, median, meshflowBinary, openPage } from './page_timing.mjs';

const ROOT = resolve(fileURLToPath(new URL('..', import.meta.url)));
const arg = (name, fallback) => (process.argv.includes(name) ? process.argv[process.argv.indexOf(name) + 1] : fallback);
const rounds = Number(arg('--rounds', 3)) || 3;
const input = resolve(arg('--input', join(ROOT, 'tests/fixtures/points/stone_lantern_2048.ply')));
const outFile = arg('-o', join(ROOT, 'bench/page_vs_cli.json'));
const meshflow = meshflowBinary();

const server = await serve(0);
const url = `http://127.0.0.1:${server.address().port}/web/?backend=cpu`;
const plainServer = await serve(0, { isolated: false });
const plainUrl = `http://127.0.0.1:${plainServer.address().port}/web/?backend=cpu`;
const work = mkdtempSync(join(tmpdir(), 'meshflow-page-vs-cli-'));

// Navigation (or reload) to the mesh on screen, less the scripted file pick and clicks; or, with
// no `navigate`, one warm generation.
async function pageRun(page, navigate) {
  const ready = navigate ? await openPage(page, navigate, input) : null;
  const run = await generateOnPage(page);
  return { model_ready_s: ready, ...run, time_to_first_mesh_s: navigate ? ready + run.generate_s : null };
}

const cliRun = (env = {}) => generateOnCli(meshflow, input, join(work, 'cli.glb'), env);

const profile = mkdtempSync(join(tmpdir(), 'meshflow-bench-'));
const context = await launchBrowser(profile);
const page = context.pages()[0] ?? (await context.newPage());
const cold = await pageRun(page, () => page.goto(url));
const warmVisit = await pageRun(page, () => page.reload());
const threads = Number(await page.evaluate(() => document.body.dataset.threads));
const plain = await context.newPage();
await pageRun(plain, () => plain.goto(plainUrl));
const workers = Number(await plain.evaluate(() => document.body.dataset.workers));
const single = await context.newPage();
await pageRun(single, () => single.goto(`${plainUrl}&workers=1`));
const singleRuns = [];
const workersRuns = [];
const pageRuns = [];
const cliRuns = [];
const oneThreadRuns = [];
// Each tab is brought to the front before it generates (generateOnPage).
for (let i = 0; i < rounds; i++) {
  pageRuns.push(await pageRun(page, null));
  workersRuns.push(await pageRun(plain, null));
  singleRuns.push(await pageRun(single, null));
  cliRuns.push(cliRun());
  oneThreadRuns.push(cliRun({ RAYON_NUM_THREADS: '1' }));
  const p = pageRuns.at(-1), w = workersRuns.at(-1), s1 = singleRuns.at(-1), c = cliRuns.at(-1), o = oneThreadRuns.at(-1);
  if (p.faces !== s1.faces || p.vertices !== s1.vertices || w.faces !== s1.faces || w.vertices !== s1.vertices) {
    throw new Error(`${threads} threads, ${workers} workers and one module differ: ${p.faces} / ${w.faces} / ${s1.faces} faces`);
  }
  console.log(
    `round ${i + 1}: page ${p.generate_s.toFixed(2)} s on ${threads} threads (${p.faces} faces), on ${workers} workers ` +
      `${w.generate_s.toFixed(2)} s, on one module ` +
      `${s1.generate_s.toFixed(2)} s, CLI ${c.process_s.toFixed(2)} s (${c.faces} faces), CLI on one thread ${o.process_s.toFixed(2)} s`,
  );
}
await context.close();
server.close();
plainServer.close();
rmSync(profile, { recursive: true, force: true });
rmSync(work, { recursive: true, force: true });

const pageMedian = median(pageRuns.map((r) => r.generate_s));
const workersMedian = median(workersRuns.map((r) => r.generate_s));
const singleMedian = median(singleRuns.map((r) => r.generate_s));
const cliMedian = median(cliRuns.map((r) => r.process_s));
const stageTable = STAGES.map((k) => ({
  stage: k.replace(/_s$/, ''),
  page_s: median(pageRuns.map((r) => r.stages_s[k])),
  page_workers_s: median(workersRuns.map((r) => r.stages_s[k])),
  page_one_module_s: median(singleRuns.map((r) => r.stages_s[k])),
  cli_s: median(cliRuns.map((r) => r.stages_s[k])),
  cli_one_thread_s: median(oneThreadRuns.map((r) => r.stages_s[k])),
}));
const cpuWasm = join(ROOT, 'web/pkg/meshflow_cpu_threads_bg.wasm');
const result = {
  method:
    `node bench/page_vs_cli.mjs --rounds ${rounds}: headless ${chromiumVersion()}, ` +
    `the page's CPU path (cross-origin isolated on ${threads} threads; not isolated, its candidates on ${workers} workers, and on one module with ?workers=1) and \`meshflow generate --backend cpu\` alternating on ${input.slice(ROOT.length + 1)} at the defaults; medians`,
  machine: `${cpus()[0].model}, ${cpus().length} threads`,
  commit: execSync('git rev-parse --short HEAD', { cwd: ROOT }).toString().trim(),
  cpu_wasm_bytes: readFileSync(cpuWasm).length,
  first_visit: { empty_cache: cold, warm_cache: warmVisit },
  page_threads: threads,
  page_workers: workers,
  page_generate_s: pageMedian,
  page_workers_generate_s: workersMedian,
  page_one_module_generate_s: singleMedian,
  cli_process_s: cliMedian,
  cli_one_thread_process_s: median(oneThreadRuns.map((r) => r.process_s)),
  ratio: pageMedian / cliMedian,
  stages: stageTable,
  page: pageRuns,
  page_on_workers: workersRuns,
  page_one_module: singleRuns,
  cli: cliRuns,
  cli_one_thread: oneThreadRuns,
};
writeFileSync(outFile, `${JSON.stringify(result, null, 2)}\n`);
console.log(`first mesh from navigation: empty cache ${cold.time_to_first_mesh_s.toFixed(2)} s, warm ${warmVisit.time_to_first_mesh_s.toFixed(2)} s`);
console.log(`page ${pageMedian.toFixed(2)} s on ${threads} threads against the CLI's ${cliMedian.toFixed(2)} s: ${(pageMedian / cliMedian).toFixed(2)}x` +
  ` (${workers} workers ${workersMedian.toFixed(2)} s: ${(workersMedian / cliMedian).toFixed(2)}x; one module ${singleMedian.toFixed(2)} s: ${(singleMedian / cliMedian).toFixed(2)}x)`);
for (const s of stageTable) {
  console.log(
    `  ${s.stage.padEnd(10)} page ${s.page_s.toFixed(3)} s  workers ${s.page_workers_s.toFixed(3)} s  one module ${s.page_one_module_s.toFixed(3)} s  CLI ${s.cli_s.toFixed(3)} s (${(s.page_s / s.cli_s).toFixed(1)}x)  ` +
      `CLI one thread ${s.cli_one_thread_s.toFixed(3)} s (${(s.page_s / s.cli_one_thread_s).toFixed(1)}x)`,
  );
}
console.log(`written to ${outFile}`);
