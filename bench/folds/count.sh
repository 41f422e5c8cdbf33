#!/usr/bin/env bash
# Folded edges (TopologyReport::folded_edges: two consistently wound faces whose normals are
# more than about 143 degrees apart) in the meshes an evaluation folder holds: ours
# (K.ours.glb), Poisson + QEM's (K.poisson.ply), the ground truth's (K.gt.glb), the VAE's
# reconstruction (K.vae.glb) and, when
# present, the unsharpened mesh (K.today.glb). Means, and the share of meshes with any, per arm.
#
#   bash bench/folds/count.sh DIR      # DIR: a `meshflow eval generate --meshes DIR` folder
set -euo pipefail
dir=${1:?usage: count.sh DIR}
meshflow=${MESHFLOW:-${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target}/release/meshflow}
for arm in ours poisson gt vae today; do
    for f in "$dir"/*."$arm".glb "$dir"/*."$arm".ply; do
        [ -e "$f" ] || continue
        "$meshflow" inspect --json "$f" 2>/dev/null |
            python3 -c "import json,sys; t=json.load(sys.stdin)['topology']; print('$arm', t['folded_edges'], t['edges'])" || true
    done
done | python3 -c '
import sys, collections
rows = collections.defaultdict(list)
for line in sys.stdin:
    arm, folded, edges = line.split()
    rows[arm].append((int(folded), int(edges)))
print("| arm | meshes | folded edges a mesh | meshes with any | share of edges |")
print("|---|---:|---:|---:|---:|")
for arm, r in rows.items():
    n = len(r)
    print(f"| {arm} | {n} | {sum(f for f, _ in r) / n:.2f} | {sum(1 for f, _ in r if f) / n:.0%} | "
          f"{sum(f for f, _ in r) / max(sum(e for _, e in r), 1):.2%} |")
'
