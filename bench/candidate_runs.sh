#!/usr/bin/env bash
# The lantern at the defaults from two CLIs, alternating: `bash bench/candidate_runs.sh BEFORE
# AFTER [ROUNDS]` prints, per round and CLI, the process's wall time (start to GLB written) and
# its stage times from --json, then compares the two GLBs byte for byte
# (docs/experiments/2026-12-04-candidate-runs.md).
set -euo pipefail
before=$1 after=$2 rounds=${3:-5}
input=tests/fixtures/points/stone_lantern_2048.ply
out=$(mktemp -d)
for r in $(seq "$rounds"); do
    for arm in before after; do
        bin=${!arm}
        /usr/bin/time -f %e -o "$out/time" "$bin" generate "$input" -o "$out/$arm.glb" --json \
            > "$out/$arm.json" 2>/dev/null
        python3 - "$arm" "$out/time" "$out/$arm.json" <<'PY'
import json, sys
arm, wall, report = sys.argv[1], open(sys.argv[2]).read().strip(), json.load(open(sys.argv[3]))
stages = ' '.join(f'{k[:-2]}={v:.3f}' for k, v in report['times'].items())
print(f'{arm} round wall={wall} {stages}')
PY
    done
done
cmp "$out/before.glb" "$out/after.glb" && echo "the same GLB"
