"""The conditioning-augmentation sweep: two fine-tunes of the stage-1 DiT with the same
schedule and wall clock, one on its training positions (control), one with positions drawn as
inference draws them from degraded surfaces (weights/dit.augment.train.json). Validation flow
loss against wall time, with the training positions and with inference's:
`python3 bench/training/plot_dit_augment.py [DIR [PNG]]`, DIR holding the two arms' logs
(default: the experiment's data folder,
docs/experiments/data/2026-11-25-conditioning-augmentation/), PNG by default dit_augment.png
there."""
import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

ROOT = Path(__file__).resolve().parents[2]
DIR = (Path(sys.argv[1]) if len(sys.argv) > 1
       else ROOT / "docs" / "experiments" / "data" / "2026-11-25-conditioning-augmentation")
PNG = Path(sys.argv[2]) if len(sys.argv) > 2 else DIR / "dit_augment.png"


def curves(path):
    rows = [json.loads(l) for l in open(path)]
    # Validation lines carry no time: take the time of the step they follow.
    elapsed, out = 0.0, []
    for r in rows:
        if "elapsed_s" in r:
            elapsed = r["elapsed_s"]
        elif "val_loss" in r:
            out.append((elapsed / 60, r["val_loss"], r.get("val_loss_inference_positions")))
    return out


arms = {
    "control: training positions": DIR / "dit_augment_control.metrics.jsonl",
    "augmented: inference's positions, degraded": DIR / "dit_augment.metrics.jsonl",
}
fig, axes = plt.subplots(1, 2, figsize=(11, 3.8))
for label, path in arms.items():
    c = curves(path)
    for ax, k in zip(axes, [1, 2]):
        ax.plot([r[0] for r in c], [r[k] for r in c], marker="o", label=label)
axes[0].set_title("validation flow loss, the mesh's own vertex positions")
axes[1].set_title("validation flow loss, positions as inference draws them")
for ax in axes:
    ax.set_xlabel("wall time (min), both arms side by side, one thread each")
    ax.grid(alpha=0.3)
axes[1].legend(fontsize=8)
fig.tight_layout()
fig.savefig(PNG, dpi=110)
