#!/usr/bin/env bash
# glibc's default allocator policy against the CLI's (meshflow::device::keep_freed_memory), side by
# side: `bash bench/allocator/bench.sh DEFAULT KEEP`, two builds of the CLI, DEFAULT without
# the mallopt call and KEEP with it. Two rounds, binaries alternated:
# - a training step of each shipped VAE stage (`meshflow bench train-vae --steps 30`; stage 1
#   in one pass, stages 2 and 3 in two half-batches as scripts/train_vae.sh runs them), with
#   the process's minor page faults (GNU time);
# - the whole generation (`meshflow bench generate --runs 20`, lantern).
# Writes bench/allocator/*.json and bench/allocator/faults.tsv. Run it on an otherwise idle machine.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
OUT=bench/allocator
DEFAULT="${1:?usage: bench.sh DEFAULT KEEP}"
KEEP="${2:?usage: bench.sh DEFAULT KEEP}"
for stage in vertex pair; do
    python3 -c "import json; c=json.load(open('weights/vae.$stage.train.json')); c['data_parallel']=2; json.dump(c, open('/tmp/alloc_$stage.json','w'), indent=2)"
done
cp weights/vae.train.json /tmp/alloc_base.json
printf 'binary\tstage\tround\tminor_faults\n' > "$OUT/faults.tsv"
for round in 1 2; do
    for stage in base vertex pair; do
        for arm in default keep; do
            bin=$DEFAULT; [[ $arm == keep ]] && bin=$KEEP
            faults=$( { /usr/bin/time -f '%R' "$bin" bench train-vae --config "/tmp/alloc_$stage.json" \
                --steps 30 -o "$OUT/train_${stage}_${arm}_r$round.json" >/dev/null; } 2>&1 | tail -1)
            printf '%s\t%s\t%s\t%s\n' "$arm" "$stage" "$round" "$faults" >> "$OUT/faults.tsv"
        done
    done
    for arm in default keep; do
        bin=$DEFAULT; [[ $arm == keep ]] && bin=$KEEP
        "$bin" bench generate --runs 20 -o "$OUT/generate_${arm}_r$round.json" >/dev/null
    done
done
