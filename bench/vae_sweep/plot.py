#!/usr/bin/env python3
"""Plot a fixed-budget MeshVAE sweep: validation edge F1, position and normal error against
wall time, one line per arm, and print a Markdown table of each arm's last validation.

    python3 bench/vae_sweep/plot.py RUNS_DIR OUT.png [--table OUT.md]

RUNS_DIR holds one folder per arm with the `metrics.jsonl` that `meshflow train vae` writes.
A validation line is placed at the `elapsed_s` of the step line just before it. Needs
matplotlib.
"""

import argparse
import json
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_arm(path):
    """(steps, meshes, validation rows with elapsed seconds) of one metrics log."""
    elapsed, meshes, steps, rows = 0.0, 0, 0, []
    for line in path.read_text().splitlines():
        rec = json.loads(line)
        if "loss" in rec:
            elapsed = rec["elapsed_s"]
            steps = rec["step"]
        elif "edge_f1" in rec:
            rec["elapsed_s"] = elapsed
            rows.append(rec)
    return steps, rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("runs", type=pathlib.Path)
    ap.add_argument("out", type=pathlib.Path)
    ap.add_argument("--table", type=pathlib.Path)
    args = ap.parse_args()
    arms = sorted(p for p in args.runs.iterdir() if (p / "metrics.jsonl").is_file())
    panels = [
        ("edge_f1", "validation edge F1 (higher is better)"),
        ("val_position", "validation position MSE (lower)"),
        ("val_normal", "validation normal MSE (lower)"),
    ]
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.5))
    table = [
        "| arm | steps | edge P / R / F1 | position MSE | normal MSE | mask acc. |",
        "|---|---:|---|---:|---:|---:|",
    ]
    for arm in arms:
        steps, rows = read_arm(arm / "metrics.jsonl")
        if not rows:
            continue
        t = [r["elapsed_s"] / 60 for r in rows]
        for ax, (key, _) in zip(axes, panels):
            ax.plot(t, [r.get(key, float("nan")) for r in rows], marker="o", ms=3, label=arm.name)
        last = rows[-1]
        table.append(
            f"| {arm.name} | {steps} | {last['edge_precision']:.3f} / {last['edge_recall']:.3f} / "
            f"{last['edge_f1']:.3f} | {last['val_position']:.4f} | "
            f"{last.get('val_normal', float('nan')):.4f} | {last['mask_accuracy']:.4f} |"
        )
    for ax, (key, title) in zip(axes, panels):
        ax.set_title(title)
        ax.set_xlabel("wall time (min)")
        if key != "edge_f1":
            ax.set_yscale("log")
        ax.grid(alpha=0.3)
    axes[0].legend()
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    text = "\n".join(table) + "\n"
    print(text)
    if args.table:
        args.table.write_text(text)


if __name__ == "__main__":
    main()
