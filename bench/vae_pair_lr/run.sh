#!/usr/bin/env bash
# The pair-head stage (weights/vae.pair.train.json, issue 14, commit 8e0d5bb, 2026-11-28) at a higher peak
# learning rate: 2e-4 (d_lr2e4, stage 2's) and 3e-4 (e_lr3e4), against the shipped 1e-4
# (its curve: docs/experiments/data/2026-11-28-pair-head/c_pair64_context.metrics.jsonl). Each continues the stage-2
# VAE that the shipped stage 3 started from (INIT; `git show 57693dd:weights/vae.*`, sha256
# 90b47205...), both at once on this 2-core CPU, one thread each, the same budget each:
#   INIT=DIR bash bench/vae_pair_lr/run.sh RUNS
# then `python3 bench/vae_edge_dim/plot.py --steps RUNS
# docs/experiments/data/2026-11-28-pair-head/c_pair64_context.metrics.jsonl RUNS/pair_lr.png`
# (the logged runs' plot: docs/experiments/data/2026-11-28-pair-head-lr/pair_lr.png).
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
RUNS="${1:?usage: INIT=DIR run.sh RUNS [ARM ...]}"; shift
ARMS=("$@"); [[ ${#ARMS[@]} -gt 0 ]] || ARMS=(d_lr2e4 e_lr3e4)
: "${INIT:?INIT: the stage-2 VAE to continue}"
CONFIGS="$HERE" BUDGET_S="${BUDGET_S:-4500}" bash "$HERE/../vae_near_negatives/run.sh" "$RUNS" "${ARMS[@]}"
