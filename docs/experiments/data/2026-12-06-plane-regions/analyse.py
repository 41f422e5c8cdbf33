"""Planar regions of the input for sharpening's planes: the tables and the plot of
docs/experiments/2026-12-06-plane-regions.md from the files beside this file.
    python3 analyse.py [DIR]"""
import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../../../bench"))
from paired import SURFACE_KEYS, finish_paired_plot, load_rows, mean_cells, paired_cells, paired_rows  # noqa: E402

here = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
# Validation arms: each point's own plane (6c777f0), regions kept at RMS <= 1.5 or 1.2 times
# the noise, and at 1.5 for confident points only.
ARMS = ["own_planes", "rms1.5", "rms1.2", "confident_rms1.5"]
SETS = [("val", "clean"), ("valn", "1% noise")]


def ef1_cell(a, b):
    d, s = paired_rows(a, b, "ef1")
    return f"{d:+.4f} ± {s:.4f}", (d, s)


points = {}
for prefix, label in SETS:
    base = load_rows(os.path.join(here, f"{prefix}_own_planes.per_mesh.csv"), SURFACE_KEYS)
    print(f"\n226 validation meshes, {label}")
    print("| arm | CD x100 | NC | ECD x100 | EF1 | faces | holes | CD vs own | NC vs own | holes vs own | EF1 vs own |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for arm in ARMS:
        rows = load_rows(os.path.join(here, f"{prefix}_{arm}.per_mesh.csv"), SURFACE_KEYS)
        cells = ["", "", ""]
        ef1 = ""
        if arm != "own_planes":
            cells, _ = paired_cells(rows, base)
            ef1, point = ef1_cell(rows, base)
            nc = paired_rows(rows, base, "nc")
            points[(label, arm)] = (nc, point)
        print(f"| {arm} | " + " | ".join(mean_cells(rows) + cells + [ef1]) + " |")


def hs_means(path):
    """Means over the hard-surface set's shapes: CD, NC, ECD, EF1, faces per gt face."""
    d = json.load(open(path))
    ms = [m for m in d["per_mesh"] if m["ours"]]
    cols = [
        [m["ours"]["chamfer_x100"] for m in ms],
        [m["ours"]["normal_consistency"] for m in ms],
        [m["ours"]["sharp"]["edge_chamfer_x100"] for m in ms],
        [m["ours"]["sharp"]["edge_f_score"]["f_score"] for m in ms],
        [m["faces_made"] / m["ours"]["gt_topology"]["faces"] for m in ms],
    ]
    return [sum(c) / len(c) for c in cols]


print("\nHard-surface set, means over its 8 shapes (seed 0 / 2 / 3, then their mean)")
print("| input | arm | CD x100 | NC | ECD x100 | EF1 | faces / gt |")
print("|---|---|---|---|---|---|---|")
for prefix, label in [("hs", "clean"), ("hsn", "1% noise")]:
    for arm in ["own_planes", "rms1.2"]:
        runs = [hs_means(os.path.join(here, f"{prefix}_{arm}_s{s}.json")) for s in (0, 2, 3)]
        mean = [sum(r[i] for r in runs) / 3 for i in range(5)]
        fmt = ["{:.2f}", "{:.3f}", "{:.2f}", "{:.3f}", "{:.2f}x"]
        cells = [" / ".join(f.format(r[i]) for r in runs) + f" (**{f.format(mean[i])}**)"
                 for i, f in enumerate(fmt)]
        print(f"| {label} | {arm} | " + " | ".join(cells) + " |")

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    sys.exit(0)
fig, ax = plt.subplots(figsize=(6.5, 4.5))
for label, marker in [("clean", "o"), ("1% noise", "s")]:
    for arm in ARMS[1:]:
        (dn, sn), (de, se) = points[(label, arm)]
        ax.errorbar(dn, de, xerr=sn, yerr=se, fmt=marker, capsize=3)
        ax.annotate(f"{arm}, {label}", (dn, de), textcoords="offset points", xytext=(5, 5),
                    fontsize=7)
finish_paired_plot(fig, ax, "NC, paired change from each point's own plane (mean ± s.e.)",
                   "EF1, paired change (mean ± s.e.)",
                   "Validation split, 226 meshes: planar regions for sharpening's planes",
                   os.path.join(here, "plane_regions.png"))
