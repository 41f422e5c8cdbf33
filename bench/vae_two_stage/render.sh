#!/usr/bin/env bash
# The first ten test reconstructions, ground truth | shipped VAE | a candidate VAE, five per
# PNG: `bash bench/vae_two_stage/render.sh CANDIDATE OUT_PREFIX` writes OUT_PREFIX_0.png
# (meshes 0-4) and OUT_PREFIX_5.png (5-9). Needs the release CLI and numpy + matplotlib.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
MESHFLOW="${MESHFLOW:-${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target}/release/meshflow}"
CANDIDATE="$(realpath "${1:?usage: render.sh CANDIDATE OUT_PREFIX}")"; OUT="${2:?}"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
"$MESHFLOW" eval vae --split test --limit 10 --weights "$ROOT/weights" --meshes "$TMP/shipped" -o "$TMP/shipped.json" > /dev/null
"$MESHFLOW" eval vae --split test --limit 10 --weights "$CANDIDATE" --meshes "$TMP/candidate" -o "$TMP/candidate.json" > /dev/null
for first in 0 5; do
    panels=(); titles=()
    for i in $(seq "$first" $((first + 4))); do
        "$MESHFLOW" convert "$TMP/shipped/${i}_gt.glb" "$TMP/${i}_gt.obj" > /dev/null
        "$MESHFLOW" convert "$TMP/shipped/$i.glb" "$TMP/${i}_shipped.obj" > /dev/null
        "$MESHFLOW" convert "$TMP/candidate/$i.glb" "$TMP/${i}_candidate.obj" > /dev/null
        panels+=("$TMP/${i}_gt.obj" "$TMP/${i}_shipped.obj" "$TMP/${i}_candidate.obj")
        titles+=("$i ground truth" "$i shipped" "$i candidate")
    done
    python3 "$ROOT/scripts/render_meshes.py" "${OUT}_$first.png" "${panels[@]}" --cols 3 --titles "${titles[@]}"
done
