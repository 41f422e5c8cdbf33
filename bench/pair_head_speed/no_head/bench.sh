#!/usr/bin/env bash
# Generation per stage with and without the pair head, one binary, side by side (issue 15
# item 8): `bash bench/pair_head_speed/no_head/bench.sh [MESHFLOW]`. The shipped pair against
# the same pair with the VAE's pair head left out (strip_head.py; for timing only). Three
# rounds, the two arms alternated, `meshflow bench generate --runs 20` on the bundled lantern
# (12 candidates; CPU, both threads); writes bench/pair_head_speed/no_head/{head,no_head}_rR.json
# and prints the medians. Run it on an otherwise idle machine.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../../.."
MESHFLOW="${1:-${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target}/release/meshflow}"
DIR=bench/pair_head_speed/no_head
STRIPPED="$(mktemp -d)"
trap 'rm -rf "$STRIPPED"' EXIT
python3 "$DIR/strip_head.py" weights "$STRIPPED"
for round in 1 2 3; do
    "$MESHFLOW" bench generate --runs 20 -o "$DIR/head_r$round.json" >/dev/null
    "$MESHFLOW" bench generate --runs 20 --weights "$STRIPPED" -o "$DIR/no_head_r$round.json" >/dev/null
done
python3 - "$DIR" <<'PY'
import json, sys
d = sys.argv[1]
stages = ('condition_s', 'sample_s', 'decode_s', 'extract_s', 'fit_s')
print('arm      round ' + ' '.join(f'{s:>12s}' for s in stages) + f" {'whole_s':>9s} faces")
for r in (1, 2, 3):
    for arm in ('head', 'no_head'):
        j = json.load(open(f'{d}/{arm}_r{r}.json'))
        print(f'{arm:8s} {r:5d} ' + ' '.join(f"{j['median'][s]:12.4f}" for s in stages)
              + f" {j['median_total_s']:9.3f} {j['faces']}")
PY
