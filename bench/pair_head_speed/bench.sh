#!/usr/bin/env bash
# Generation per stage with the pair head's input built (BEFORE, a build of the commit before
# this one) and never built (AFTER, this build): `bash bench/pair_head_speed/bench.sh BEFORE AFTER`.
# Three rounds, the two binaries alternated, `meshflow bench generate --runs 20` on the bundled
# lantern (12 candidates; CPU, both threads); writes bench/pair_head_speed/{before,after}_rR.json.
# Run it on an otherwise idle machine.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
BEFORE="${1:?usage: bench.sh BEFORE AFTER}"
AFTER="${2:?usage: bench.sh BEFORE AFTER}"
for round in 1 2 3; do
    "$BEFORE" bench generate --runs 20 -o "bench/pair_head_speed/before_r$round.json" >/dev/null
    "$AFTER" bench generate --runs 20 -o "bench/pair_head_speed/after_r$round.json" >/dev/null
done
