#!/usr/bin/env bash
# Reproduce the shipped DiT (weights/dit.*) on the shipped VAE's latents:
# `bash scripts/train_dit.sh RUN [DATA]`.
#
# 1. RUN/base: `meshflow train dit --vae weights --config weights/dit.train.json` (10,000 steps
#    of 16 at lr 3e-4; about 55-60 minutes alone on the 2-core CPU);
# 2. RUN/continued: `meshflow train dit --vae weights --init RUN/base --config
#    weights/dit.continue.train.json` (4,000 more steps at lr 1e-4 on a new cosine, about 26
#    minutes): better validation and test Chamfer distance at every sampling seed tried
#    (BENCHMARKS.md "Trained longer still").
# RUN/continued/dit.* are the files to ship. Both stages resume from their checkpoints when
# interrupted; each logs to RUN/<stage>/train.log and RUN/<stage>/metrics.jsonl.
set -euo pipefail

RUN="$(realpath -m "${1:?usage: scripts/train_dit.sh RUN [DATA]}")"
DATA="${2:+$(realpath "$2")}"
source "$(dirname "${BASH_SOURCE[0]}")/train_stages.sh"

if [[ ! -f "$RUN/base/dit.manifest.json" ]]; then
    stage "$RUN/base" train dit --vae weights --config weights/dit.train.json
fi
stage "$RUN/continued" train dit --vae weights --config weights/dit.continue.train.json \
    --init "$RUN/base"
echo "[train_dit.sh] ship: cp $RUN/continued/dit.{safetensors,json,manifest.json} weights/"
