// The page's CPU module in V8 (Node runs the same engine as Chromium), one thread: the
// generations that bench/cpu_profile/run.sh profiles with `node --cpu-prof` (wasm_self.py
// then keeps the samples inside `MeshFlow.generate`). Not a test.
//   node --cpu-prof --cpu-prof-dir DIR bench/cpu_profile/wasm.mjs PKG_DIR INPUT ROUNDS OUT.json
// PKG_DIR holds meshflow_cpu.js and its module built with its name section (run.sh makes it
// with wasm-bindgen from cargo's output, before wasm-opt strips the names). It runs ROUNDS + 1
// generations, the first a warm-up that is profiled too (as `meshflow bench generate` is under
// perf); OUT.json gets their mean wall time and the last one's stage times.
import { readFileSync, writeFileSync } from 'node:fs';
import { join, resolve } from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

const ROOT = resolve(fileURLToPath(new URL('../..', import.meta.url)));
const [pkg, input, rounds, out] = process.argv.slice(2);
const glue = await import(pathToFileURL(join(resolve(pkg), 'meshflow_cpu.js')).href);
await glue.default({ module_or_path: readFileSync(join(pkg, 'meshflow_cpu_bg.wasm')) });
const weights = (name) => readFileSync(join(ROOT, 'weights', name));
const model = await glue.MeshFlow.load(
  weights('vae.manifest.json').toString(),
  weights('vae.safetensors'),
  weights('dit.manifest.json').toString(),
  weights('dit.safetensors'),
  'cpu',
);
const points = glue.readInput(readFileSync(input), input).points;
const started = performance.now();
let stages = null;
for (let r = 0; r <= Number(rounds); r++) {
  const mesh = await model.generate(points, '{}', null);
  stages = JSON.parse(mesh.report).times;
}
const wall = (performance.now() - started) / 1000 / (Number(rounds) + 1);
writeFileSync(out, JSON.stringify({ wall_s: wall, stages }, null, 1));
