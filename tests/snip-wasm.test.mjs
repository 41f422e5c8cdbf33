// Tests of scripts/snip-wasm.mjs on a small module built here: `node tests/snip-wasm.test.mjs`.
// Prints one line per check and a "snip-wasm: N passed, N failed" tally (scripts/test.sh sums it).
import binaryen from 'binaryen';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { snipFunctions } from '../scripts/snip-wasm.mjs';

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');

// cube::gpu_kernel(x) = 2x; cube::cpu_kernel(x) = 3x, reached only through pick_cpu; keep(x) = x+1;
// and an imported function, which has no body to snip. Names as Rust's mangling would give.
function fixture() {
    const m = new binaryen.Module();
    const i32 = binaryen.i32;
    const x = () => m.local.get(0, i32);
    m.addFunctionImport('host_log', 'env', 'log', i32, binaryen.none);
    m.addFunction('cube::gpu_kernel', i32, i32, [], m.i32.mul(x(), m.i32.const(2)));
    m.addFunction('cube::cpu_kernel', i32, i32, [], m.i32.mul(x(), m.i32.const(3)));
    m.addFunction('pick_cpu', i32, i32, [], m.call('cube::cpu_kernel', [x()], i32));
    m.addFunction('keep', i32, i32, [], m.i32.add(x(), m.i32.const(1)));
    for (const name of ['cube::gpu_kernel', 'pick_cpu', 'keep']) m.addFunctionExport(name, name);
    // Declared features, written as rustc writes them: the snip must keep exactly these.
    m.setFeatures(binaryen.Features.MutableGlobals | binaryen.Features.SignExt);
    const section = [2];
    for (const name of ['mutable-globals', 'sign-ext']) section.push(0x2b, name.length, ...new TextEncoder().encode(name));
    m.addCustomSection('target_features', new Uint8Array(section));
    assert.ok(m.validate());
    // The name section is what the patterns match against, as in wasm-bindgen's output.
    const debugInfo = binaryen.getDebugInfo();
    binaryen.setDebugInfo(true);
    try {
        return m.emitBinary();
    } finally {
        binaryen.setDebugInfo(debugInfo);
        m.dispose();
    }
}

// The features a module declares in its target_features section, e.g. ['+mutable-globals'].
function declaredFeatures(bytes) {
    const [section] = WebAssembly.Module.customSections(new WebAssembly.Module(bytes), 'target_features');
    if (!section) return [];
    const b = new Uint8Array(section);
    const features = [];
    let p = 1; // the count is below 128 here: one byte
    for (let i = 0; i < b[0]; i++) {
        const prefix = String.fromCharCode(b[p]);
        const len = b[p + 1];
        features.push(prefix + new TextDecoder().decode(b.slice(p + 2, p + 2 + len)));
        p += 2 + len;
    }
    return features.sort();
}

// The module's exports, instantiated synchronously (the fixture is tiny).
function run(bytes) {
    return new WebAssembly.Instance(new WebAssembly.Module(bytes), { env: { log() {} } }).exports;
}

const checks = [];
const check = (name, fn) => checks.push([name, fn]);

check('a snipped function traps; the others compute as before', async () => {
    const before = run(fixture());
    assert.equal(before.pick_cpu(5), 15);
    const { bytes, snipped } = snipFunctions(fixture(), ['::cpu_kernel$']);
    assert.deepEqual(snipped, ['cube::cpu_kernel']);
    const after = run(bytes);
    assert.equal(after.keep(5), 6);
    assert.equal(after['cube::gpu_kernel'](5), 10);
    assert.throws(() => after.pick_cpu(5), (e) => e instanceof WebAssembly.RuntimeError && /unreachable/.test(e.message));
});

check('the module keeps its declared features and its names', async () => {
    const input = fixture();
    assert.deepEqual(declaredFeatures(input), ['+mutable-globals', '+sign-ext']);
    const { bytes } = snipFunctions(input, ['cpu_kernel']);
    assert.deepEqual(declaredFeatures(bytes), ['+mutable-globals', '+sign-ext']);
    // With its names kept, the output can be snipped again.
    assert.deepEqual(snipFunctions(bytes, ['gpu_kernel']).snipped, ['cube::gpu_kernel']);
});

check('several patterns; imports are never touched', async () => {
    const { bytes, snipped } = snipFunctions(fixture(), [/^cube::/, 'host_log']);
    assert.deepEqual(snipped.sort(), ['cube::cpu_kernel', 'cube::gpu_kernel']);
    const after = run(bytes);
    assert.equal(after.keep(1), 2);
});

check('no match is an error naming the pattern', async () => {
    assert.throws(() => snipFunctions(fixture(), ['tiled::cmma']), /no function matches \/tiled::cmma\//);
});

check('the command writes nothing when it fails, and the module when it succeeds', async () => {
    const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'snip-wasm-'));
    try {
        const input = path.join(dir, 'in.wasm');
        const output = path.join(dir, 'out.wasm');
        fs.writeFileSync(input, fixture());
        const script = path.join(ROOT, 'scripts', 'snip-wasm.mjs');
        const miss = spawnSync(process.execPath, [script, input, output, 'nothing_like_this'], { encoding: 'utf8' });
        assert.equal(miss.status, 1);
        assert.match(miss.stderr, /no function matches/);
        assert.deepEqual(fs.readdirSync(dir), ['in.wasm']);
        const hit = spawnSync(process.execPath, [script, input, output, 'cpu_kernel'], { encoding: 'utf8' });
        assert.equal(hit.status, 0, hit.stderr);
        assert.match(hit.stdout, /1 functions replaced/);
        const written = run(fs.readFileSync(output));
        assert.equal(written.keep(2), 3);
        assert.throws(() => written.pick_cpu(2), /unreachable/);
        // In place, as scripts/build-web.sh runs it, and through a symlinked path.
        const link = path.join(dir, 'snip-link.mjs');
        fs.symlinkSync(script, link);
        const inPlace = spawnSync(process.execPath, [link, input, input, 'cpu_kernel'], { encoding: 'utf8' });
        assert.equal(inPlace.status, 0, inPlace.stderr);
        assert.throws(() => run(fs.readFileSync(input)).pick_cpu(2), /unreachable/);
        assert.deepEqual(fs.readdirSync(dir).sort(), ['in.wasm', 'out.wasm', 'snip-link.mjs']);
    } finally {
        fs.rmSync(dir, { recursive: true, force: true });
    }
});

let passed = 0;
let failed = 0;
for (const [name, fn] of checks) {
    try {
        await fn();
        passed++;
        console.log(`ok   ${name}`);
    } catch (err) {
        failed++;
        console.log(`FAIL ${name}\n     ${err.stack ?? err}`);
    }
}
console.log(`snip-wasm: ${passed} passed, ${failed} failed`);
process.exit(failed === 0 ? 0 : 1);
