"""Validation curves of the shipped VAE's two stages (whole VAE, then the decoder alone):
python3 bench/training/plot_vae_decoder.py -> bench/training/vae_decoder.png."""
import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

HERE = Path(__file__).parent


def validation(path):
    return [json.loads(l) for l in open(path) if '"edge_f1"' in l]


base = validation(HERE / "vae.metrics.jsonl")
decoder = validation(HERE / "vae_decoder.metrics.jsonl")
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
fig.savefig(HERE / "vae_decoder.png", dpi=110)
