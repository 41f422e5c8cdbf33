#!/usr/bin/env bash
# Side by side, one binary, arms alternated over two rounds: the shipped DiT recipe
# (weights/dit.train.json on the shipped VAE's latents) for 40 steps with the batch in one
# pass (--data-parallel 1) and in two sub-batches at once (2). Each run's metrics.jsonl goes to
# bench/dit_data_parallel/dpK_rR.metrics.jsonl; the summary (steps 10 -> 40, after warm-up) to
# bench/dit_data_parallel/summary.json. Run it on an otherwise idle machine.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
M="${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target}/release/meshflow"
OUT=bench/dit_data_parallel
RUN="$(mktemp -d)"
for round in 1 2; do
    for k in 1 2; do
        rm -rf "$RUN/dp$k"
        "$M" train dit -o "$RUN/dp$k" --steps 40 --data-parallel "$k" > /dev/null 2>&1
        cp "$RUN/dp$k/metrics.jsonl" "$OUT/dp${k}_r$round.metrics.jsonl"
    done
done
python3 - "$OUT" <<'PY'
import json, sys, glob, os
out = sys.argv[1]
rows = []
for f in sorted(glob.glob(f"{out}/dp*_r*.metrics.jsonl")):
    steps = {d["step"]: d for d in map(json.loads, open(f)) if "elapsed_s" in d}
    s_per_step = (steps[40]["elapsed_s"] - steps[10]["elapsed_s"]) / 30
    rows.append({"run": os.path.basename(f).split(".")[0], "s_per_step": s_per_step,
                 "examples_per_s": 16 / s_per_step, "loss_step_40": steps[40]["loss"]})
for r in rows:
    print(f'{r["run"]}: {r["s_per_step"]:.3f} s/step, {r["examples_per_s"]:.1f} examples/s, loss {r["loss_step_40"]:.4f}')
json.dump({"method": "meshflow train dit --steps 40 --data-parallel K, seconds per step from step 10 to 40 (elapsed_s in metrics.jsonl)", "runs": rows}, open(f"{out}/summary.json", "w"), indent=2)
PY
