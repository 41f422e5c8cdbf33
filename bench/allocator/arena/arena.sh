#!/usr/bin/env bash
# One malloc arena for all threads against one per thread (glibc default), both with the
# CLI's memory policy: `bash bench/allocator/arena/arena.sh` with KEEP, a build of the CLI with
# the policy, in /tmp/meshflow_alloc, and /tmp/alloc_{base,vertex,pair}.json written as
# bench/allocator/bench.sh writes them. Two rounds, arms alternated; writes t.tsv (page
# faults, ms per step) and the JSON files beside it.
set -e
cd "$(dirname "${BASH_SOURCE[0]}")/../../.."
OUT=bench/allocator/arena; mkdir -p $OUT
printf 'arm\tstage\tround\tfaults\tstep_ms\n' > $OUT/t.tsv
for round in 1 2; do
  for stage in vertex pair base; do
    for arm in many one; do
      v=A=1; [[ $arm == one ]] && v=MALLOC_ARENA_MAX=1
      f=$( { env $v /usr/bin/time -f '%R' /tmp/meshflow_alloc bench train-vae --config /tmp/alloc_$stage.json --steps 30 -o $OUT/${stage}_${arm}_r$round.json >/dev/null; } 2>&1 | tail -1)
      ms=$(python3 -c "import json;print(round(json.load(open('$OUT/${stage}_${arm}_r$round.json'))['step_ms']))")
      printf '%s\t%s\t%s\t%s\t%s\n' $arm $stage $round $f $ms >> $OUT/t.tsv
    done
  done
  for arm in many one; do
    v=A=1; [[ $arm == one ]] && v=MALLOC_ARENA_MAX=1
    env $v /tmp/meshflow_alloc bench generate --runs 10 -o $OUT/gen_${arm}_r$round.json >/dev/null 2>&1
  done
done
