#!/usr/bin/env bash
# Two builds of `meshflow` side by side in one run (this machine is noisy: compare within a
# round): first, each input generated at the defaults by both, and the GLBs compared byte for
# byte (a change meant to be exact must give the same meshes); then `meshflow bench generate
# --runs 2` at the defaults, alternating the builds, ROUNDS times, with the BEFORE build's
# unsharpened generation (`--no-sharpen`) as a third arm. JSON per run in OUT
# (INPUT_ARM_rROUND.json, ARM one of before, after, plain), then a Markdown table of the
# higher of the rounds' medians.
#
#   bash bench/sharpen_time/before_after.sh BEFORE_BINARY AFTER_BINARY OUT [ROUNDS]
#
# PLAIN=after takes the unsharpened arm from the AFTER build instead, for a BEFORE build
# older than `--no-sharpen` (the build issue 52 was filed against, which had no sharpening).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
BEFORE="$1"; AFTER="$2"; OUT="$3"; ROUNDS="${4:-2}"
PLAIN="${PLAIN:-before}"
case "$PLAIN" in before) PLAIN_BIN="$BEFORE" ;; after) PLAIN_BIN="$AFTER" ;; *) echo "PLAIN must be before or after" >&2; exit 2 ;; esac
mkdir -p "$OUT/meshes"
inputs=(
    "$ROOT/tests/fixtures/hard_surface/points/box.ply"
    "$ROOT/web/examples/milk_truck_4096.ply"
    "$ROOT/tests/fixtures/hard_surface/points/stair_noise1.ply"
    "$ROOT/tests/fixtures/points/stone_lantern_2048.ply"
)
same=0; differ=0
for input in "${inputs[@]}" "$ROOT"/tests/fixtures/hard_surface/points/*.ply; do
    name="$(basename "$input" .ply)"
    "$BEFORE" generate "$input" -o "$OUT/meshes/${name}_before.glb" >/dev/null 2>&1
    "$AFTER" generate "$input" -o "$OUT/meshes/${name}_after.glb" >/dev/null 2>&1
    if cmp -s "$OUT/meshes/${name}_before.glb" "$OUT/meshes/${name}_after.glb"; then
        same=$((same + 1))
    else
        differ=$((differ + 1)); echo "differs: $name"
    fi
done
echo "meshes: $same the same, $differ different"
for round in $(seq 1 "$ROUNDS"); do
    for input in "${inputs[@]}"; do
        name="$(basename "$input" .ply)"
        "$BEFORE" bench generate --input "$input" --runs 2 -o "$OUT/${name}_before_r$round.json" >/dev/null
        "$AFTER" bench generate --input "$input" --runs 2 -o "$OUT/${name}_after_r$round.json" >/dev/null
        "$PLAIN_BIN" bench generate --input "$input" --runs 2 --no-sharpen -o "$OUT/${name}_plain_r$round.json" >/dev/null
    done
done
python3 - "$OUT" "$PLAIN" <<'PY'
import json, pathlib, sys
out, plain = pathlib.Path(sys.argv[1]), sys.argv[2]
rows = {}
for f in sorted(out.glob("*_r*.json")):
    name, arm, _ = f.stem.rsplit("_", 2)
    rows.setdefault(name, {}).setdefault(arm, []).append(json.loads(f.read_text()))
print(f"| input | unsharpened ({plain}) | total, before | total, after | after / before | after / unsharpened | fit stage, before | fit stage, after | faces |")
print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
for name, arms in rows.items():
    worst = lambda arm, f: max(f(r) for r in arms[arm])
    p, b, a = (worst(arm, lambda r: r["median_total_s"]) for arm in ("plain", "before", "after"))
    fb, fa = (worst(arm, lambda r: r["median"]["fit_s"]) for arm in ("before", "after"))
    print(f"| {name} | {p:.2f} s | {b:.2f} s | {a:.2f} s | {a / b:.2f} | {a / p:.2f} | {fb:.2f} s | {fa:.2f} s | {arms['after'][0]['faces']} |")
PY
