"""Table and plot of docs/experiments/2026-12-07-seed-parts.md: two rules meant to tell a part
the model left out from a surface it put off the input, tried on `--complete-seed-gap 0.7`'s
clusters of missed points; the first 80 validation meshes (paired against no seeding and
against the shipped rule) and the hard-surface set at seeds 0 to 4.
    python3 analyse.py   (needs matplotlib)"""
import csv
import os
import sys

here = os.path.dirname(os.path.abspath(__file__))
clusters_dir = os.path.join(here, "..", "2026-12-07-seed-clusters")
sys.path.insert(0, os.path.join(here, "..", "..", "..", "..", "bench"))
from paired import (SURFACE_KEYS, arm_row, faces_per_gt, finish_paired_plot,  # noqa: E402
                    hard_surface_table, load_gt_faces, load_rows, paired_rows)

# arm: (the rule, where its per-mesh CSV is)
ARMS = {
    "base": ("no seeding (the default)", clusters_dir),
    "shipped": ("clusters of at least 1/32 of the input (35b0a2e's option)", clusters_dir),
    "air0.5": ("shipped, less clusters with over half their points nearest a face off the input", here),
    "air0.25": ("the same, over a quarter", here),
    "max0.25": ("shipped, less clusters of over 1/4 of the input", here),
    "max0.125": ("shipped, less clusters of over 1/8 of the input", here),
}
rows = {arm: load_rows(os.path.join(d, f"val80_{arm}.per_mesh.csv"), SURFACE_KEYS) for arm, (_, d) in ARMS.items()}
gt = load_gt_faces(os.path.join(clusters_dir, "val80_gt_faces.csv"))

keys = ["cd", "nc", "ef1", "holes", "faces"]
print("First 80 validation meshes (means; differences per mesh against no seeding, mean ± s.e.)")
print("| arm | rule | CD x100 | NC | ECD x100 | EF1 | faces | holes | CD vs base | NC vs base | EF1 vs base"
      " | holes vs base | faces vs base | faces / gt |")
print("|---|---|" + "---:|" * 12)
for arm, (rule, _) in ARMS.items():
    ratio = faces_per_gt(rows[arm], gt)
    line = arm_row(arm, rows[arm], None if arm == "base" else rows["base"], keys)[:-1] + f"| {ratio:.2f}x |"
    print(line.replace(f"| {arm} |", f"| {arm} | {rule} |", 1))

# The hard-surface set: no seeding and the shipped rule from the seed-clusters entry, the trial
# arms from here.
hs = [r for r in csv.DictReader(open(os.path.join(clusters_dir, "hard_surface.csv")))
      if r["arm"] in ("off", "clusters")]
hs += list(csv.DictReader(open(os.path.join(here, "hard_surface.csv"))))
print()
hard_surface_table(hs, ["off", "clusters", "air0.5", "max0.25", "max0.125"], seeds=tuple(str(s) for s in range(5)))
print()
print("Clean faces per shape, seeds 0 to 4")
print("| shape | gt | " + " | ".join(["off", "clusters", "max0.25", "max0.125"]) + " |")
print("|---|---:|" + "---|" * 4)
clean_faces = {}
for shape in sorted({r["shape"] for r in hs}):
    cells = []
    for arm in ["off", "clusters", "max0.25", "max0.125"]:
        f = [r["faces"] for r in hs if r["arm"] == arm and r["input"] == "clean" and r["shape"] == shape]
        cells.append(" ".join(f))
    g = next(r["gt_faces"] for r in hs if r["shape"] == shape)
    print(f"| {shape} | {g} | " + " | ".join(cells) + " |")
for arm in ["off", "clusters", "air0.5", "max0.25", "max0.125"]:
    rs = [r for r in hs if r["arm"] == arm and r["input"] == "clean"]
    clean_faces[arm] = sum(float(r["faces"]) / float(r["gt_faces"]) for r in rs) / len(rs)

# One plot: what each rule keeps of the validation gain against what it costs on the clean
# hard-surface set.
import matplotlib  # noqa: E402
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

fig, ax = plt.subplots(figsize=(6.4, 4.4))
for arm in ["base", "shipped", "air0.5", "max0.25", "max0.125"]:
    cd = 0.0 if arm == "base" else paired_rows(rows[arm], rows["base"], "cd")[0]
    x = clean_faces["off" if arm == "base" else "clusters" if arm == "shipped" else arm]
    ax.scatter([x], [cd])
    ax.annotate(arm, (x, cd), textcoords="offset points", xytext=(5, 4))
finish_paired_plot(fig, ax, "clean hard-surface set: faces per ground-truth face (seeds 0-4)",
                   "80 validation meshes: CD x100 against no seeding", "Seeding rules: validation gain against"
                   " hard-surface faces", os.path.join(here, "seed_parts.png"), x_zero=False)
