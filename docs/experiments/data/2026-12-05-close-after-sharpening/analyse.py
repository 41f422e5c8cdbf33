"""Closing holes after sharpening: the table and the plot of
docs/experiments/2026-12-05-close-after-sharpening.md from the per-mesh CSVs beside this file.
    python3 analyse.py [DIR]"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../../../bench"))
from paired import SURFACE_KEYS, finish_paired_plot, load_rows, mean_cells, paired_cells  # noqa: E402

here = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
ARMS = {
    "val": ["base", "cut10", "cut5", "cut3", "guard10", "guard5", "nocut10", "nocut5"],
    "hs": ["base", "cut10", "nocut10", "nocut5"],
    "hsn": ["base", "cut10", "nocut10", "nocut5"],
}


def load(split, arm):
    return load_rows(os.path.join(here, f"{split}_{arm}.per_mesh.csv"), SURFACE_KEYS)


points = []
for split, arms in ARMS.items():
    base = load(split, "base")
    print(f"\n{split}: arm | " + " | ".join(SURFACE_KEYS) + " | changed meshes | CD vs base | NC vs base | holes vs base")
    for arm in arms:
        rows = load(split, arm)
        changed = sum(1 for n in rows if rows[n]["faces"] != base[n]["faces"] or rows[n]["cd"] != base[n]["cd"])
        line = f"| {arm} | " + " | ".join(mean_cells(rows)) + f" | {changed} |"
        if arm != "base" and split == "val":
            cells, point = paired_cells(rows, base)
            line += " " + " | ".join(cells) + " |"
            points.append((arm, *point))
        print(line)

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    sys.exit(0)
fig, ax = plt.subplots(figsize=(6, 4.5))
for i, (arm, dh, sh, dc, sc) in enumerate(points):
    ax.errorbar(dh, dc, xerr=sh, yerr=sc, fmt="o", capsize=3)
    # Staggered labels: the arms near zero CD lie close together.
    ax.annotate(arm, (dh, dc), textcoords="offset points", xytext=(4, 6 + 12 * (i % 3)), fontsize=8)
finish_paired_plot(fig, ax, "holes a mesh, paired change from 79d5737 (mean ± s.e.)",
                   "CD x100, paired change (mean ± s.e.)",
                   "Validation split, 226 meshes: closing after sharpening", os.path.join(here, "close_after.png"))
