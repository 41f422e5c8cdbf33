#!/usr/bin/env bash
# Build the browser module: `bash scripts/build-web.sh`.
#
# 1. compiles the crate's wasm-bindgen API for wasm32 as a cdylib in the `wasm-release` profile
#    (opt-level z, fat LTO), twice: features `web,wgpu` (meshflow: WebGPU and the CPU) and
#    `web` (meshflow_cpu: the CPU alone, the smaller download);
# 2. runs wasm-bindgen (the CLI at the exact version in Cargo.lock, installed if missing)
#    with `--target web` into web/pkg/;
# 3. shrinks each with npm binaryen@132's `wasm-opt -Oz` (Debian's binaryen 108 corrupts
#    this module; docs/design.md section 6);
# 4. writes the half-size (f16) weights the page and npm package download by default
#    (scripts/half-weights.mjs: weights/ -> weights/f16/);
# 5. prints both modules' sizes, raw and gzipped.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target}"
OUT="${MESHFLOW_WEB_PKG:-web/pkg}"

log() { printf '[build-web.sh] %s\n' "$*"; }

rustup target list --installed 2>/dev/null | grep -qx wasm32-unknown-unknown ||
    rustup target add wasm32-unknown-unknown

# wasm-bindgen's CLI must match the library version exactly.
want=$(awk '/^name = "wasm-bindgen"$/ { getline; gsub(/[^0-9.]/, ""); print; exit }' Cargo.lock)
have=$(wasm-bindgen --version 2>/dev/null | awk '{ print $2 }' || true)
if [[ "$have" != "$want" ]]; then
    log "installing wasm-bindgen-cli $want (found: ${have:-none})"
    cargo install wasm-bindgen-cli --version "$want"
fi

[[ -x node_modules/.bin/wasm-opt ]] || npm ci --no-audit --no-fund

# Two modules from one API (crate/src/web/api.rs): meshflow (WebGPU and the CPU, with the
# wgpu viewer) and meshflow_cpu (the CPU alone, without cubecl's kernels). The npm package
# loads the CPU module wherever the CPU path is the faster one (no adapter, a software one).
build_module() {
    local name="$1" features="$2"
    log "compiling $name (features $features, profile wasm-release)"
    cargo rustc -p meshflow --profile wasm-release --target wasm32-unknown-unknown \
        --features "$features" --crate-type cdylib
    local wasm="$CARGO_TARGET_DIR/wasm32-unknown-unknown/wasm-release/meshflow.wasm"
    log "wasm-bindgen --target web -> $OUT/$name.js"
    wasm-bindgen --target web --out-dir "$OUT" --out-name "$name" "$wasm"
    log "wasm-opt -Oz $name"
    node_modules/.bin/wasm-opt -Oz --enable-bulk-memory --enable-nontrapping-float-to-int \
        --enable-sign-ext --enable-mutable-globals --enable-reference-types \
        "$OUT/${name}_bg.wasm" -o "$OUT/${name}_bg.opt.wasm"
    mv "$OUT/${name}_bg.opt.wasm" "$OUT/${name}_bg.wasm"
}
mkdir -p "$OUT"
build_module meshflow web,wgpu
build_module meshflow_cpu web

log "half-size weights for the browser -> weights/f16/"
node scripts/half-weights.mjs weights weights/f16

for name in meshflow meshflow_cpu; do
    raw=$(stat -c %s "$OUT/${name}_bg.wasm")
    gz=$(gzip -9 -c "$OUT/${name}_bg.wasm" | wc -c)
    log "$name: $raw bytes, $gz gzipped ($(awk -v b="$gz" 'BEGIN { printf "%.2f", b / 1048576 }') MiB)"
done
