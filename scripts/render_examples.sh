#!/usr/bin/env bash
# Render the page's five examples side by side: points | ours | Poisson + QEM at our face count.
#
#   bash scripts/render_examples.sh OUT.png
#
# Generates from web/examples/*.ply with the shipped weights (defaults), runs
# bench/poisson_qem.py on them (pymeshlab) and renders with scripts/render_cases.sh. Needs the
# meshflow CLI (MESHFLOW=path, default: the release build) and python3 with numpy, matplotlib
# and pymeshlab.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
MESHFLOW="${MESHFLOW:-${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target}/release/meshflow}"
OUT="$1"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
targets="{"
k=0
for ply in "$ROOT"/web/examples/*.ply; do
    cp "$ply" "$TMP/$k.points.ply"
    "$MESHFLOW" generate "$ply" -o "$TMP/$k.ours.glb" >/dev/null
    faces="$("$MESHFLOW" inspect "$TMP/$k.ours.glb" --json |
        python3 -c 'import json, sys; print(json.load(sys.stdin)["faces"])')"
    if ((k > 0)); then targets+=","; fi
    targets+="\"$k\": $faces"
    k=$((k + 1))
done
echo "$targets}" >"$TMP/targets.json"
python3 "$ROOT/bench/poisson_qem.py" "$TMP" >/dev/null
# No ground truth here: three panels a row.
MESHFLOW="$MESHFLOW" COLS=3 bash "$ROOT/scripts/render_cases.sh" "$TMP" "$OUT" $(seq 0 $((k - 1)))
