#!/usr/bin/env bash
# Near-negative weighting of the adjacency loss, decoder-only continuations of the shipped VAE:
# the arms given (default: round 1, a_control b_near1 c_near3) run at once on this 2-core
# CPU, one thread each, each with the same wall-clock budget (BUDGET_S, default 2400 s).
#   bash bench/vae_near_negatives/run.sh RUNS                                   # round 1
#   BUDGET_S=3300 bash bench/vae_near_negatives/run.sh RUNS d_near3_long e_near10_long  # round 2
# then `python3 bench/vae_near_negatives/plot.py RUNS` for RUNS/near_negatives.png and the table
# (without RUNS it draws the logged rounds, docs/experiments/data/2026-11-27-near-non-edges/),
# and tau_sweep.sh to score each result on the validation split at several thresholds.
# CONFIGS names another folder of ARM.json files (bench/vae_vertex_blocks/run.sh); INIT the
# weights to continue (default: the shipped ones).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
RUNS="${1:?usage: run.sh RUNS [ARM ...]}"; shift
MESHFLOW="${MESHFLOW:-${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target}/release/meshflow}"
BUDGET_S="${BUDGET_S:-2400}"
CONFIGS="${CONFIGS:-$ROOT/bench/vae_near_negatives}"
INIT="${INIT:-$ROOT/weights}"
ARMS=("$@"); [[ ${#ARMS[@]} -gt 0 ]] || ARMS=(a_control b_near1 c_near3)
mkdir -p "$RUNS"
for arm in "${ARMS[@]}"; do
    RAYON_NUM_THREADS=1 nice "$MESHFLOW" train vae --out "$RUNS/$arm" --init "$INIT" \
        --config "$CONFIGS/$arm.json" --time-budget-s "$BUDGET_S" \
        > "$RUNS/$arm.log" 2>&1 &
done
wait
