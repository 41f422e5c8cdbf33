#!/usr/bin/env bash
# Where the page's CPU path loses to the CLI, per kind of work: the same generations (INPUT at
# the page's defaults) profiled in the CPU module under V8 (Node, the engine Chromium runs)
# and in the release CLI, both on one thread, and one table of their self times per
# generation (matrix products, attention, GELU's erf, other tensor work, k-d trees,
# allocation, mesh geometry). Not a test: run it on an otherwise idle machine, after
# `bash scripts/build-web.sh` (its cargo output still has the function names, which wasm-opt
# strips from web/pkg) and `cargo build --release -p meshflow-cli`:
#   bash bench/cpu_profile/run.sh OUT [INPUT] [ROUNDS]
# Needs perf (Debian's linux-perf); MESHFLOW names the CLI.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
OUT="$1"; INPUT="${2:-$ROOT/tests/fixtures/points/stone_lantern_2048.ply}"; ROUNDS="${3:-3}"
TARGET="${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target}"
MESHFLOW="${MESHFLOW:-$TARGET/release/meshflow}"
mkdir -p "$OUT/pkg"
wasm-bindgen --target web --out-dir "$OUT/pkg" --out-name meshflow_cpu \
    "$TARGET/wasm32-unknown-unknown/wasm-release-cpu/meshflow.wasm"
node --cpu-prof --cpu-prof-dir "$OUT/prof" --cpu-prof-interval 500 \
    "$ROOT/bench/cpu_profile/wasm.mjs" "$OUT/pkg" "$INPUT" "$ROUNDS" "$OUT/wasm_run.json"
python3 "$ROOT/bench/cpu_profile/wasm_self.py" "$OUT"/prof/*.cpuprofile "$((ROUNDS + 1))" "$OUT/wasm.json"
FREQ=1000
RAYON_NUM_THREADS=1 perf record -q -F "$FREQ" --call-graph dwarf,32768 -o "$OUT/perf.data" \
    "$MESHFLOW" bench generate --input "$INPUT" --runs "$ROUNDS" -o "$OUT/native_bench.json" >/dev/null
# Each side runs one generation more than ROUNDS, a warm-up, and counts it (bench generate's).
perf script -i "$OUT/perf.data" --no-inline 2>/dev/null |
    python3 "$ROOT/bench/cpu_profile/native.py" "$FREQ" "$((ROUNDS + 1))" "$OUT/native.json"
rm -rf "$OUT/perf.data" "$OUT/pkg" "$OUT/prof"
grep -m1 "model name" /proc/cpuinfo | sed 's/.*: /machine: /'
python3 "$ROOT/bench/cpu_profile/table.py" "$OUT/wasm.json" "$OUT/native.json" | tee "$OUT/table.md"
