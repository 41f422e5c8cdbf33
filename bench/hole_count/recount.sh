#!/usr/bin/env bash
# The holes of an eval run's meshes (`meshflow eval generate --meshes DIR`) counted again by
# the given build's `meshflow inspect`: a run of one build's meshes scored with another
# build's hole count, so that two runs are paired on one definition.
#   MESHFLOW=BIN bash bench/hole_count/recount.sh DIR > DIR.holes.csv   (columns: index, holes)
set -euo pipefail
dir=${1:?usage: recount.sh MESHES_DIR}
meshflow=${MESHFLOW:-${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target}/release/meshflow}
echo "index,holes"
for f in $(ls "$dir" | grep '\.ours\.glb$' | sort -n); do
  k=${f%.ours.glb}
  holes=$("$meshflow" inspect --json "$dir/$f" | python3 -c 'import json,sys; print(json.load(sys.stdin)["topology"]["holes"])')
  echo "$k,$holes"
done
