#!/usr/bin/env bash
# Side by side, one binary, arms alternated: a training step of a shipped decoder stage with
# the batch in one pass (data_parallel 1) and in sub-batches run at once (2; for stage 2 also
# 4): `bash bench/vae_data_parallel/bench.sh vertex|pair`.
#   vertex (stage 2, weights/vae.vertex.train.json): 1, 2, 1, 2, then 4, 2;
#   pair (stage 3, weights/vae.pair.train.json): 1, 2, 1, 2.
# Writes bench/vae_data_parallel/STAGE_dpK_rR.json (`meshflow bench train-vae`, 30 steps after
# one warm-up, the first 256 training meshes). Run it on an otherwise idle machine.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
M="${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target}/release/meshflow"
OUT=bench/vae_data_parallel
STAGE="${1:?usage: bench.sh vertex|pair}"
for k in 1 2 4; do
    python3 -c "import json; c=json.load(open('weights/vae.$STAGE.train.json')); c['data_parallel']=$k; json.dump(c, open('/tmp/${STAGE}_dp$k.json','w'), indent=2)"
done
run() { "$M" bench train-vae --config "/tmp/${STAGE}_dp$1.json" --steps 30 -o "$OUT/${STAGE}_dp$1_r$2.json" | tail -2 | head -1; }
for round in 1 2; do
    run 1 "$round"
    run 2 "$round"
done
if [[ "$STAGE" == vertex ]]; then
    run 4 3
    run 2 3
fi
