#!/usr/bin/env bash
# Fixed-budget MeshVAE sweep: every arm in bench/vae_sweep/configs/ trains for the same wall
# time (BUDGET_S, default 300 s) on this machine, one after another, into RUNS/<arm>/, then
# bench/vae_sweep/plot.py draws validation F1, position and normal error against time.
#   bash bench/vae_sweep/run_sweep.sh RUNS [ARM ...]
# Each arm uses the full ship schedule truncated by the budget, so any arm can be resumed
# into a full run (`meshflow train vae --out RUNS/<arm> --config <its config>`).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
RUNS="${1:?usage: run_sweep.sh RUNS [ARM ...]}"; shift
MESHFLOW="${MESHFLOW:-${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target}/release/meshflow}"
BUDGET_S="${BUDGET_S:-300}"
ARMS=("$@")
if [[ ${#ARMS[@]} -eq 0 ]]; then
    for f in "$ROOT"/bench/vae_sweep/configs/*.json; do ARMS+=("$(basename "$f" .json)"); done
fi
mkdir -p "$RUNS"
for arm in "${ARMS[@]}"; do
    echo "[sweep] $arm: $BUDGET_S s"
    "$MESHFLOW" train vae --out "$RUNS/$arm" --config "$ROOT/bench/vae_sweep/configs/$arm.json" \
        --time-budget-s "$BUDGET_S" > "$RUNS/$arm.log" 2>&1
done
python3 "$ROOT/bench/vae_sweep/plot.py" "$RUNS" "$ROOT/bench/vae_sweep/sweep.png" \
    --table "$ROOT/bench/vae_sweep/sweep.md"
