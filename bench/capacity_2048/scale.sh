#!/usr/bin/env bash
# Issue 53 item 3: how generation scales with the vertex budget. `bash
# bench/capacity_2048/scale.sh WEIGHTS OUT [INPUT]`: `meshflow bench generate --vertices N
# --runs 2` for N = 128, 512, 1,024 and 2,048 on INPUT (default: the page's milk truck, 4,096
# points) with the pair in WEIGHTS (a capacity of 2,048: bench/capacity_2048/raise.py makes one
# from weights/), each in its own process under /usr/bin/time for the peak resident memory.
# Writes OUT/bench_N.json and OUT/scale.json (per N: the median stage times, the generated
# mesh's size, peak RSS in MiB) and prints a table.
set -euo pipefail
weights=$1 out=$2 input=${3:-web/examples/milk_truck_4096.ply}
meshflow=${MESHFLOW:-meshflow}
mkdir -p "$out"
for n in 128 512 1024 2048; do
    /usr/bin/time -f %M -o "$out/rss_$n.txt" "$meshflow" bench generate --input "$input" \
        --weights "$weights" --vertices "$n" --runs 2 -o "$out/bench_$n.json" > /dev/null
done
python3 - "$out" <<'PY'
import json, os, sys
out = sys.argv[1]
rows = {}
for n in (128, 512, 1024, 2048):
    b = json.load(open(os.path.join(out, f'bench_{n}.json')))
    rows[n] = dict(b, peak_rss_mib=int(open(os.path.join(out, f'rss_{n}.txt')).read()) / 1024)
json.dump(rows, open(os.path.join(out, 'scale.json'), 'w'), indent=2)
print('| vertices | condition | sample | decode | extract | fit | whole | faces | peak RSS |')
print('|---:|---:|---:|---:|---:|---:|---:|---:|---:|')
for n, r in rows.items():
    m = r['median']
    stages = ' | '.join(f"{m[k]:.3f} s" for k in ('condition_s', 'sample_s', 'decode_s', 'extract_s', 'fit_s'))
    print(f"| {n} | {stages} | **{r['median_total_s']:.2f} s** | {r['faces']} | {r['peak_rss_mib']:.0f} MiB |")
PY
