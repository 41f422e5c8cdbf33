#!/usr/bin/env bash
# Reproduce the shipped MeshVAE (weights/vae.*): `bash scripts/train_vae.sh RUN [DATA]`.
#
# 1. RUN/base: `meshflow train vae --config weights/vae.train.json --data-parallel 2` (10,000
#    steps of the whole VAE with 64-wide latents).
# 2. RUN/decoder: `meshflow train vae --config weights/vae.pair.train.json --init RUN/base
#    --data-parallel 2` (13,500 steps of the decoder alone, lr 3e-4): one self-attention block
#    over the vertex tokens added (starting as the identity) and a pair head (starting silent)
#    that rescores each vertex's 16 best partners from both vertices' features and the pair's
#    context; near non-edges weighted 10, positions weighted 80; written with the extraction
#    threshold chosen on the validation split (tau -2.5). The encoder stays the first stage's.
# `--data-parallel 2` computes each batch's gradient from two half-batches run at once on the
# two cores: the same gradient up to float rounding, 1.8-1.9x the steps per second, so the
# files match the shipped ones statistically, not bit for bit. About 135 minutes end to end on
# a 2-core host whose flex matrix products peak near 74 GFLOP/s (50 + 83 minutes;
# docs/experiments/2026-11-29-two-stage-vae.md). The encoder sets the latent space, so a VAE
# from this script needs a DiT trained on its latents (scripts/train_dit.sh) before the two
# ship together.
# RUN/decoder/vae.* are the files to ship. Every stage resumes from its checkpoints when
# interrupted; each logs to RUN/<stage>/train.log and RUN/<stage>/metrics.jsonl.
set -euo pipefail

RUN="$(realpath -m "${1:?usage: scripts/train_vae.sh RUN [DATA]}")"
DATA="${2:+$(realpath "$2")}"
source "$(dirname "${BASH_SOURCE[0]}")/train_stages.sh"

if [[ ! -f "$RUN/base/vae.manifest.json" ]]; then
    stage "$RUN/base" train vae --config weights/vae.train.json --data-parallel 2
fi
stage "$RUN/decoder" train vae --config weights/vae.pair.train.json --init "$RUN/base" \
    --data-parallel 2
echo "[train_vae.sh] ship: cp $RUN/decoder/vae.{safetensors,json,manifest.json} weights/ && node scripts/half-weights.mjs"
