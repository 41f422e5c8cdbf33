#!/usr/bin/env bash
# Render generated test cases side by side: points | ours | Poisson + QEM | ground truth.
#
#   bash scripts/render_cases.sh DIR OUT.png K1 K2 ...
#
# DIR is a folder written by `meshflow eval generate --meshes DIR` (K.points.ply, K.ours.glb,
# K.gt.glb) after `python3 bench/poisson_qem.py DIR` (K.poisson.ply); a missing file leaves
# its panel out. Each case is one row of COLS panels (default 4; 3 without ground truth). Needs the meshflow CLI (built by scripts/demo.sh, or
# MESHFLOW=path) and numpy + matplotlib for scripts/render_meshes.py.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
MESHFLOW="${MESHFLOW:-${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target}/release/meshflow}"
DIR="$1"; OUT="$2"; shift 2
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
panels=()
for k in "$@"; do
    for what in points.ply ours.glb poisson.ply gt.glb; do
        src="$DIR/$k.$what"
        [[ -f "$src" ]] || continue
        dst="$TMP/${k}_${what%%.*}.obj"
        "$MESHFLOW" convert "$src" "$dst" >/dev/null
        panels+=("$dst")
    done
done
python3 "$ROOT/scripts/render_meshes.py" "$OUT" "${panels[@]}" --cols "${COLS:-4}"
