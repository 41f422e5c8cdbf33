#!/usr/bin/env bash
# Run the product on the bundled fixtures: `bash scripts/demo.sh [MESH]`.
#
# Builds the `meshflow` CLI in release mode (needs only cargo), then on one
# fixture mesh (default: the CC0 stone lantern) runs
#   inspect  -> mesh statistics
#   sample   -> 8,192-point PLY point cloud
#   extract  -> the mesh's own adjacency in token order -> Algorithm 1 ->
#               faces, reporting what was lost, added or flipped
#   convert  -> binary glTF (.glb)
#   compare  -> the .glb against the original mesh
#   reconstruct -> the shipped MeshVAE (weights/): encode, decode, extract,
#               with its reconstruction figures
#   generate -> the bundled 2,048-point scan of the lantern through the
#               shipped DiT and VAE to a mesh, with per-stage times
# Output files go to $MESHFLOW_DEMO_OUT if set, else a fresh temporary
# directory; either way they are kept, and the path is printed at the end.
# Then it builds the browser module (scripts/build-web.sh) and serves the web
# page on 127.0.0.1, printing its URL (Ctrl-C stops it); MESHFLOW_DEMO_NO_SERVE=1
# skips that part.

set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"

export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target}"

MESH="${1:-tests/fixtures/meshes/stone_lantern.obj}"
OUT="${MESHFLOW_DEMO_OUT:-$(mktemp -d "${TMPDIR:-/tmp}/meshflow-demo.XXXXXX")}"
mkdir -p "$OUT"

log() { printf '\n[demo.sh] %s\n' "$*"; }

command -v cargo >/dev/null 2>&1 || {
    echo "[demo.sh] cargo not found: install Rust with rustup first" >&2
    exit 1
}
[[ -f "$MESH" ]] || {
    echo "[demo.sh] no such mesh: $MESH" >&2
    exit 1
}

log "building the CLI (release; CARGO_TARGET_DIR=$CARGO_TARGET_DIR)"
cargo build --release -p meshflow-cli
MESHFLOW="$CARGO_TARGET_DIR/release/meshflow"

# Echo each command as a person would type it, then run it.
run() {
    log "\$ meshflow $*"
    "$MESHFLOW" "$@"
}

run inspect "$MESH"
run sample "$MESH" -n 8192 -o "$OUT/points.ply"
run extract "$MESH"
run convert "$MESH" "$OUT/out.glb"
run compare "$OUT/out.glb" "$MESH"
run reconstruct "$MESH" -o "$OUT/reconstructed.glb" --weights weights
run generate tests/fixtures/points/stone_lantern_2048.ply -o "$OUT/generated.glb" --weights weights
# The page's examples, which come from no training source (web/examples/SOURCES.md).
run generate web/examples/ -o "$OUT/examples/" --weights weights

log "done. Input: $MESH"
echo "[demo.sh] outputs in $OUT:"
echo "[demo.sh]   $OUT/points.ply  (8,192 sampled points, binary PLY)"
echo "[demo.sh]   $OUT/out.glb     (binary glTF of the mesh)"
echo "[demo.sh]   $OUT/reconstructed.glb (the shipped MeshVAE's reconstruction)"
echo "[demo.sh]   $OUT/generated.glb (generated from the bundled point cloud)"
echo "[demo.sh]   $OUT/examples/*.glb (generated from the page's five example point clouds)"
echo "[demo.sh] the CLI binary is $MESHFLOW"

if [[ "${MESHFLOW_DEMO_NO_SERVE:-}" != 1 ]]; then
    log "building the web page (scripts/build-web.sh)"
    bash scripts/build-web.sh
    command -v node >/dev/null 2>&1 || {
        echo "[demo.sh] node not found: install nodejs to serve the page" >&2
        exit 1
    }
    log "serving the page; open the URL below in a browser with WebGPU (Ctrl-C stops)"
    exec node web/serve.mjs "${MESHFLOW_PORT:-8080}"
fi
