#!/usr/bin/env bash
# Fixed-budget DiT sweep (issue 15 item 2): every arm in bench/dit_sweep/configs/ trains on the
# shipped VAE's latents for the same budget of single-thread compute (BUDGET_S seconds of this
# machine, default 1200), one arm after another, into RUNS/<arm>/.
#   bash bench/dit_sweep/run_sweep.sh RUNS [ARM ...]
# Per arm:
#  1. a 40-step probe measures seconds per step on one thread, and the arm's cosine schedule
#     is sized to the budget (steps = 0.97 * BUDGET_S / s_per_step), so no arm is cut
#     mid-schedule. The budget is in probe seconds, not wall time, so that other work on
#     this (shared, 2-core) machine while the arms train does not tilt the comparison (the
#     probe itself needs a quiet machine: a probe.json already in RUNS/<arm>/ is kept, so one
#     measured earlier can be reused);
#  2. training stops at STAGES equal step fractions (`--stop-at-step`; the same command then
#     resumes exactly), and the EMA weights at each stop are kept as a snapshot;
#  3. every snapshot is evaluated by generation on the first EVAL_LIMIT validation meshes
#     (`meshflow eval generate --split val`, the default pipeline), giving validation CD
#     against training time beside the flow loss in metrics.jsonl.
#  4. the arm's records without its weights (probe, config, the validation rows of
#     metrics.jsonl, each snapshot's stage and evaluation summary) are copied into
#     KEEP/<arm>/ (default: docs/experiments/data/2026-11-25-dit-size-sweep/runs/, the logged
#     sweep's records, which are committed), so the curves outlive the machine.
# Then bench/dit_sweep/plot.py draws both against time from KEEP and writes sweep.png and the
# table sweep.md beside KEEP.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
RUNS="${1:?usage: run_sweep.sh RUNS [ARM ...]}"; shift
MESHFLOW="${MESHFLOW:-${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target}/release/meshflow}"
BUDGET_S="${BUDGET_S:-1200}"
STAGES="${STAGES:-4}"
EVAL_LIMIT="${EVAL_LIMIT:-64}"
VAE="${VAE:-$ROOT/weights}"
export RAYON_NUM_THREADS="${RAYON_NUM_THREADS:-1}"
ARMS=("$@")
if [[ ${#ARMS[@]} -eq 0 ]]; then
    for f in "$ROOT"/bench/dit_sweep/configs/*.json; do ARMS+=("$(basename "$f" .json)"); done
fi
mkdir -p "$RUNS"
for arm in "${ARMS[@]}"; do
    cfg="$ROOT/bench/dit_sweep/configs/$arm.json"
    run="$RUNS/$arm"
    mkdir -p "$run"
    if [[ ! -f "$run/probe.json" ]]; then
        echo "[sweep] $arm: probing the step time"
        rm -rf "$RUNS/probe_$arm"
        "$MESHFLOW" train dit --vae "$VAE" --out "$RUNS/probe_$arm" --config "$cfg" --steps 40 \
            > "$run/probe.log" 2>&1
        python3 - "$RUNS/probe_$arm/metrics.jsonl" "$BUDGET_S" "$cfg" "$run" <<'EOF'
import json, sys
metrics, budget, cfg, run = sys.argv[1], float(sys.argv[2]), sys.argv[3], sys.argv[4]
rows = [json.loads(l) for l in open(metrics) if '"elapsed_s"' in l]
t = {r["step"]: r["elapsed_s"] for r in rows}
s_per_step = (t[40] - t[10]) / 30
steps = int(0.97 * budget / s_per_step)
config = json.load(open(cfg))
config["steps"] = steps
json.dump(config, open(f"{run}/config.json", "w"), indent=2)
json.dump({"s_per_step": s_per_step, "steps": steps, "budget_s": budget}, open(f"{run}/probe.json", "w"))
print(f"  {s_per_step:.3f} s/step -> {steps} steps")
EOF
        rm -rf "$RUNS/probe_$arm"
    fi
    steps=$(python3 -c "import json; print(json.load(open('$run/probe.json'))['steps'])")
    for stage in $(seq 1 "$STAGES"); do
        snap="$run/snap_$stage"
        [[ -f "$snap/dit.safetensors" ]] && continue
        stop=$(( steps * stage / STAGES ))
        echo "[sweep] $arm: stage $stage of $STAGES (to step $stop of $steps)"
        "$MESHFLOW" train dit --vae "$VAE" --out "$run/train" --config "$run/config.json" \
            --stop-at-step "$stop" >> "$run/train.log" 2>&1
        mkdir -p "$snap.tmp"
        cp "$run/train/dit.safetensors" "$run/train/dit.json" "$run/train/dit.manifest.json" "$snap.tmp/"
        for f in "$VAE"/vae.json "$VAE"/vae.safetensors "$VAE"/vae.manifest.json; do
            ln -sf "$f" "$snap.tmp/"
        done
        python3 -c "import json; json.dump({'stage': $stage, 'step': $stop}, open('$snap.tmp/stage.json', 'w'))"
        mv "$snap.tmp" "$snap"
    done
done
# Generation on validation meshes for every snapshot (both threads: the training is over),
# and for the shipped DiT as the reference line.
if [[ ! -f "$RUNS/shipped_eval.json" ]]; then
    RAYON_NUM_THREADS=2 "$MESHFLOW" eval generate --split val --limit "$EVAL_LIMIT" \
        --weights "$ROOT/weights" -o "$RUNS/shipped_eval.json" > "$RUNS/shipped_eval.log" 2>&1
fi
for arm in "${ARMS[@]}"; do
    for snap in "$RUNS/$arm"/snap_*; do
        [[ -f "$snap/eval.json" ]] && continue
        echo "[sweep] $arm: evaluating $(basename "$snap")"
        RAYON_NUM_THREADS=2 "$MESHFLOW" eval generate --split val --limit "$EVAL_LIMIT" \
            --weights "$snap" -o "$snap/eval.json" > "$snap/eval.log" 2>&1
    done
done
KEEP="${KEEP:-$ROOT/docs/experiments/data/2026-11-25-dit-size-sweep/runs}"
for arm in "${ARMS[@]}"; do
    python3 - "$RUNS/$arm" "$KEEP/$arm" <<'EOF'
import json, pathlib, shutil, sys
run, keep = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
(keep / "train").mkdir(parents=True, exist_ok=True)
for f in ("probe.json", "config.json"):
    shutil.copy(run / f, keep / f)
rows = [l for l in (run / "train" / "metrics.jsonl").read_text().splitlines() if '"val_loss"' in l]
(keep / "train" / "metrics.jsonl").write_text("\n".join(rows) + "\n")
for snap in sorted(run.glob("snap_*")):
    if (snap / "eval.json").is_file():
        (keep / snap.name).mkdir(exist_ok=True)
        shutil.copy(snap / "stage.json", keep / snap.name / "stage.json")
        summary = {"all": json.loads((snap / "eval.json").read_text())["all"]}
        (keep / snap.name / "eval.json").write_text(json.dumps(summary, indent=1) + "\n")
EOF
done
if [[ -f "$RUNS/shipped_eval.json" ]]; then
    python3 -c "import json, sys; json.dump({'all': json.load(open(sys.argv[1]))['all']}, open(sys.argv[2], 'w'), indent=1)" \
        "$RUNS/shipped_eval.json" "$KEEP/shipped_eval.json"
fi
python3 "$ROOT/bench/dit_sweep/plot.py" "$KEEP" "$(dirname "$KEEP")/sweep.png" \
    --table "$(dirname "$KEEP")/sweep.md"
