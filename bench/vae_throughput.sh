#!/usr/bin/env bash
# MeshVAE training throughput side by side, in one run: a `meshflow` binary built from e9e3de3
# (before length buckets) on that commit's ship preset, and this checkout's binary on the same
# preset padded to 512 and with length buckets. meshes/s from metrics.jsonl over steps 10-40.
#   bash bench/vae_throughput.sh OLD_MESHFLOW [OUT_DIR]
set -e
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
OLD="${1:?usage: vae_throughput.sh OLD_MESHFLOW [OUT_DIR]}"
NEW="${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target}/release/meshflow"
OUT="${2:-$(mktemp -d)}"; rm -rf "$OUT"; mkdir -p "$OUT"
git show e9e3de3:weights/vae.train.json > $OUT/old.json
python3 - <<PY
import json
c=json.load(open('$OUT/old.json'))
c['model']['length_buckets']=True
json.dump(c,open('$OUT/buckets.json','w'))
PY
rate() { python3 -c "
import json,sys
r=[json.loads(l) for l in open('$1/metrics.jsonl') if '\"lr\"' in l]
a,b=r[9],r[39]
print(round(30*8/(b['elapsed_s']-a['elapsed_s']),2))"; }
for round in 1; do
  for arm in old padded buckets; do
    case $arm in
      old) $OLD train vae --out $OUT/$arm$round --config $OUT/old.json --steps 40 --limit 300 >/dev/null 2>&1 ;;
      padded) $NEW train vae --out $OUT/$arm$round --config $OUT/old.json --steps 40 --limit 300 >/dev/null 2>&1 ;;
      buckets) $NEW train vae --out $OUT/$arm$round --config $OUT/buckets.json --steps 40 --limit 300 >/dev/null 2>&1 ;;
    esac
    echo "$arm round $round: $(rate $OUT/$arm$round) meshes/s"
  done
done
