#!/bin/bash
# Experiment docs/experiments/2026-12-07-seed-clusters.md: `meshflow bench generate --runs 2` of four
# inputs without and with --complete-seed-gap 0.7, alternating, two rounds; JSON per run in OUT.
#   MESHFLOW=BIN bash bench/seed_time.sh OUT
set -euo pipefail
OUT=${1:?usage: bench/seed_time.sh OUT}; mkdir -p $OUT
R=$(cd "$(dirname "$0")/.." && pwd)
inputs=($R/tests/fixtures/points/stone_lantern_2048.ply $R/web/examples/milk_truck_4096.ply $R/tests/fixtures/hard_surface/points/box.ply $R/tests/fixtures/hard_surface/points/table_noise1.ply)
for round in 1 2; do
  for input in "${inputs[@]}"; do
    n=$(basename $input .ply)
    ${MESHFLOW:?MESHFLOW=path to the meshflow binary} bench generate --input $input --runs 2 -o $OUT/${n}_off_r$round.json > /dev/null
    ${MESHFLOW:?MESHFLOW=path to the meshflow binary} bench generate --input $input --runs 2 --complete-seed-gap 0.7 -o $OUT/${n}_on_r$round.json > /dev/null
  done
done
