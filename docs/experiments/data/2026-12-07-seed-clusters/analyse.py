"""Tables and plot of docs/experiments/2026-12-07-seed-clusters.md: seeding only the clusters of
missed input points that are large enough, on the first 80 validation meshes (paired against
no seeding), the hard-surface set at seeds 0 to 4, and the test split.
    python3 analyse.py   (needs matplotlib)"""
import csv
import json
import os
import sys

here = os.path.dirname(os.path.abspath(__file__))
bench = os.path.join(here, "..", "..", "..", "..", "bench")
sys.path.insert(0, bench)
from paired import (SURFACE_KEYS, arm_row, diff_cells, faces_per_gt, finish_paired_plot,  # noqa: E402
                    hard_surface_table, json_at, load_gt_faces, load_rows, mean_of, mean_se, paired_rows)

# arm: (the rule, the per-mesh CSV's name)
ARMS = {
    "base": "no seeding (4e964b6's default)",
    "all": "every cluster (4e964b6's --complete-seed-gap 0.7)",
    "c8": "at least 8 points", "c24": "at least 24 points", "c64": "at least 64 points",
    "c128": "at least 128 points (1/32)", "c256": "at least 256 points (1/16)",
    "k3": "at least 3 seeds", "k5": "at least 5 seeds", "k8": "at least 8 seeds",
    "shipped": "at least 1/32 of the input, linked within the gap (shipped)",
    "guard": "shipped, and dropped where it covers less",
    "drop_over": "shipped, less the faces off the input within 2 median edges of a seed",
}
rows = {arm: load_rows(os.path.join(here, f"val80_{arm}.per_mesh.csv"), SURFACE_KEYS) for arm in ARMS}
gt = load_gt_faces(os.path.join(here, "val80_gt_faces.csv"))

# 1. The arms: means over the 80 meshes, per-mesh differences from base, faces per ground-truth
# face (the mean of the meshes' ratios).
keys = ["cd", "nc", "ef1", "holes", "faces"]
print("| arm | rule | CD x100 | NC | ECD x100 | EF1 | faces | holes | CD vs base | NC vs base | EF1 vs base"
      " | holes vs base | faces vs base | faces / gt |")
print("|---|---|" + "---:|" * 12)
for arm, rule in ARMS.items():
    ratio = faces_per_gt(rows[arm], gt)
    line = arm_row(arm, rows[arm], None if arm == "base" else rows["base"], keys)[:-1] + f"| {ratio:.2f}x |"
    print(line.replace(f"| {arm} |", f"| {arm} | {rule} |", 1))

# 2. The hard-surface set, seeds 0 to 4: no seeding, every cluster, the shipped rule; then the
# holes and the paired differences from no seeding (by shape and seed, mean ± s.e.).
hs = list(csv.DictReader(open(os.path.join(here, "hard_surface.csv"))))
print()
hard_surface_table(hs, ["off", "all", "clusters"], seeds=tuple(str(s) for s in range(5)))
print()
print("| input | arm | holes | CD vs off | EF1 vs off | holes vs off |")
print("|---|---|---:|---:|---:|---:|")
for inp in ["clean", "noise1"]:
    off = {(r["seed"], r["shape"]): r for r in hs if r["arm"] == "off" and r["input"] == inp}
    for arm in ["off", "all", "clusters"]:
        rs = [r for r in hs if r["arm"] == arm and r["input"] == inp]
        holes = sum(float(r["holes"]) for r in rs) / len(rs)
        diffs = [] if arm == "off" else [
            "{:+.3f} ± {:.3f}".format(*mean_se([float(r[k]) - float(off[(r["seed"], r["shape"])][k]) for r in rs]))
            for k in ["cd", "ef1", "holes"]]
        print(f"| {inp} | {arm} | {holes:.2f} | " + " | ".join(diffs or ["", "", ""]) + " |")

# The drop-over arm, clean only, against the shipped rule (paired by shape and seed).
shipped_clean = {(r["seed"], r["shape"]): r for r in hs if r["arm"] == "clusters" and r["input"] == "clean"}
drop = [r for r in hs if r["arm"] == "drop_over"]
print()
print("| clean | arm | CD x100 | NC | EF1 | faces / gt | holes |")
print("|---|---|---:|---:|---:|---:|---:|")
for arm, rs in [("clusters", list(shipped_clean.values())), ("drop_over", drop)]:
    m = {k: sum(float(r[k]) for r in rs) / len(rs) for k in ["cd", "nc", "ef1", "holes"]}
    ratio = sum(float(r["faces"]) / float(r["gt_faces"]) for r in rs) / len(rs)
    print(f"| clean | {arm} | {m['cd']:.3f} | {m['nc']:.3f} | {m['ef1']:.3f} | {ratio:.2f}x | {m['holes']:.2f} |")

# 3. The test split: the shipped rule, paired against the shipped pipeline without seeding
# (bench/sharpen_eval/test_sharpened.json as 39c4eb4 wrote it, read from git) and against
# every cluster seeded (docs/experiments/data/2026-12-07-seed-uncovered/test_option.per_mesh.csv).
names = {"cd_x100": "cd", "nc": "nc", "ecd_x100": "ecd", "ef1": "ef1", "faces": "faces", "holes": "holes"}
off = {m["name"]: {names[k]: m[k] for k in names}
       for m in json_at("39c4eb4", "bench/sharpen_eval/test_sharpened.json")["per_mesh"]}
every = load_rows(os.path.join(here, "..", "2026-12-07-seed-uncovered", "test_option.per_mesh.csv"), SURFACE_KEYS)
clusters = load_rows(os.path.join(here, "test_clusters.per_mesh.csv"), SURFACE_KEYS)
print()
print("| test split (244) | CD x100 | NC | ECD x100 | EF1 | faces | holes |")
print("|---|---:|---:|---:|---:|---:|---:|")
for label, r in [("no seeding", off), ("every cluster", every), ("clusters of 1/32 (shipped option)", clusters)]:
    print(f"| {label} | " + " | ".join(f"{mean_of(r, k):.4g}" for k in SURFACE_KEYS) + " |")
print("| 1/32 minus no seeding | " + " | ".join(diff_cells(clusters, off, SURFACE_KEYS)) + " |")
print("| 1/32 minus every cluster | " + " | ".join(diff_cells(clusters, every, SURFACE_KEYS)) + " |")

# The plot: paired change in CD against the change in holes, per arm (mean ± s.e.), the two
# families of rules joined in order.
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

fig, ax = plt.subplots(figsize=(6.4, 4.4))
for family, arms, style in [("points", ["all", "c8", "c24", "c64", "c128", "c256"], "o-"),
                            ("seeds", ["all", "k3", "k5", "k8"], "s--")]:
    pts = [(paired_rows(rows[a], rows["base"], "holes"), paired_rows(rows[a], rows["base"], "cd")) for a in arms]
    ax.plot([h for (h, _), _ in pts], [c for _, (c, _) in pts], style, label=f"fewest {family} a cluster")
    for a, ((h, _), (c, _)) in zip(arms, pts):
        ax.annotate(a, (h, c), fontsize=7, xytext=(3, 3), textcoords="offset points")
for a, m in [("shipped", "*"), ("guard", "x")]:
    (h, sh), (c, sc) = paired_rows(rows[a], rows["base"], "holes"), paired_rows(rows[a], rows["base"], "cd")
    ax.errorbar(h, c, xerr=sh, yerr=sc, fmt=m, capsize=3, label=a, ms=9)
ax.legend(fontsize=8)
finish_paired_plot(fig, ax, "holes a mesh, change from no seeding", "CD x100, change from no seeding",
                   "Seeding only large clusters of missed points, 80 validation meshes",
                   os.path.join(here, "seed_clusters.png"))
