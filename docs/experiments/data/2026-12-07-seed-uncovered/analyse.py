"""Tables and plot of docs/experiments/2026-12-07-seed-uncovered.md: the seeding arms on the
first 80 validation meshes (paired against base, with faces per ground-truth face), and the
hard-surface set at seed 0 without and with seeding.
    python3 analyse.py   (needs matplotlib)"""
import csv
import os
import sys

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, "..", "..", "..", "..", "bench"))
from paired import (SURFACE_KEYS, arm_row, diff_cells, faces_per_gt, finish_paired_plot,  # noqa: E402
                    load_gt_faces, load_rows, mean_of, paired_rows)

ARMS = ["base", "s07", "s10", "s07p2", "s10p2", "s07p4", "s07p2k", "sp2", "shipped_option"]
rows = {arm: load_rows(os.path.join(here, f"val80_{arm}.per_mesh.csv"), SURFACE_KEYS) for arm in ARMS}
gt = load_gt_faces(os.path.join(here, "val80_gt_faces.csv"))

# 1. The arms: means over the 80 meshes, per-mesh differences from base, and our faces per
# ground-truth face (the mean of the meshes' ratios, as BENCHMARKS.md gives it).
keys = ["cd", "nc", "ef1", "holes", "faces"]
print("| arm | CD x100 | NC | ECD x100 | EF1 | faces | holes | CD vs base | NC vs base | EF1 vs base | holes vs base"
      " | faces vs base | faces / gt |")
print("|---|" + "---:|" * 12)
for arm in ARMS:
    ratio = faces_per_gt(rows[arm], gt)
    print(arm_row(arm, rows[arm], None if arm == "base" else rows["base"], keys)[:-1] + f"| {ratio:.2f}x |")

# 2. The hard-surface set at seed 0, means over its 8 shapes, then per shape.
hs = list(csv.DictReader(open(os.path.join(here, "hard_surface.csv"))))
print()
print("| input | seed gap | CD x100 | NC | EF1 | faces / gt | holes |")
print("|---|---:|---:|---:|---:|---:|---:|")
for inp in ["clean", "noise1"]:
    for gap in ["0", "0.7"]:
        rs = [r for r in hs if r["input"] == inp and r["seed_gap"] == gap]
        mean = lambda k: sum(float(r[k]) for r in rs) / len(rs)  # noqa: E731
        ratio = sum(float(r["faces"]) / float(r["gt_faces"]) for r in rs) / len(rs)
        print(f"| {inp} | {gap} | {mean('cd'):.3f} | {mean('nc'):.3f} | {mean('ef1'):.3f} | {ratio:.2f}x | {mean('holes'):.2f} |")
print()
print("| input | shape | CD x100 (0 -> 0.7) | NC | EF1 | faces | holes |")
print("|---|---|---|---|---|---|---|")
for inp in ["clean", "noise1"]:
    for shape in dict.fromkeys(r["shape"] for r in hs):
        a, b = ([r for r in hs if r["input"] == inp and r["seed_gap"] == g and r["shape"] == shape][0]
                for g in ["0", "0.7"])
        cells = [f"{float(a[k]):.{d}f} -> {float(b[k]):.{d}f}" for k, d in [("cd", 2), ("nc", 3), ("ef1", 2)]]
        cells += [f"{a['faces']} -> {b['faces']} (gt {a['gt_faces']})", f"{a['holes']} -> {b['holes']}"]
        print(f"| {inp} | {shape} | " + " | ".join(cells) + " |")

# The plot: the paired change in CD against the change in faces per arm (mean ± s.e.).
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

fig, ax = plt.subplots(figsize=(6, 4.2))
for arm in ARMS[1:]:
    (df, sf), (dc, sc) = (paired_rows(rows[arm], rows["base"], k) for k in ("faces", "cd"))
    ax.errorbar(df, dc, xerr=sf, yerr=sc, fmt="o", capsize=3, label=arm)
ax.legend(fontsize=8)
finish_paired_plot(fig, ax, "faces a mesh, change from base", "CD x100, change from base",
                   "Seeding the uncovered input, 80 validation meshes", os.path.join(here, "seed_uncovered.png"))

# 3. The test split with the option (`meshflow eval generate --split test --complete-seed-gap
# 0.7`, per mesh in test_option.per_mesh.csv), paired against the shipped run without it
# (bench/sharpen_eval/test_sharpened.json as 39c4eb4 wrote it, read from git); ECD over the
# meshes with sharp edges in both.
from paired import json_at  # noqa: E402

names = {"cd_x100": "cd", "nc": "nc", "ecd_x100": "ecd", "ef1": "ef1", "faces": "faces", "holes": "holes"}
shipped = {m["name"]: {names[k]: m[k] for k in names}
           for m in json_at("39c4eb4", "bench/sharpen_eval/test_sharpened.json")["per_mesh"]}
option = load_rows(os.path.join(here, "test_option.per_mesh.csv"), SURFACE_KEYS)
print()
print("| test split (244) | CD x100 | NC | ECD x100 | EF1 | faces | holes |")
print("|---|---:|---:|---:|---:|---:|---:|")
print("| shipped | " + " | ".join(f"{mean_of(shipped, k):.4g}" for k in SURFACE_KEYS) + " |")
print("| --complete-seed-gap 0.7 | " + " | ".join(f"{mean_of(option, k):.4g}" for k in SURFACE_KEYS) + " |")
print("| paired difference | " + " | ".join(diff_cells(option, shipped, SURFACE_KEYS)) + " |")
