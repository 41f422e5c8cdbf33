#!/usr/bin/env bash
# Whole-generation time with and without sharpening, side by side in one run: for each input,
# `meshflow bench generate` at the defaults, then the same with --no-sharpen, alternating,
# ROUNDS times (this machine is noisy: compare within a round). JSON per run in OUT, then a
# Markdown table of the medians over rounds.
#
#   bash bench/sharpen_time.sh OUT [ROUNDS]
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
MESHFLOW="${MESHFLOW:-${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target}/release/meshflow}"
OUT="$1"; ROUNDS="${2:-2}"
mkdir -p "$OUT"
inputs=(
    "$ROOT/tests/fixtures/points/stone_lantern_2048.ply"
    "$ROOT/web/examples/milk_truck_4096.ply"
    "$ROOT/tests/fixtures/hard_surface/points/box.ply"
    "$ROOT/tests/fixtures/hard_surface/points/stair_noise1.ply"
)
for round in $(seq 1 "$ROUNDS"); do
    for input in "${inputs[@]}"; do
        name="$(basename "$input" .ply)"
        "$MESHFLOW" bench generate --input "$input" --runs 2 -o "$OUT/${name}_sharpen_r$round.json" >/dev/null
        "$MESHFLOW" bench generate --input "$input" --runs 2 --no-sharpen -o "$OUT/${name}_plain_r$round.json" >/dev/null
    done
done
python3 - "$OUT" <<'PY'
import json, pathlib, sys
out = pathlib.Path(sys.argv[1])
rows = {}
for f in sorted(out.glob("*_r*.json")):
    name, arm, _ = f.stem.rsplit("_", 2)
    r = json.loads(f.read_text())
    rows.setdefault(name, {}).setdefault(arm, []).append(r)
print("| input | total, plain (s) | total, sharpened (s) | ratio | fit stage, plain | fit stage, sharpened | faces plain -> sharpened |")
print("|---|---:|---:|---:|---:|---:|---|")
for name, arms in rows.items():
    med = lambda arm, f: sorted(f(r) for r in arms[arm])[len(arms[arm]) // 2]
    plain, sharp = med("plain", lambda r: r["median_total_s"]), med("sharpen", lambda r: r["median_total_s"])
    print(f"| {name} | {plain:.2f} | {sharp:.2f} | {sharp / plain:.2f} | "
          f"{med('plain', lambda r: r['median']['fit_s']):.2f} | {med('sharpen', lambda r: r['median']['fit_s']):.2f} | "
          f"{arms['plain'][0]['faces']} -> {arms['sharpen'][0]['faces']} |")
PY
