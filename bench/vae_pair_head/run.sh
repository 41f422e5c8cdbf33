#!/usr/bin/env bash
# A pair head (issue 14, commit a92f332, 2026-11-28): the shipped VAE continued decoder-only with the shipped
# stage-2 recipe at a lower peak learning rate (1e-4, 7,000 steps), as it is (a_control) or with
# a pair head of hidden width 64 that rescores each vertex's 16 highest-scoring partners
# (b_pair64, `VaeConfig::pair_head`). Both at once on the 2-core AMD EPYC VM, one thread each, each
# with the same wall-clock budget (BUDGET_S, default 3000 s):
#   bash bench/vae_pair_head/run.sh RUNS
# then `python3 bench/vae_edge_dim/plot.py RUNS RUNS/pair_head.png` (the logged runs, with a
# third arm that started later, against steps: `python3 bench/vae_edge_dim/plot.py --steps
# docs/experiments/data/2026-11-28-pair-head docs/experiments/data/2026-11-28-pair-head/pair_head.png`).
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
RUNS="${1:?usage: run.sh RUNS [ARM ...]}"; shift
ARMS=("$@"); [[ ${#ARMS[@]} -gt 0 ]] || ARMS=(a_control b_pair64)
CONFIGS="$HERE" BUDGET_S="${BUDGET_S:-3000}" bash "$HERE/../vae_near_negatives/run.sh" "$RUNS" "${ARMS[@]}"
