"""Crease points joining a planar region again, after the regions' meeting shipped: the tables
and the plot of the section "Again at 44192db" of docs/experiments/2026-12-06-crease-points.md
from the files beside this file.
    python3 analyse.py [DIR]"""
import csv
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../../../../bench"))
from paired import (SURFACE_KEYS, arm_row, compact_changes, finish_paired_plot, hard_surface_table,  # noqa: E402
                    load_rows, paired_rows)

here = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
# base: 44192db. fringe: every point left out of a region joins the nearest region plane among
# its neighbours' within the growth's distance limit (the entry's ab1). fringe2: only points
# with two regions among their neighbours (ab1two). meetonly: fringe, but the joined points
# keep their own planes (the fringe seen by the meeting of regions only). explained: only
# points all of whose neighbours lie within the limit of one of their regions' planes. gated:
# explained, only where the regions' member-weighted median RMS off their planes is over 0.35
# point spacings (a noisy input).
HS_ARMS = ["base", "fringe", "fringe2", "meetonly", "explained", "gated"]
VAL_ARMS = ["base", "fringe", "fringe2", "explained", "gated"]
rows = list(csv.DictReader(open(os.path.join(here, "hard_surface.csv"))))
ef1 = hard_surface_table(rows, HS_ARMS)

print("\nPer shape with 1% noise: EF1 (mean of the 3 seeds) and faces (seeds 0, 2, 3)")
print("| shape | EF1 base | EF1 fringe | EF1 gated | faces base | faces fringe | faces gated |")
print("|---|---:|---:|---:|---|---|---|")
for shape in sorted({r["shape"] for r in rows}):
    cells = []
    for key in ["ef1", "faces"]:
        for arm in ["base", "fringe", "gated"]:
            rs = sorted((r for r in rows if r["arm"] == arm and r["input"] == "noise1" and r["shape"] == shape),
                        key=lambda r: r["seed"])
            cells.append(f"{sum(float(r['ef1']) for r in rs) / len(rs):.2f}" if key == "ef1"
                         else ", ".join(r["faces"] for r in rs))
    print(f"| {shape} | " + " | ".join(cells) + " |")

diffs = {}
for prefix, label in [("val", "clean"), ("valn", "1% noise")]:
    base = load_rows(os.path.join(here, f"{prefix}_base.per_mesh.csv"), SURFACE_KEYS)
    print(f"\n226 validation meshes, {label} (paired differences from base, mean ± s.e.)")
    print("| arm | CD x100 | NC | ECD x100 | EF1 | faces | holes | CD vs base | NC vs base | EF1 vs base "
          "| faces vs base | holes vs base |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for arm in VAL_ARMS:
        r = base if arm == "base" else load_rows(os.path.join(here, f"{prefix}_{arm}.per_mesh.csv"), SURFACE_KEYS)
        print(arm_row(arm, r, None if arm == "base" else base, ["cd", "nc", "ef1", "faces", "holes"]))
        if arm != "base":
            diffs[(prefix, arm)] = paired_rows(r, base, "ef1")

# The test split clean, with 1% noise and with 30% missing: gated (this folder's
# test*_gated_sharpened.json) against the shipped build's runs at 0c04384 (read from git), per
# mesh; both compacted by bench/sharpen_eval/compact.py.
root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../../../..")
for prefix, label in [("test", "clean"), ("test_noise1", "1% noise"), ("test_missing30", "30% missing")]:
    shipped_json = subprocess.run(["git", "-C", root, "show", f"0c04384:bench/sharpen_eval/{prefix}_sharpened.json"],
                                  capture_output=True, text=True, check=True).stdout
    shipped = {m["name"]: m for m in json.loads(shipped_json)["per_mesh"]}
    gated = {m["name"]: m for m in json.load(open(os.path.join(here, f"{prefix}_gated_sharpened.json")))["per_mesh"]}
    compact_changes(shipped, gated, f"Test split, {label}: gated against the shipped build")

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    sys.exit(0)
fig, ax = plt.subplots(figsize=(7, 4))
points = [([ef1[(a, inp)] for a in HS_ARMS[1:]], sum(ef1[("base", inp)]) / 3) for inp in ["clean", "noise1"]]
x = 0
for arms_seeds, base_mean in points:
    for k, per_seed in enumerate(arms_seeds):
        ax.bar(x + k * 0.16, sum(per_seed) / 3 - base_mean, width=0.16, color=f"C{k}",
               label=HS_ARMS[1 + k] if x == 0 else None)
        ax.plot([x + k * 0.16] * 3, [s - base_mean for s in per_seed], "k.", ms=3)
    x += 1
for prefix, label in [("val", "clean"), ("valn", "1% noise")]:
    for arm in VAL_ARMS[1:]:
        mean, se = diffs[(prefix, arm)]
        k = HS_ARMS.index(arm) - 1
        ax.bar(x + k * 0.16, mean, width=0.16, color=f"C{k}", yerr=se, capsize=3)
    x += 1
ax.set_xticks([i + 0.3 for i in range(4)], ["clean\nhard-surface", "1% noise\nhard-surface",
                                              "clean\nvalidation", "1% noise\nvalidation"], fontsize=8)
ax.legend(fontsize=8)
finish_paired_plot(fig, ax, None, "EF1 against base (dots: seeds; bars: ± s.e.)",
                   "Crease points joining a region at 44192db: EF1 against base",
                   os.path.join(here, "after_region_meet.png"), x_zero=False)
