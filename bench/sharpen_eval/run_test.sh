#!/usr/bin/env bash
# Issue 52's test-split figures: generation with and without sharpening, Poisson + QEM at the
# sharpened meshes' face counts, each scored against the ground truth.
#   bash bench/sharpen_eval/run_test.sh OUT [NOISE] [MISSING]
# writes OUT/today.json, OUT/sharpened.json, OUT/meshes/ (K.points.ply, K.ours.glb, K.gt.glb,
# K.poisson.ply, K.poisson.cmp.json) and, via summarize.py, OUT/summary.txt. SHARPEN_ARGS
# (e.g. "--sharpen-accept 1.1") go to the sharpened arm.
set -euo pipefail
out=${1:?usage: run_test.sh OUT [NOISE] [MISSING]}
noise=${2:-0}
missing=${3:-0}
meshflow=${MESHFLOW:-${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target}/release/meshflow}
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out/meshes"
common=(eval generate --split test --noise "$noise" --missing "$missing")
date
# Today's arm does not depend on the sharpening options: kept when it is there (SKIP_TODAY=1
# leaves it out).
[ -s "$out/today.json" ] || [ -n "${SKIP_TODAY:-}" ] ||
  "$meshflow" "${common[@]}" --no-sharpen -o "$out/today.json" > "$out/today.log" 2>&1
date
"$meshflow" "${common[@]}" ${SHARPEN_ARGS:-} --meshes "$out/meshes" -o "$out/sharpened.json" > "$out/sharpened.log" 2>&1
date
# One MeshLab thread per process, two processes: about 1 s a mesh on 2 cores.
OMP_NUM_THREADS=1 python3 "$here/../poisson_qem.py" "$out/meshes" > "$out/poisson.log" 2>&1
date
for f in "$out"/meshes/*.poisson.ply; do
  k=$(basename "$f" .poisson.ply)
  "$meshflow" compare "$f" "$out/meshes/$k.gt.glb" --json > "$out/meshes/$k.poisson.cmp.json" 2>/dev/null || true
done
date
python3 "$here/summarize.py" "$out" | tee "$out/summary.txt"
