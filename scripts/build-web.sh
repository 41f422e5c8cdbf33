#!/usr/bin/env bash
# Build the browser module: `bash scripts/build-web.sh`.
#
# 1. compiles the crate's wasm-bindgen API for wasm32 as a cdylib, three times: features
#    `web,wgpu` without the default `cpu` (meshflow: WebGPU alone) in the `wasm-release` profile
#    (opt-level z, fat LTO: its size target), `web,webgl` (meshflow_cpu: the CPU path and its
#    WebGL2 viewer) in `wasm-release-cpu` (opt-level 3: it runs the models and the geometry
#    itself, 15-30% faster a generation for 0.69 MB more gzipped,
#    docs/experiments/2026-12-02-wasm-cpu-opt-level.md), and `web,webgl,threads`
#    (meshflow_cpu_threads: the same on rayon's threads, for cross-origin isolated pages; see
#    THREADS below);
# 2. runs wasm-bindgen (the CLI at the exact version in Cargo.lock, installed if missing)
#    with `--target web` into web/pkg/;
# 3. in the WebGPU module, replaces the matmul kernels WebGPU can never launch with `unreachable`
#    (scripts/snip-wasm.mjs; see SNIP below), then optimises each module with npm binaryen@132's
#    `wasm-opt` (-Oz for the WebGPU module, -O3 for the CPU one; Debian's binaryen 108 corrupts
#    this module; docs/design.md section 6);
# 4. prints the modules' sizes, raw and gzipped.
# The page and the npm package download weights/ as it is (f16, the files the CLI runs).
#
# Size flags (BENCHMARKS.md "Module and weight sizes"; how they were chosen:
# docs/experiments/2026-11-25-wasm-module-size.md): `-Z location-detail=none` drops the file and
# line of each panic site (`-Z merge-functions=disabled`: see SNIP below). They are unstable
# flags, so the stable compiler is told to accept them (RUSTC_BOOTSTRAP=1, for these two
# commands only): the nightly here has no wasm32 standard
# library, and the pinned stable compiler keeps its meaning fixed. Not `-Z fmt-debug=none`:
# cubecl writes WGSL float literals with `{:?}`, which that flag turns into nothing.
# `--low-memory-unused` lets wasm-opt fold addresses below 1 KiB, which Rust's wasm32 layout
# never uses for data (the stack sits below 1 MiB and would have to overflow to reach them).
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

# Two modules from one API (crate/src/web/api.rs): meshflow (WebGPU with the wgpu viewer, no
# CPU backend) and meshflow_cpu (the CPU path, without cubecl's kernels). The npm package
# loads the CPU module wherever the CPU path is the faster one (no adapter, a software one)
# and where WebGPU fails to start; the WebGPU module leaves it out (7% of its bytes).

# SNIP: burn-cubecl turns on cubek-matmul's `tiled` routines, and Cargo cannot turn a
# dependency's feature off, so their kernels are linked (a megabyte of code before wasm-opt).
# Neither can run here: cubek-matmul sends a matmul to `tiled::cmma` only when an operand is
# stored in tiles (nothing in Burn's tensor API makes one; only burn-cubecl's own tests do), and
# burn-cubecl's autotuner offers `tiled::cpu_gemm` only on a CPU runtime (its `cpu` group).
# Were one reached, it would trap with "unreachable" (never a wrong mesh), which the browser
# tests' wasm-native equality check would catch. Snipping by name needs every generic instance
# to keep its own body: LLVM otherwise merges identical instances (say a tile view over the
# tiled kernel's element type and the same view over the multi-level one's) under one name, and
# snipping that name broke the multi-level matmul. Hence `-Z merge-functions=disabled` (also
# unstable, so also under RUSTC_BOOTSTRAP=1); wasm-opt merges the duplicates that remain after
# the snip. docs/experiments/2026-11-25-wasm-module-size.md.
SNIP=('::tiled::(cmma|cpu_gemm)::kernel::')

build_module() {
    local name="$1" snip="$2" profile="$3" opt="$4"
    shift 4
    log "compiling $name ($*, profile $profile)"
    RUSTC_BOOTSTRAP=1 cargo rustc -p meshflow --profile "$profile" \
        --target wasm32-unknown-unknown "$@" --crate-type cdylib \
        --config 'target.wasm32-unknown-unknown.rustflags = ["-Zlocation-detail=none", "-Zmerge-functions=disabled"]'
    local wasm="$CARGO_TARGET_DIR/wasm32-unknown-unknown/$profile/meshflow.wasm"
    log "wasm-bindgen --target web -> $OUT/$name.js"
    wasm-bindgen --target web --out-dir "$OUT" --out-name "$name" "$wasm"
    if [[ "$snip" == snip ]]; then
        log "snip-wasm $name: ${SNIP[*]}"
        node scripts/snip-wasm.mjs "$OUT/${name}_bg.wasm" "$OUT/${name}_bg.wasm" "${SNIP[@]}"
    fi
    log "wasm-opt $opt $name"
    node_modules/.bin/wasm-opt "$opt" --low-memory-unused --enable-bulk-memory \
        --enable-nontrapping-float-to-int --enable-sign-ext --enable-mutable-globals \
        --enable-reference-types "$OUT/${name}_bg.wasm" -o "$OUT/${name}_bg.opt.wasm"
    mv "$OUT/${name}_bg.opt.wasm" "$OUT/${name}_bg.wasm"
}
# THREADS: meshflow_cpu_threads is meshflow_cpu with rayon on Web Workers (feature `threads`,
# wasm-bindgen-rayon), for pages that are cross-origin isolated (COOP and COEP): the matrix
# products and the per-candidate stages on every core, as natively. Its memory is shared, so
# std must be rebuilt with atomics (`-Z build-std`), which needs the standard library's source:
# rustup's toolchains here have none, Debian bookworm-security's `rust-web-src` (with
# `rustc-web` 1.96, installed below; rustup's proxies stay first on the PATH) has. Debian
# ships no `rust-lld`; the rustup toolchain's links it. Its own target folder: another
# compiler. docs/experiments/2026-12-04-wasm-threads-build.md.
threads_toolchain() {
    if ! /usr/bin/rustc --version 2>/dev/null | grep -q '^rustc 1\.96\.' ||
        [[ ! -d /usr/lib/rustlib/src/rust/library/std ]] || [[ ! -x /usr/bin/cargo ]]; then
        log "installing Debian's rustc-web, cargo-web and rust-web-src (the threaded module's std source)"
        local sudo=()
        [[ $(id -u) -eq 0 ]] || sudo=(sudo)
        "${sudo[@]}" apt-get update -qq
        "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq rustc-web cargo-web rust-web-src
    fi
}

build_threads_module() {
    local name=meshflow_cpu_threads profile=wasm-release-cpu
    threads_toolchain
    local host lld
    host=$(rustc -vV | sed -n 's/^host: //p')
    lld="$(rustc --print sysroot)/lib/rustlib/$host/bin/rust-lld"
    [[ -x "$lld" ]] || { log "no rust-lld at $lld"; exit 1; }
    local target="$CARGO_TARGET_DIR/threads"
    log "compiling $name (--features web,webgl,threads, profile $profile, std with atomics)"
    # Link arguments for the final module only: its memory shared, imported (the glue creates
    # it, and hands it to each worker), up to 4 GiB, and the thread-local storage each worker
    # sets up.
    RUSTC=/usr/bin/rustc RUSTC_BOOTSTRAP=1 CARGO_TARGET_DIR="$target" \
        RUSTFLAGS="-C target-feature=+atomics,+bulk-memory,+mutable-globals,+simd128 -C linker=$lld -Zlocation-detail=none" \
        /usr/bin/cargo rustc -p meshflow --profile "$profile" --target wasm32-unknown-unknown \
        --features web,webgl,threads --crate-type cdylib -Z build-std=std,panic_abort -- \
        -C link-arg=--shared-memory -C link-arg=--max-memory=4294967296 -C link-arg=--import-memory \
        -C link-arg=--export=__wasm_init_tls -C link-arg=--export=__tls_size \
        -C link-arg=--export=__tls_align -C link-arg=--export=__tls_base
    log "wasm-bindgen --target web -> $OUT/$name.js"
    # Its JS snippets (wasm-bindgen-rayon's worker script) are its alone: none left from an
    # earlier version.
    rm -rf "$OUT/snippets"
    wasm-bindgen --target web --out-dir "$OUT" --out-name "$name" \
        "$target/wasm32-unknown-unknown/$profile/meshflow.wasm"
    # wasm-bindgen-rayon's worker script imports the package by its folder ('../../..'), which
    # a bundler resolves and a browser cannot: point it at the module's own glue.
    local helper
    helper=$(find "$OUT/snippets" -path '*wasm-bindgen-rayon-*' -name workerHelpers.js | head -n 1)
    grep -q "import('../../..')" "$helper" || { log "$helper: no import('../../..') to point at $name.js"; exit 1; }
    sed -i "s|import('../../..')|import('../../../$name.js')|" "$helper"
    log "wasm-opt -O3 $name"
    node_modules/.bin/wasm-opt -O3 --low-memory-unused --enable-bulk-memory --enable-threads \
        --enable-nontrapping-float-to-int --enable-sign-ext --enable-mutable-globals \
        --enable-reference-types --enable-simd "$OUT/${name}_bg.wasm" -o "$OUT/${name}_bg.opt.wasm"
    mv "$OUT/${name}_bg.opt.wasm" "$OUT/${name}_bg.wasm"
}

# MESHFLOW_WEB_MODULES picks some of the three (default: all), e.g. while working on one.
MODULES="${MESHFLOW_WEB_MODULES:-meshflow meshflow_cpu meshflow_cpu_threads}"
built() { [[ " $MODULES " == *" $1 "* ]]; }
mkdir -p "$OUT"
built meshflow && build_module meshflow snip wasm-release -Oz --no-default-features --features web,wgpu
built meshflow_cpu && build_module meshflow_cpu no-snip wasm-release-cpu -O3 --features web,webgl
built meshflow_cpu_threads && build_threads_module

for name in $MODULES; do
    raw=$(stat -c %s "$OUT/${name}_bg.wasm")
    gz=$(gzip -9 -c "$OUT/${name}_bg.wasm" | wc -c)
    log "$name: $raw bytes, $gz gzipped ($(awk -v b="$gz" 'BEGIN { printf "%.2f", b / 1048576 }') MiB)"
done
