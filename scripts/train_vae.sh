#!/usr/bin/env bash
# Reproduce the shipped MeshVAE (weights/vae.*): `bash scripts/train_vae.sh RUN [DATA]`.
#
# 1. RUN/base: `meshflow train vae --config weights/vae.train.json` (10,000 steps of the whole
#    VAE with 64-wide latents; about 37 minutes alone on a 2-core CPU whose flex matrix
#    products peak near 200 GFLOP/s; on one near 95 GFLOP/s every stage takes about twice
#    as long: BENCHMARKS.md). One pass per batch, so the encoder, and the latent space the
#    shipped DiT was trained on, come out bit for bit.
# 2. RUN/vertex: `meshflow train vae --config weights/vae.vertex.train.json --init RUN/base
#    --data-parallel 2` (16,000 steps of the decoder alone, about 47 minutes): one
#    self-attention block over the vertex tokens added (starting as the identity), near
#    non-edges weighted 10, positions weighted 80, written with the extraction threshold
#    chosen on the validation split (tau -2.5). The encoder stays the first stage's.
# 3. RUN/pair: `meshflow train vae --config weights/vae.pair.train.json --init RUN/vertex
#    --data-parallel 2` (7,000 steps of the decoder alone, lr 3e-4, about 21 minutes): a pair
#    head added (starting silent) that rescores each vertex's 16 best partners from both
#    vertices' features and the pair's context (the best triangle it closes, the quad diagonal
#    it competes with). The encoder is still the first stage's.
# `--data-parallel 2` computes each batch's gradient from two half-batches run at once on the
# two cores: the same gradient up to float rounding, 1.65x (stage 2) and 1.9x (stage 3) the
# steps per second. The decoder stages therefore match the shipped decoder statistically, not
# bit for bit.
# RUN/pair/vae.* are the files to ship. Every stage resumes from its checkpoints when
# interrupted; each logs to RUN/<stage>/train.log and RUN/<stage>/metrics.jsonl.
set -euo pipefail

RUN="$(realpath -m "${1:?usage: scripts/train_vae.sh RUN [DATA]}")"
DATA="${2:+$(realpath "$2")}"
source "$(dirname "${BASH_SOURCE[0]}")/train_stages.sh"

if [[ ! -f "$RUN/base/vae.manifest.json" ]]; then
    stage "$RUN/base" train vae --config weights/vae.train.json
fi
if [[ ! -f "$RUN/vertex/vae.manifest.json" ]]; then
    stage "$RUN/vertex" train vae --config weights/vae.vertex.train.json --init "$RUN/base" \
        --data-parallel 2
fi
stage "$RUN/pair" train vae --config weights/vae.pair.train.json --init "$RUN/vertex" \
    --data-parallel 2
echo "[train_vae.sh] ship: cp $RUN/pair/vae.{safetensors,json,manifest.json} weights/"
