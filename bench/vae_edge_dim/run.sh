#!/usr/bin/env bash
# Wider edge embeddings (issue 14, commit a92f332, 2026-11-28): the shipped VAE continued decoder-only with the
# shipped stage-2 recipe at a lower peak learning rate (1e-4, 8,000 steps), its edge embedding
# kept at 32 channels (a_edge32, the control) or widened to 64 / 128 (the trained channels kept,
# the added ones starting small: `widen_edge_embeddings`). The arms run at once on the 2-core
# AMD EPYC VM, one thread each, each with the same wall-clock budget (BUDGET_S, default 4200 s):
#   bash bench/vae_edge_dim/run.sh RUNS
# then `python3 bench/vae_edge_dim/plot.py RUNS` for RUNS/edge_dim.png and the table (without
# RUNS it draws the logged arms, docs/experiments/data/2026-11-28-edge-embedding-width/).
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
RUNS="${1:?usage: run.sh RUNS [ARM ...]}"; shift
ARMS=("$@"); [[ ${#ARMS[@]} -gt 0 ]] || ARMS=(a_edge32 b_edge64 c_edge128)
CONFIGS="$HERE" BUDGET_S="${BUDGET_S:-4200}" bash "$HERE/../vae_near_negatives/run.sh" "$RUNS" "${ARMS[@]}"
