#!/usr/bin/env bash
# Generation per stage, side by side in one run (issue 15 item 8, commit a4df796, 2026-11-29):
#   bash bench/pair_head_speed/grid/bench.sh BEFORE AFTER
# BEFORE and AFTER are two builds of `meshflow` (here: main before and after the overlap grid).
# Three arms, alternated, two rounds, `meshflow bench generate --runs 20` on the bundled
# lantern (12 candidates; CPU, both threads):
#   no_head  BEFORE with the shipped VAE's pair head left out (../no_head/strip_head.py): the
#            stage times before the head, which item 8 compares with;
#   before   BEFORE with the shipped pair;
#   after    AFTER with the shipped pair.
# Writes bench/pair_head_speed/grid/{no_head,before,after}_rR.json and prints the medians.
# Run it on an otherwise idle machine.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../../.."
BEFORE="$1"
AFTER="$2"
DIR=bench/pair_head_speed/grid
STRIPPED="$(mktemp -d)"
trap 'rm -rf "$STRIPPED"' EXIT
python3 bench/pair_head_speed/no_head/strip_head.py weights "$STRIPPED"
for round in 1 2; do
    "$BEFORE" bench generate --runs 20 --weights "$STRIPPED" -o "$DIR/no_head_r$round.json" >/dev/null
    "$BEFORE" bench generate --runs 20 -o "$DIR/before_r$round.json" >/dev/null
    "$AFTER" bench generate --runs 20 -o "$DIR/after_r$round.json" >/dev/null
done
python3 - "$DIR" <<'PY'
import json, sys
d = sys.argv[1]
stages = ('condition_s', 'sample_s', 'decode_s', 'extract_s', 'fit_s')
print('arm      round ' + ' '.join(f'{s:>12s}' for s in stages) + f" {'whole_s':>9s} faces")
for r in (1, 2):
    for arm in ('no_head', 'before', 'after'):
        j = json.load(open(f'{d}/{arm}_r{r}.json'))
        print(f'{arm:8s} {r:5d} ' + ' '.join(f"{j['median'][s]:12.4f}" for s in stages)
              + f" {j['median_total_s']:9.3f} {j['faces']}")
PY
