#!/usr/bin/env bash
# Render generated test cases side by side: points | ours | Poisson + QEM | ground truth.
#
#   bash scripts/render_cases.sh DIR OUT.png K1 K2 ...
#
# DIR is a folder written by `meshflow eval generate --meshes DIR` (K.points.ply, K.ours.glb,
# K.gt.glb) after `python3 bench/poisson_qem.py DIR` (K.poisson.ply); a missing file leaves
# its panel out. BEFORE=DIR2 (another such folder, e.g. the previous weights' run) adds DIR2's
# K.ours.glb as a "K_before" panel left of ours. Each case is one row of COLS panels (default:
# as many as the first case has). Needs the meshflow CLI (built by scripts/demo.sh, or
# MESHFLOW=path) and numpy + matplotlib for scripts/render_meshes.py.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
MESHFLOW="${MESHFLOW:-${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target}/release/meshflow}"
DIR="$1"; OUT="$2"; shift 2
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
panels=()
cols=0
for k in "$@"; do
    sources=("$DIR/$k.points.ply")
    [[ -n "${BEFORE:-}" ]] && sources+=("$BEFORE/$k.ours.glb")
    sources+=("$DIR/$k.ours.glb" "$DIR/$k.poisson.ply" "$DIR/$k.gt.glb")
    for src in "${sources[@]}"; do
        [[ -f "$src" ]] || continue
        name="$(basename "$src")"; name="${name#*.}"; name="${name%%.*}"
        [[ "$src" == "${BEFORE:-/nonexistent}/"* ]] && name=before
        dst="$TMP/${k}_$name.obj"
        "$MESHFLOW" convert "$src" "$dst" >/dev/null
        panels+=("$dst")
    done
    (( cols == 0 )) && cols=${#panels[@]}
done
python3 "$ROOT/scripts/render_meshes.py" "$OUT" "${panels[@]}" --cols "${COLS:-$cols}"
