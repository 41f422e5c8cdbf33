"""Crease points joining the nearest planar region: the tables and the plot of
docs/experiments/2026-12-06-crease-points.md from the files beside this file.
    python3 analyse.py [DIR]"""
import csv
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../../../bench"))
from paired import SURFACE_KEYS, arm_row, load_rows, paired_rows  # noqa: E402

here = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
# base: 5fa9777's behaviour; ab1: one ring of joining, own confidence; ab2c5: two rings, and
# every region point's confidence at least 0.5; ab2: two rings; ab1d4: one ring within 0.4
# of the growing's distance limit; ab1two: one ring, only points with two or more regions
# among their neighbours (a crease between planes).
HS_ARMS = ["base", "ab1", "ab2", "ab2c5", "ab1d4", "ab1two"]
VAL_ARMS = ["base", "ab1", "ab2c5", "ab1two"]

print("Hard-surface set, means over its 8 shapes (seed 0 / 2 / 3, then their mean)")
print("| input | arm | CD x100 | NC | ECD x100 | EF1 | faces / gt |")
print("|---|---|---|---|---|---|---|")
rows = list(csv.DictReader(open(os.path.join(here, "hard_surface.csv"))))
for inp, label in [("clean", "clean"), ("noise1", "1% noise")]:
    for arm in HS_ARMS:
        cells = []
        for key in ["cd", "nc", "ecd", "ef1", "faces"]:
            per_seed = []
            for s in ("0", "2", "3"):
                rs = [r for r in rows if r["arm"] == arm and r["input"] == inp and r["seed"] == s]
                if not rs:
                    continue
                v = [float(r[key]) / (float(r["gt_faces"]) if key == "faces" else 1.0) for r in rs]
                per_seed.append(sum(v) / len(v))
            mean = sum(per_seed) / len(per_seed)
            fmt = "{:.2f}x" if key == "faces" else "{:.3f}"
            cells.append(" / ".join(fmt.format(v) for v in per_seed) + " (**" + fmt.format(mean) + "**)")
        print(f"| {label} | {arm} | " + " | ".join(cells) + " |")

points = {}
for prefix, label in [("val", "clean"), ("valn", "1% noise")]:
    base = load_rows(os.path.join(here, f"{prefix}_base.per_mesh.csv"), SURFACE_KEYS)
    print(f"\n226 validation meshes, {label} (paired differences from base, mean ± s.e.)")
    print("| arm | CD x100 | NC | ECD x100 | EF1 | faces | holes | CD vs base | NC vs base | EF1 vs base | faces vs base |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for arm in VAL_ARMS:
        path = os.path.join(here, f"{prefix}_{arm}.per_mesh.csv")
        if not os.path.exists(path):
            continue
        r = load_rows(path, SURFACE_KEYS)
        if arm != "base":
            points[(label, arm)] = (paired_rows(r, base, "nc"), paired_rows(r, base, "ef1"))
        print(arm_row(arm, r, None if arm == "base" else base, ["cd", "nc", "ef1", "faces"]))

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    sys.exit(0)
fig, ax = plt.subplots(figsize=(5.5, 4))
for (label, arm), ((nc, nc_se), (ef1, ef1_se)) in points.items():
    ax.errorbar(nc, ef1, xerr=nc_se, yerr=ef1_se, fmt="o" if label == "clean" else "s", capsize=3,
                label=f"{arm}, {label}")
ax.axhline(0, color="grey", lw=0.5)
ax.axvline(0, color="grey", lw=0.5)
ax.set_xlabel("NC vs base (paired mean ± s.e.)")
ax.set_ylabel("EF1 vs base (paired mean ± s.e.)")
ax.set_title("Validation split: crease points joining a region")
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(os.path.join(here, "crease_points.png"), dpi=110)
