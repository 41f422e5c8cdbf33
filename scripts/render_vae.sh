#!/usr/bin/env bash
# The first ten test reconstructions side by side, ground truth | BEFORE | AFTER, five per PNG:
#
#   bash scripts/render_vae.sh BEFORE AFTER OUT_PREFIX
#
# BEFORE and AFTER are VAE weight folders (vae.safetensors, vae.json, vae.manifest.json), e.g.
# `weights` and a training run's output. Writes OUT_PREFIX_0.png (meshes 0-4) and
# OUT_PREFIX_5.png (5-9); LABELS="old new" names the two columns (default: before after). Needs
# the meshflow CLI (built by scripts/demo.sh, or MESHFLOW=path) and numpy + matplotlib for
# scripts/render_meshes.py.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
MESHFLOW="${MESHFLOW:-${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target}/release/meshflow}"
BEFORE="$(realpath "${1:?usage: render_vae.sh BEFORE AFTER OUT_PREFIX}")"
AFTER="$(realpath "${2:?usage: render_vae.sh BEFORE AFTER OUT_PREFIX}")"
OUT="${3:?usage: render_vae.sh BEFORE AFTER OUT_PREFIX}"
read -r LABEL_BEFORE LABEL_AFTER <<< "${LABELS:-before after}"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
for side in before after; do
    weights="$BEFORE"; [[ "$side" == after ]] && weights="$AFTER"
    "$MESHFLOW" eval vae --split test --limit 10 --weights "$weights" --meshes "$TMP/$side" \
        -o "$TMP/$side.json" > /dev/null
done
for first in 0 5; do
    panels=(); titles=()
    for i in $(seq "$first" $((first + 4))); do
        "$MESHFLOW" convert "$TMP/before/${i}_gt.glb" "$TMP/${i}_gt.obj" > /dev/null
        "$MESHFLOW" convert "$TMP/before/$i.glb" "$TMP/${i}_before.obj" > /dev/null
        "$MESHFLOW" convert "$TMP/after/$i.glb" "$TMP/${i}_after.obj" > /dev/null
        panels+=("$TMP/${i}_gt.obj" "$TMP/${i}_before.obj" "$TMP/${i}_after.obj")
        titles+=("$i ground truth" "$i $LABEL_BEFORE" "$i $LABEL_AFTER")
    done
    python3 "$ROOT/scripts/render_meshes.py" "${OUT}_$first.png" "${panels[@]}" --cols 3 \
        --titles "${titles[@]}"
done
