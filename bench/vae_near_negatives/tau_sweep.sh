#!/usr/bin/env bash
# The edge threshold tau swept for each arm's VAE (and the shipped one) on the validation split:
# near-negative weighting moves where the decoder's scores cross, so arms are compared at each
# one's best tau, not only at the shipped 0.6.
#   bash bench/vae_near_negatives/tau_sweep.sh RUNS OUT [ARM ...]
# RUNS/<arm> holds a finished run's vae.*; "shipped" stands for weights/. Writes
# OUT/<arm>_tau<T>.json (`meshflow eval vae --split val`) for each tau.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
RUNS="${1:?usage: tau_sweep.sh RUNS OUT [ARM ...]}"; OUT="${2:?}"; shift 2
MESHFLOW="${MESHFLOW:-${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target}/release/meshflow}"
TAUS="${TAUS:--1.0 -0.4 0.0 0.3 0.6 0.9 1.2 1.6 2.0 2.5}"
ARMS=("$@"); [[ ${#ARMS[@]} -gt 0 ]] || ARMS=(shipped a_control b_near1 c_near3)
mkdir -p "$OUT"
for arm in "${ARMS[@]}"; do
    src="$RUNS/$arm"; [[ "$arm" == shipped ]] && src="$ROOT/weights"
    for tau in $TAUS; do
        tmp="$(mktemp -d)"
        cp "$src"/vae.safetensors "$tmp"/
        for f in vae.json vae.manifest.json; do
            python3 -c "import json,sys; d=json.load(open(sys.argv[1])); m=d.get('model',d); m['tau']=float(sys.argv[2]); json.dump(d,open(sys.argv[3],'w'),indent=2)" \
                "$src/$f" "$tau" "$tmp/$f"
        done
        "$MESHFLOW" eval vae --split val --weights "$tmp" -o "$OUT/${arm}_tau${tau}.json" > /dev/null
        rm -rf "$tmp"
        echo "[tau_sweep] $arm tau $tau done"
    done
done
