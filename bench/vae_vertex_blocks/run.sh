#!/usr/bin/env bash
# Vertex blocks (VaeConfig::num_layers_vertex): the shipped decoder continued decoder-only with
# near non-edges weighted 10 (the best recipe of commit 2342ade, 2026-11-27), without (a_near10) and with one
# self-attention block over the vertex tokens (b_near10_vertex1), both at once on the 2 cores,
# one thread each, the same wall-clock budget (BUDGET_S, default 3000 s).
#   bash bench/vae_vertex_blocks/run.sh RUNS
# then `python3 bench/vae_near_negatives/plot.py RUNS` and tau_sweep.sh as for near negatives.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
RUNS="${1:?usage: run.sh RUNS [ARM ...]}"; shift
ARMS=("$@"); [[ ${#ARMS[@]} -gt 0 ]] || ARMS=(a_near10 b_near10_vertex1)
CONFIGS="$HERE" BUDGET_S="${BUDGET_S:-3000}" bash "$HERE/../vae_near_negatives/run.sh" "$RUNS" "${ARMS[@]}"
