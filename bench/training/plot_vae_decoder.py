"""Validation curves of the VAE's first two stages as shipped at 5b5ff14 (whole VAE, then the
decoder alone): `python3 bench/training/plot_vae_decoder.py [BASE DECODER [PNG]]`. BASE and
DECODER are the two stages' metrics.jsonl (default: vae.metrics.jsonl in
docs/experiments/data/2026-11-24-vae-stage-1/ and vae_decoder.metrics.jsonl in
docs/experiments/data/2026-11-25-vae-decoder-stage/); PNG by default vae_decoder.png beside
DECODER."""
import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

DATA = Path(__file__).resolve().parents[2] / "docs" / "experiments" / "data"
BASE = Path(sys.argv[1]) if len(sys.argv) > 2 else DATA / "2026-11-24-vae-stage-1" / "vae.metrics.jsonl"
DECODER = (Path(sys.argv[2]) if len(sys.argv) > 2
           else DATA / "2026-11-25-vae-decoder-stage" / "vae_decoder.metrics.jsonl")
PNG = Path(sys.argv[3]) if len(sys.argv) > 3 else DECODER.with_name("vae_decoder.png")


def validation(path):
    return [json.loads(l) for l in open(path) if '"edge_f1"' in l]


base = validation(BASE)
decoder = validation(DECODER)
offset = base[-1]["step"]
fig, axes = plt.subplots(1, 3, figsize=(13, 3.6))
for ax, key, label in zip(axes, ["edge_f1", "val_position", "val_normal"],
                          ["edge F1", "position MSE", "normal MSE"]):
    ax.plot([r["step"] for r in base], [r[key] for r in base], label="stage 1: whole VAE (10,000 steps)")
    ax.plot([offset + r["step"] for r in decoder], [r[key] for r in decoder],
            label="stage 2: decoder alone (14,000 steps)")
    ax.set_xlabel("step (stage 2 counted after stage 1)")
    ax.set_title(f"validation {label} (64 meshes)")
    if key != "edge_f1":
        ax.set_yscale("log")
    ax.grid(alpha=0.3)
axes[0].legend(fontsize=8)
fig.tight_layout()
fig.savefig(PNG, dpi=110)
