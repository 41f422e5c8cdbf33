#!/usr/bin/env bash
# Latent noise in decoder training: the shipped decoder continued decoder-only with Gaussian
# noise of std 0.3 and 0.75 added to every training latent, both arms at once on this 2-core
# CPU, one thread each, the same budget (2,000 steps of 8, lr 1e-4; about 8 minutes).
#   bash bench/vae_latent_noise/run.sh RUNS
# then, for each arm, a pair folder (weights/dit.* beside RUNS/<arm>/vae.*) and
#   meshflow eval vae --split val --weights RUNS/<arm> -o DIR/vae_val_<arm>.json
#   meshflow eval generate --split val --weights PAIR -o DIR/generate_val_<arm>.json
# with RUNS/<arm>/metrics.jsonl copied to DIR/<arm>.metrics.jsonl, and
# `python3 bench/vae_latent_noise/plot.py DIR` for DIR/latent_noise.png. The logged run's files
# are in docs/experiments/data/2026-11-27-latent-noise/, plot.py's default DIR.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
RUNS="${1:?usage: run.sh RUNS}"
MESHFLOW="${MESHFLOW:-${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target}/release/meshflow}"
mkdir -p "$RUNS"
for arm in noise0.3 noise0.75; do
    RAYON_NUM_THREADS=1 "$MESHFLOW" train vae --out "$RUNS/$arm" --init "$ROOT/weights" \
        --config "$ROOT/bench/vae_latent_noise/$arm.json" --time-budget-s 1200 \
        > "$RUNS/$arm.log" 2>&1 &
done
wait
