#!/usr/bin/env bash
# Steps against candidates, and how the kept candidate is chosen (issue 15, commit 6244e77, 2026-11-26).
#
#   bash bench/samples_sweep/run.sh OUT_DIR      (about 25 minutes on 2 cores)
#
# 1. The arms: `meshflow eval generate --split val --steps S --samples K` for each row of
#    arms.csv's measured arms; each writes OUT_DIR/NAME.json and .log.
# 2. The candidates: twelve one-sample runs at 7 steps with seeds 0, 8, ..., 88 and
#    `--meshes`: eval batches hold 8 meshes, and candidate j of a batch's input k is seeded
#    seed + k + 8j, so these are exactly the candidates `--samples 12` draws. candidates.py
#    then scores each one (holes, CD to the ground truth, and the distance to the input that
#    keep_best measures) into OUT_DIR/candidates_val_s7.csv, and plot.py replays selection rules
#    on it (OUT_DIR/sweep.png; arms.csv, the measured arms' table with their lantern times, is
#    the one logged in docs/experiments/data/2026-11-26-candidates-and-steps/samples_sweep/).
#
# arms.csv's "holes first" rows (hf) were measured with the build of 412950f, before keep_best
# weighed holes against the distance; with a later build every arm of more than one candidate
# keeps by the hole weight, and the replay (plot.py) is where the two rules meet.
set -euo pipefail
OUT="${1:?usage: run.sh OUT_DIR}"
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
MESHFLOW="${MESHFLOW:-${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target}/release/meshflow}"
mkdir -p "$OUT"
arm() {
    local name=$1; shift
    "$MESHFLOW" eval generate --split val "$@" -o "$OUT/$name.json" > "$OUT/$name.log" 2>&1
    echo "$name: $(grep -h '  ours ' "$OUT/$name.log")"
}
cd "$ROOT"
for s in 4 7 14 28; do arm "s${s}_k1" --steps "$s" --samples 1; done
for k in 4 8; do arm "s7_k${k}" --steps 7 --samples "$k"; done
arm s14_k8 --steps 14 --samples 8
arm s7_k12 --steps 7 --samples 12
for j in $(seq 0 11); do
    arm "cand_seed$((8 * j))" --steps 7 --samples 1 --seed $((8 * j)) --meshes "$OUT/cand_seed$((8 * j))"
done
python3 bench/samples_sweep/candidates.py "$OUT" 12 "$OUT/candidates_val_s7.csv"
python3 bench/samples_sweep/plot.py "$OUT"
