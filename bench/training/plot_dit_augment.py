"""The conditioning-augmentation sweep: two fine-tunes of the stage-1 DiT with the same
schedule and wall clock, one on its training positions (control), one with positions drawn as
inference draws them from degraded surfaces (weights/dit.augment.train.json). Validation flow
loss against wall time, with the training positions and with inference's:
python3 bench/training/plot_dit_augment.py -> bench/training/dit_augment.png."""
import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

HERE = Path(__file__).parent


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
    "control: training positions": HERE / "dit_augment_control.metrics.jsonl",
    "augmented: inference's positions, degraded": HERE / "dit_augment.metrics.jsonl",
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
fig.savefig(HERE / "dit_augment.png", dpi=110)
