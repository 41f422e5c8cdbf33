#!/usr/bin/env bash
# The sampler sweep of docs/experiments/2026-11-27-second-order-sampling.md (commit a36ab9f,
# 2026-11-27): validation generation for each pair, solver and step count, one `meshflow eval
# generate` each (3-6 minutes on the 2-core AMD EPYC VM), into bench/sampler/val_*.json, then
# `python3 bench/sampler/plot.py bench/sampler` (the logged results are in
# docs/experiments/data/2026-11-27-second-order-sampling/, which plot.py reads by default).
#
#   bash bench/sampler/run.sh SHIPPED_PAIR WIDE_CONTINUED_PAIR WIDE_LARGE_PAIR
#
# Each PAIR is a folder with vae.* and dit.*: the shipped weights/, and the 64-wide VAE of
# docs/experiments/2026-11-26-latent-64.md (its manifest: decoder.manifest.json in that entry's
# data folder) with its continued DiT (dit_continued.*, same folder) or its large DiT (dit_big.*,
# docs/experiments/data/2026-11-27-larger-dit-latent-64/). The time-grid arms (`_g1`, `_g2`) ran on a build whose step_times read
# the grid from an environment variable; that build is not shipped (neither grid helped), so
# they are not repeated here. The committed JSON files have `per_mesh` removed.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
MESHFLOW="${MESHFLOW:-${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target}/release/meshflow}"
declare -A PAIR=([S]="$1" [F]="$2" [B]="$3")
arm() { # NAME PAIR SOLVER STEPS [SEED] [CANDIDATES] [SCHEDULE]
    "$MESHFLOW" eval generate --split val --weights "${PAIR[$2]}" --solver "$3" --steps "$4" \
        --seed "${5:-0}" --samples "${6:-12}" --schedule "${7:-to-zero}" \
        -o "$ROOT/bench/sampler/val_$1.json"
}
cd "$ROOT"
arm big_heun4 B heun 4
arm big_heun7 B heun 7
arm big_mid4 B midpoint 4
arm ft_heun4 F heun 4
arm ft_mid4 F midpoint 4
arm ship_heun4 S heun 4
arm ship_heun7 S heun 7
arm ship_mid3 S midpoint 3
arm ship_mid3_s1 S midpoint 3 1
arm ship_mid4 S midpoint 4
arm ship_mid4_s1 S midpoint 4 1
arm ship_mid5 S midpoint 5
arm ship_mid3_k16 S midpoint 3 0 16
arm ship_mid2_k16 S midpoint 2 0 16
arm ship_mid3_ref S midpoint 3 0 12 reference
arm ship_mid3_ref_s1 S midpoint 3 1 12 reference
python3 bench/sampler/plot.py bench/sampler
