#!/usr/bin/env bash
# One decoder stage instead of two: the stage-1 VAE (INIT, the weights shipped at 39237f8, which
# `scripts/train_vae.sh` stage 1 writes) continued decoder-only with the stage-3 recipe (near
# non-edges weighted 10) for the decoder-only time that stages 2 and 3 spend together, with one
# vertex block (a_vertex1, 16,000 steps) or two (b_vertex2, 12,000 steps: a block costs about a
# third of a step), both at once on the 2 cores, one thread each, capped at BUDGET_S.
#   INIT=DIR bash bench/vae_one_stage/run.sh RUNS
# The follow-up pair, 8,000 steps each, position weight 10 against 20 (run beside CI):
#   INIT=DIR BUDGET_S=3900 bash bench/vae_one_stage/run.sh RUNS c_short_position10 d_short_position20
# The full-length candidate that pair points to (one block, 16,000 steps, position weight 20),
# alone on both cores; it resumes from its checkpoints when interrupted:
#   meshflow train vae --out RUN --init DIR --config bench/vae_one_stage/e_vertex1_position20.json
# and its position-weight-40 twin (f_vertex1_position40.json, shipped in commit aa27690 as
# weights/vae.vertex.train.json), run beside it on one thread (RAYON_NUM_THREADS=1); commit 97863bc
# started g_vertex1_position80.json (position weight 80) the same way; commit 726955e resumed it beside
# h_vertex1_position160.json (position weight 160), one thread each;
# then `python3 bench/vae_one_stage/plot.py --steps DIR` and bench/vae_near_negatives/tau_sweep.sh.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
RUNS="${1:?usage: INIT=DIR run.sh RUNS [ARM ...]}"; shift
: "${INIT:?INIT=DIR: the stage-1 weights (git show 39237f8:weights/vae.*)}"
ARMS=("$@"); [[ ${#ARMS[@]} -gt 0 ]] || ARMS=(a_vertex1 b_vertex2)
CONFIGS="$HERE" INIT="$INIT" BUDGET_S="${BUDGET_S:-5400}" bash "$HERE/../vae_near_negatives/run.sh" "$RUNS" "${ARMS[@]}"
