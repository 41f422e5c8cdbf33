#!/usr/bin/env bash
# Stage 4 per edge source, two builds side by side (issue 15 item 8, commit a4df796, 2026-11-29):
#   bash bench/pair_head_speed/trace/bench.sh BEFORE AFTER
# For the bundled lantern and the page's five examples, `meshflow bench pair-head --seconds
# 0.5` with BEFORE then AFTER (alternated per input): both decode the same candidates, so
# the edges and candidate faces match and only the extraction's own speed differs. Writes
# bench/pair_head_speed/trace/{before,after}_NAME.json and prints one table. Run it on an
# otherwise idle machine.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../../.."
BEFORE="$1"
AFTER="$2"
DIR=bench/pair_head_speed/trace
for input in tests/fixtures/points/stone_lantern_2048.ply web/examples/*.ply; do
    name="$(basename "$input" .ply)"
    "$BEFORE" bench pair-head --input "$input" --seconds 0.5 -o "$DIR/before_$name.json" >/dev/null
    "$AFTER" bench pair-head --input "$input" --seconds 0.5 -o "$DIR/after_$name.json" >/dev/null
done
python3 - "$DIR" <<'PY'
import glob, json, os, sys
d = sys.argv[1]
sources = ('embeddings', 'spacetime_distances', 'pair_head_distances')
print(f"{'input':28s} {'build':7s} " + ' '.join(f'{s + " ms":>24s}' for s in sources)
      + f" {'cliques (emb / head)':>21s}")
for path in sorted(glob.glob(f'{d}/before_*.json')):
    name = os.path.basename(path)[len('before_'):-len('.json')]
    for build in ('before', 'after'):
        j = json.load(open(f'{d}/{build}_{name}.json'))
        print(f'{name:28s} {build:7s} ' + ' '.join(f"{j[s]['median_ms']:24.2f}" for s in sources)
              + f" {j['embeddings']['clique_faces']:>10d} / {j['pair_head_distances']['clique_faces']:<8d}")
PY
