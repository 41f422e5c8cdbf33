"""Crease lines and corners from where the input's planar regions meet: the tables and the plot
of docs/experiments/2026-12-06-region-meet.md from the files beside this file (the validation
base run is the crease-points entry's, the same behaviour).
    python3 analyse.py [DIR]"""
import csv
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../../../bench"))
from paired import SURFACE_KEYS, arm_row, hard_surface_table, load_rows  # noqa: E402

here = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
base_dir = os.path.join(here, "../2026-12-06-crease-points")
# base: a1f91a4. meet: the snap (step 4) only, the regions of the 10 nearest points, planes
# within 1 spacing; meetw5: within 0.5; meetk24: 24 nearest. meetpl: placement (step 2) and
# snap, 10 nearest; meetplkK: K nearest; meetplk24w2: 24 nearest, within 2 spacings.
HS_ARMS = ["base", "meet", "meetw5", "meetk24", "meetpl", "meetplk16", "meetplk24", "meetplk24w2",
           "meetplk36", "meetplk48"]
VAL_ARMS = ["base", "meet", "meetplk24"]
rows = list(csv.DictReader(open(os.path.join(here, "hard_surface.csv"))))
ef1 = hard_surface_table(rows, HS_ARMS)

print("\nPer shape, base -> meetplk24: EF1 (mean of the 3 seeds) and faces (seed 0, 2, 3)")
print("| shape | input | EF1 base | EF1 meetplk24 | faces base | faces meetplk24 |")
print("|---|---|---:|---:|---|---|")
for inp in ["clean", "noise1"]:
    for shape in sorted({r["shape"] for r in rows}):
        cells = []
        for key in ["ef1", "faces"]:
            for arm in ["base", "meetplk24"]:
                rs = sorted((r for r in rows if r["arm"] == arm and r["input"] == inp and r["shape"] == shape),
                            key=lambda r: r["seed"])
                cells.append(f"{sum(float(r['ef1']) for r in rs) / len(rs):.2f}" if key == "ef1"
                             else ", ".join(r["faces"] for r in rs))
        print(f"| {shape} | {inp} | " + " | ".join(cells) + " |")

for prefix, label in [("val", "clean"), ("valn", "1% noise")]:
    base = load_rows(os.path.join(base_dir, f"{prefix}_base.per_mesh.csv"), SURFACE_KEYS)
    print(f"\n226 validation meshes, {label} (paired differences from base, mean ± s.e.)")
    print("| arm | CD x100 | NC | ECD x100 | EF1 | faces | holes | CD vs base | NC vs base | EF1 vs base | faces vs base | holes vs base |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for arm in VAL_ARMS:
        r = base if arm == "base" else load_rows(os.path.join(here, f"{prefix}_{arm}.per_mesh.csv"), SURFACE_KEYS)
        print(arm_row(arm, r, None if arm == "base" else base, ["cd", "nc", "ef1", "faces", "holes"]))

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    sys.exit(0)
fig, ax = plt.subplots(figsize=(7, 4))
for k, (inp, label) in enumerate([("clean", "clean"), ("noise1", "1% noise")]):
    xs = [i + (k - 0.5) * 0.35 for i in range(len(HS_ARMS))]
    means = [sum(ef1[(a, inp)]) / 3 for a in HS_ARMS]
    ax.bar(xs, means, width=0.35, label=label)
    for x, a in zip(xs, HS_ARMS):
        ax.plot([x] * 3, ef1[(a, inp)], "k.", ms=3)
ax.set_xticks(range(len(HS_ARMS)), HS_ARMS, rotation=40, ha="right", fontsize=8)
ax.set_ylabel("EF1, mean of 8 shapes (dots: seeds 0, 2, 3)")
ax.set_title("Hard-surface set: where planar regions meet")
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(os.path.join(here, "region_meet.png"), dpi=110)
