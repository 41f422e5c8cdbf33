"""The candidate choice's hole weight: the table and the plot of
docs/experiments/2026-12-06-hole-weight.md from the per-mesh CSVs beside this file.
    python3 analyse.py [DIR]"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../../../bench"))
from paired import SURFACE_KEYS, finish_paired_plot, load_rows, mean_cells, paired_cells  # noqa: E402

here = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
# Arm name and the weight each hole adds to a candidate's distance to the input.
ARMS = [("w0.5", 0.5), ("w1", 1), ("w2", 2), ("w4", 4), ("holes_first", 1e6)]


def load(arm):
    return load_rows(os.path.join(here, f"val_{arm}.per_mesh.csv"), SURFACE_KEYS)


base = load("w0.5")
print("| arm | CD x100 | NC | ECD x100 | EF1 | faces | holes | meshes with holes | CD vs 0.5 | NC vs 0.5 | holes vs 0.5 |")
print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
points = []
for arm, w in ARMS:
    rows = load(arm)
    with_holes = sum(1 for r in rows.values() if r["holes"])
    cells, point = paired_cells(rows, base)
    line = f"| {arm} | " + " | ".join(mean_cells(rows) + [str(with_holes)] + cells) + " |"
    points.append((arm, *point))
    print(line)

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    sys.exit(0)
fig, ax = plt.subplots(figsize=(6, 4.5))
ax.errorbar([p[1] for p in points], [p[3] for p in points], xerr=[p[2] for p in points],
            yerr=[p[4] for p in points], fmt="o-", capsize=3)
for arm, dh, _, dc, _ in points:
    ax.annotate(arm, (dh, dc), textcoords="offset points", xytext=(5, 5), fontsize=8)
finish_paired_plot(fig, ax, "holes a mesh, paired change from the shipped weight 0.5 (mean ± s.e.)",
                   "CD x100, paired change (mean ± s.e.)",
                   "Validation split, 226 meshes: the hole weight of the candidate choice",
                   os.path.join(here, "hole_weight.png"))
