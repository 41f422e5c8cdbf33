#!/usr/bin/env python3
"""Plot a fixed-budget DiT sweep (bench/dit_sweep/run_sweep.sh): validation flow loss (with
the training's token positions and with inference's) and validation CD of generation
against training time, one line per arm, and write a Markdown table.

    python3 bench/dit_sweep/plot.py RUNS_DIR OUT.png [--table OUT.md]

RUNS_DIR holds one folder per arm: probe.json (seconds per step on one thread),
train/metrics.jsonl, and snap_K/{stage.json,eval.json}; RUNS_DIR/shipped_eval.json, when
present, is the shipped DiT on the same validation meshes (a dashed line). Time is steps x
the probe's seconds per step: the compute each arm had, whatever else ran beside it.
Needs matplotlib.
"""

import argparse
import json
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_arm(arm):
    """The arm's seconds per step, validation rows and evaluated snapshots."""
    probe = json.loads((arm / "probe.json").read_text())
    rows = [
        json.loads(line)
        for line in (arm / "train" / "metrics.jsonl").read_text().splitlines()
        if '"val_loss"' in line
    ]
    snaps = []
    for snap in sorted(arm.glob("snap_*")):
        if (snap / "eval.json").is_file():
            stage = json.loads((snap / "stage.json").read_text())
            ours = json.loads((snap / "eval.json").read_text())["all"]["ours"]
            snaps.append((stage["step"], ours))
    config = json.loads((arm / "config.json").read_text())
    return probe["s_per_step"], config, rows, sorted(snaps, key=lambda s: s[0])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("runs", type=pathlib.Path)
    ap.add_argument("out", type=pathlib.Path)
    ap.add_argument("--table", type=pathlib.Path)
    args = ap.parse_args()
    arms = sorted(p for p in args.runs.iterdir() if (p / "probe.json").is_file())
    shipped_file = args.runs / "shipped_eval.json"
    shipped = json.loads(shipped_file.read_text())["all"]["ours"] if shipped_file.is_file() else None
    fig, axes = plt.subplots(1, 3, figsize=(17, 4.6))
    table = [
        "| arm | width x depth | s/step (1 thread) | steps | val flow loss | "
        "with inference's positions | val CD x100 | holes |",
        "|---|---|---:|---:|---:|---:|---:|---:|",
    ]
    for arm in arms:
        s_per_step, config, rows, snaps = read_arm(arm)
        name = arm.name
        minutes = lambda step: step * s_per_step / 60  # noqa: E731
        line = axes[0].plot([minutes(r["step"]) for r in rows], [r["val_loss"] for r in rows],
                            label=name)[0]
        axes[1].plot([minutes(r["step"]) for r in rows],
                     [r.get("val_loss_inference_positions", float("nan")) for r in rows],
                     color=line.get_color(), label=name)
        axes[2].plot([minutes(s) for s, _ in snaps], [o["chamfer_x100"] for _, o in snaps],
                     "o-", color=line.get_color(), label=name)
        last = rows[-1] if rows else {}
        end = snaps[-1][1] if snaps else {}
        model = config["model"]
        table.append(
            f"| {name} | {model['width']} x {model['depth']} | {s_per_step:.3f} | "
            f"{config['steps']} | {last.get('val_loss', float('nan')):.3f} | "
            f"{last.get('val_loss_inference_positions', float('nan')):.3f} | "
            f"{end.get('chamfer_x100', float('nan')):.3f} | {end.get('holes', float('nan')):.2f} |"
        )
    if shipped is not None:
        axes[2].axhline(shipped["chamfer_x100"], color="k", linestyle="--",
                        label="shipped DiT (10,000 steps, 2 threads)")
        table.append(f"| shipped (reference) | 192 x 6 | | 10000 | | | "
                     f"{shipped['chamfer_x100']:.3f} | {shipped['holes']:.2f} |")
    titles = [
        "validation flow loss (training's token positions)",
        "validation flow loss (inference's token positions)",
        "validation CD x100 of generated meshes (64 meshes)",
    ]
    for ax, title in zip(axes, titles):
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("training time, minutes of one thread")
        ax.grid(alpha=0.3)
    axes[2].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    text = "\n".join(table) + "\n"
    print(text)
    if args.table:
        args.table.write_text(text)


if __name__ == "__main__":
    main()
