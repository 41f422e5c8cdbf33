"""The reach arms of docs/experiments/2026-12-04-sharpen-reach.md: one row of panels a measure,
the hard-surface set on the left and the validation split on the right. `python3 plot.py`."""
import json
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

arms = json.load(open("arms.json"))
measures = [("cd_x100", "CD x100 (lower is better)"), ("nc", "NC"), ("ecd_x100", "ECD x100 (lower is better)"),
            ("ef1", "EF1"), ("faces_over_gt", "faces / ground truth")]
fig, axes = plt.subplots(len(measures), 2, figsize=(12, 14))
for col, split in enumerate(["hard_surface", "val"]):
    names = list(arms[split])
    for row, (key, title) in enumerate(measures):
        ax = axes[row][col]
        values = [arms[split][n][key] for n in names]
        colours = ["tab:green" if "shipped" in arms[split][n]["label"] else
                   "tab:grey" if "no reach (" in arms[split][n]["label"] else "tab:blue" for n in names]
        ax.bar(names, values, color=colours)
        lo = min(values)
        ax.set_ylim(lo - 0.15 * (max(values) - lo) - 1e-9, max(values) + 0.1 * (max(values) - lo) + 1e-9)
        ax.set_title(f"{'hard-surface set (8 shapes)' if split == 'hard_surface' else 'validation split (226 meshes)'}: {title}", fontsize=9)
        ax.tick_params(axis="x", labelsize=8)
fig.tight_layout()
fig.savefig("sharpen_reach.png", dpi=80)
