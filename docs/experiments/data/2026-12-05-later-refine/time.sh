#!/usr/bin/env bash
# Whole-generation time of sharpening's arms side by side in one run, alternating, on the four
# inputs of bench/sharpen_time/before_after.sh:
#   bash time.sh MESHFLOW OUT [ROUNDS]
# MESHFLOW: a release CLI with --sharpen-later-refine. Arms: unsharpened (--no-sharpen), p8_lr2
# (the shipped 8 rounds, 2 splits each), p8_lr1 and p12_lr1 (rounds after the first split
# once). Each is `meshflow bench generate --runs 2`; the table gives the middle of the rounds'
# medians, whole generation and fit stage.
set -euo pipefail
B="$1"; OUT="$2"; ROUNDS="${3:-3}"
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../../../.." && pwd)"
mkdir -p "$OUT"
inputs=(
    "$ROOT/tests/fixtures/hard_surface/points/box.ply"
    "$ROOT/web/examples/milk_truck_4096.ply"
    "$ROOT/tests/fixtures/hard_surface/points/stair_noise1.ply"
    "$ROOT/tests/fixtures/points/stone_lantern_2048.ply"
)
declare -A args=(
    [unsharpened]="--no-sharpen"
    [p8_lr2]="--sharpen-passes 8 --sharpen-later-refine 2"
    [p8_lr1]="--sharpen-passes 8 --sharpen-later-refine 1"
    [p12_lr1]="--sharpen-passes 12 --sharpen-later-refine 1"
)
for round in $(seq 1 "$ROUNDS"); do
    for input in "${inputs[@]}"; do
        for arm in unsharpened p8_lr2 p8_lr1 p12_lr1; do
            # shellcheck disable=SC2086
            "$B" bench generate --input "$input" --runs 2 ${args[$arm]} \
                -o "$OUT/$(basename "$input" .ply)_${arm}_r$round.json" >/dev/null
        done
    done
done
python3 - "$OUT" <<'PY'
import json, pathlib, sys
out = pathlib.Path(sys.argv[1])
arms = ["unsharpened", "p8_lr2", "p8_lr1", "p12_lr1"]
rows = {}
for f in sorted(out.glob("*_r*.json")):
    stem = f.stem.rsplit("_", 1)[0]
    arm = next(a for a in arms if stem.endswith("_" + a))
    rows.setdefault(stem[: -len(arm) - 1], {}).setdefault(arm, []).append(json.loads(f.read_text()))
mid = lambda rs, f: sorted(f(r) for r in rs)[len(rs) // 2]
print("| input | " + " | ".join(arms) + " | p8_lr2 / unsharpened | p8_lr1 / unsharpened | p12_lr1 / unsharpened | fit stage (" + ", ".join(arms) + ") | faces (p8_lr2, p8_lr1, p12_lr1) |")
print("|---|" + "---:|" * 9)
for name, a in rows.items():
    t = {k: mid(a[k], lambda r: r["median_total_s"]) for k in arms}
    fit = ", ".join(f"{mid(a[k], lambda r: r['median']['fit_s']):.2f}" for k in arms)
    faces = ", ".join(str(a[k][0]["faces"]) for k in arms[1:])
    print(f"| {name} | " + " | ".join(f"{t[k]:.2f} s" for k in arms)
          + " | " + " | ".join(f"{t[k] / t['unsharpened']:.2f}" for k in arms[1:]) + f" | {fit} s | {faces} |")
print()
print("machine:", json.loads(next(out.glob("*_r1.json")).read_text())["machine"])
PY
