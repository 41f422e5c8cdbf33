// Replace the bodies of named functions in a wasm module with `unreachable`, so that a later
// `wasm-opt` drops everything only they reached (the technique of the Rust wasm book's
// "wasm-snip", on binaryen's own reader and writer, which know every wasm feature we use).
//
//     node scripts/snip-wasm.mjs IN.wasm OUT.wasm REGEX...
//
// The module must still carry its name section (wasm-bindgen keeps it, and so does this script;
// wasm-opt drops it). The wasm features it is written with are the ones its target_features
// section declares, as read: forcing more (say binaryen's `All`) writes encodings that browsers
// reject.
// Fails, writing nothing, when no function matches: a dependency that renamed what the
// patterns name would otherwise silently bring the code back.
//
// scripts/build-web.sh uses it for code that the WebGPU module links but can never run
// (BENCHMARKS.md "Module and weight sizes"; docs/experiments/2026-11-25-wasm-module-size.md).
// A snipped function that does run traps with "unreachable", a loud failure that the browser
// tests would catch, never a wrong mesh.
import binaryen from 'binaryen';
import fs from 'node:fs';
import { fileURLToPath } from 'node:url';

/**
 * Snip every defined function whose name matches one of `patterns` (RegExp or string).
 * Returns the new module's bytes and the names snipped. Throws when nothing matches.
 */
export function snipFunctions(bytes, patterns) {
    const regexes = patterns.map((p) => (p instanceof RegExp ? p : new RegExp(p)));
    if (regexes.length === 0) throw new Error('snip-wasm: no patterns given');
    const module = binaryen.readBinary(bytes);
    try {
        const snipped = [];
        for (let i = 0; i < module.getNumFunctions(); i++) {
            const func = module.getFunctionByIndex(i);
            const info = binaryen.getFunctionInfo(func);
            // Imports have no body to replace.
            if (!info.body || !regexes.some((r) => r.test(info.name))) continue;
            binaryen.Function.setBody(func, module.unreachable());
            snipped.push(info.name);
        }
        if (snipped.length === 0) {
            throw new Error(
                `snip-wasm: no function matches ${regexes.map(String).join(', ')} ` +
                    '(renamed by a dependency update, or the name section is missing)',
            );
        }
        // Names are kept, so the output can be snipped again or read in a debugger.
        const debugInfo = binaryen.getDebugInfo();
        binaryen.setDebugInfo(true);
        try {
            return { bytes: module.emitBinary(), snipped };
        } finally {
            binaryen.setDebugInfo(debugInfo);
        }
    } finally {
        module.dispose();
    }
}

function main(argv) {
    const [input, output, ...patterns] = argv;
    if (!input || !output || patterns.length === 0) {
        console.error('usage: node scripts/snip-wasm.mjs IN.wasm OUT.wasm REGEX...');
        process.exit(2);
    }
    const { bytes, snipped } = snipFunctions(fs.readFileSync(input), patterns);
    // Written beside the target and renamed, so a failure never leaves half a module.
    const partial = `${output}.partial`;
    fs.writeFileSync(partial, bytes);
    fs.renameSync(partial, output);
    console.log(`snip-wasm: ${snipped.length} functions replaced by unreachable`);
}

// Run as a command, also through a symlinked path (import.meta.url has symlinks resolved).
if (process.argv[1] && fs.realpathSync(process.argv[1]) === fileURLToPath(import.meta.url)) {
    try {
        main(process.argv.slice(2));
    } catch (err) {
        console.error(err.message);
        process.exit(1);
    }
}
