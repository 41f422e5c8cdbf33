#!/usr/bin/env bash
# Reproduce the shipped DiT (weights/dit.*) on the shipped VAE's latents:
# `bash scripts/train_dit.sh RUN [DATA]`; `VAE=DIR` trains on another VAE's latents instead
# (e.g. a run of scripts/train_vae.sh: VAE=VAE_RUN/decoder).
#
# `meshflow train dit --vae weights --config weights/dit.train.json --data-parallel 2 -o RUN`:
# 6,000 steps of 16 at lr 3e-4, every block reading 256 of the input points. Each batch's
# gradient comes from two half-batches at once on the two cores: the same up to float rounding
# and 1.9x the steps per second of one pass. About 36 minutes on a 2-core CPU whose flex matrix
# products peak near 200 GFLOP/s, 73 near 74 GFLOP/s (BENCHMARKS.md "Training time";
# docs/experiments/2026-11-28-data-parallel-training.md).
# RUN/dit.* are the files to ship. The run resumes from its checkpoint when interrupted; it
# logs to RUN/train.log and RUN/metrics.jsonl.
set -euo pipefail

RUN="$(realpath -m "${1:?usage: scripts/train_dit.sh RUN [DATA]}")"
DATA="${2:+$(realpath "$2")}"
VAE="${VAE:+$(realpath "$VAE")}"
source "$(dirname "${BASH_SOURCE[0]}")/train_stages.sh"

stage "$RUN" train dit --vae "${VAE:-weights}" --config weights/dit.train.json --data-parallel 2
echo "[train_dit.sh] ship: cp $RUN/dit.{safetensors,json,manifest.json} weights/ && node scripts/half-weights.mjs"
