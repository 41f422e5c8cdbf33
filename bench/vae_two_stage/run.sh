#!/usr/bin/env bash
# A two-stage candidate for `scripts/train_vae.sh`, timed end to end:
# `bash bench/vae_two_stage/run.sh RUN [DATA]`.
# 1. RUN/base: stage 1 as shipped (`weights/vae.train.json`), but with `--data-parallel 2`.
# 2. RUN/decoder: the pair-head stage's recipe (`weights/vae.pair.train.json`: vertex block,
#    near non-edges weighted 10, positions 80, pair head, lr 3e-4) straight from stage 1, for
#    13,500 steps (`bench/vae_two_stage/decoder.train.json`), instead of a 16,000-step
#    stage 2 followed by a 7,000-step stage 3.
# Writes RUN/time.log with the start and end of each stage.
set -euo pipefail
RUN="$(realpath -m "${1:?usage: run.sh RUN [DATA]}")"
DATA="${2:+$(realpath "$2")}"
CONFIG="$(realpath "$(dirname "${BASH_SOURCE[0]}")/decoder.train.json")"
mkdir -p "$RUN"
echo "start $(date -u +%FT%TZ)" >> "$RUN/time.log"
source "$(dirname "${BASH_SOURCE[0]}")/../../scripts/train_stages.sh"
echo "built $(date -u +%FT%TZ)" >> "$RUN/time.log"
if [[ ! -f "$RUN/base/vae.manifest.json" ]]; then
    stage "$RUN/base" train vae --config weights/vae.train.json --data-parallel 2
fi
echo "stage 1 done $(date -u +%FT%TZ)" >> "$RUN/time.log"
stage "$RUN/decoder" train vae --config "$CONFIG" --init "$RUN/base" --data-parallel 2
echo "stage 2 done $(date -u +%FT%TZ)" >> "$RUN/time.log"
