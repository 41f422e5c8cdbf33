// The page's CPU module in V8 (Node runs the same engine as Chromium), one thread, profiled by
// the inspector's sampling profiler around the generations only: self time per wasm function,
// for bench/cpu_profile/run.sh. Not a test.
//   node bench/cpu_profile/wasm.mjs PKG_DIR INPUT ROUNDS OUT.json
// PKG_DIR holds meshflow_cpu.js and its module built with its name section (run.sh makes it
// with wasm-bindgen from cargo's output, before wasm-opt strips the names).
import { readFileSync, writeFileSync } from 'node:fs';
import { Session } from 'node:inspector/promises';
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
await model.generate(points, '{}', null); // warm-up, unprofiled

const session = new Session();
session.connect();
await session.post('Profiler.enable');
await session.post('Profiler.setSamplingInterval', { interval: 500 });
await session.post('Profiler.start');
const started = performance.now();
let stages = null;
for (let r = 0; r < Number(rounds); r++) {
  const mesh = await model.generate(points, '{}', null);
  stages = JSON.parse(mesh.report).times;
}
const wall = (performance.now() - started) / 1000;
const { profile } = await session.post('Profiler.stop');

// Self time per function: each sample's interval to the node it landed in.
const byId = new Map(profile.nodes.map((n) => [n.id, n]));
const self = new Map();
for (let i = 0; i < profile.samples.length; i++) {
  const name = byId.get(profile.samples[i]).callFrame.functionName || '(anonymous)';
  const dt = (profile.timeDeltas[i + 1] ?? 0) / 1e6;
  self.set(name, (self.get(name) ?? 0) + dt);
}
const perGeneration = Object.fromEntries(
  [...self].map(([name, s]) => [name, s / Number(rounds)]).sort((a, b) => b[1] - a[1]),
);
writeFileSync(out, JSON.stringify({ wall_s: wall / Number(rounds), stages, self_s: perGeneration }, null, 1));
