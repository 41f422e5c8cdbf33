#!/usr/bin/env bash
# Folded edges and holes of `meshflow generate` on the hard-surface set (clean and 1% noise),
# the page's examples and the lantern, at the defaults and with stages turned off, one row an
# input: folded/holes for the defaults, --no-sharpen, --no-sharpen --no-close-holes and
# --no-close-holes.
#
#   bash bench/folds/fixtures.sh > OUT.txt
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
meshflow=${MESHFLOW:-${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target}/release/meshflow}
out=$(mktemp -d)
for f in "$ROOT"/tests/fixtures/hard_surface/points/*.ply "$ROOT"/web/examples/*.ply "$ROOT"/tests/fixtures/points/*.ply; do
    row="$(basename "$f" .ply)"
    for flags in "" "--no-sharpen" "--no-sharpen --no-close-holes" "--no-close-holes"; do
        # The last line of the report: "... N holes, ... N folded edges".
        line=$("$meshflow" generate "$f" -o "$out/mesh.glb" $flags 2>&1 | tail -1)
        folded=$(sed -E 's/.* ([0-9]+) folded edges.*/\1/' <<< "$line")
        holes=$(sed -E 's/.* ([0-9]+) holes.*/\1/' <<< "$line")
        row="$row $folded/$holes"
    done
    echo "$row"
done
rm -rf "$out"
