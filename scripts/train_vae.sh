#!/usr/bin/env bash
# Reproduce the shipped MeshVAE (weights/vae.*): `bash scripts/train_vae.sh RUN [DATA]`.
#
# 1. RUN/base: `meshflow train vae --config weights/vae.train.json` (10,000 steps of the whole
#    VAE; about 55-60 minutes alone on the 2-core CPU);
# 2. RUN/decoder: `meshflow train vae --config weights/vae.decoder.train.json --init RUN/base`
#    (14,000 steps of the decoder alone, about 45 minutes): the encoder, and so the latent space
#    the shipped DiT was trained on, stays bit for bit the first stage's.
# RUN/decoder/vae.* are the files to ship. Both stages resume from their checkpoints when
# interrupted; each logs to RUN/<stage>/train.log and RUN/<stage>/metrics.jsonl.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
RUN="${1:?usage: scripts/train_vae.sh RUN [DATA]}"
DATA=("${@:2:1}")
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target}"

cd "$ROOT"
cargo build --release -p meshflow-cli
MESHFLOW="$CARGO_TARGET_DIR/release/meshflow"
data_args=()
[[ -n "${DATA[0]:-}" ]] && data_args=(--data "${DATA[0]}")

mkdir -p "$RUN/base" "$RUN/decoder"
if [[ ! -f "$RUN/base/vae.manifest.json" ]]; then
    "$MESHFLOW" train vae -o "$RUN/base" --config weights/vae.train.json "${data_args[@]}" \
        2>&1 | tee -a "$RUN/base/train.log"
fi
"$MESHFLOW" train vae -o "$RUN/decoder" --config weights/vae.decoder.train.json \
    --init "$RUN/base" "${data_args[@]}" 2>&1 | tee -a "$RUN/decoder/train.log"
echo "[train_vae.sh] ship: cp $RUN/decoder/vae.{safetensors,json,manifest.json} weights/"
