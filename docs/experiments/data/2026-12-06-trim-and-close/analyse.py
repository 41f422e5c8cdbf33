"""Why holes stay open after closing, and what trimming a crumpled rim before closing buys: the
tables and the plot of docs/experiments/2026-12-06-trim-and-close.md from the files beside this
file.
    python3 analyse.py [DIR]"""
import collections
import csv
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../../../bench"))
from paired import SURFACE_KEYS, arm_row, finish_paired_plot, load_rows, paired_rows  # noqa: E402

here = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
# base: 254c467. local: the triangulation tried again with each face facing the rim faces at
# its corners instead of the loop's Newell normal. trimR: a loop that stays open has the faces
# touching it removed (R rings at most) and the larger loop closed, within max_gap; gapG: the
# trimmed loop's patch within G spacings of the input; areaA: and at least A times the area cut.
ARMS = ["base", "local", "trim1", "trim3", "trim1gap2", "trim2gap2", "trim1gap10area05", "trim1gap4area03"]


def reason(fan, tri):
    """A loop's failure in words: the fan's first fault, then the triangulation's."""
    if fan == "-":
        f = "three edges"
    else:
        c = dict(re.match(r"([a-z]+)(\d+)", x).groups() for x in fan.split(",")[:3])
        last = fan.split(",")[-1]
        f = ("faces backwards" if c["back"] != "0" else "off the input" if c["off"] != "0"
             else "no area" if c["small"] != "0" else "folds onto a rim face" if last.startswith("rim")
             else "folds within" if last == "within" else "closes")
    t = {"none_even_without_rim": "none faces the normal", "none_rimfold": "each folds onto a rim face",
         "toolong": "too long"}.get(tri, "off the input" if re.match(r"off[1-9]", tri) else tri)
    return f, t


for name, label in [("loops_base.csv", "Newell normal"), ("loops_local.csv", "rim faces' normals")]:
    loops = list(csv.DictReader(open(os.path.join(here, name))))
    print(f"\nLoops left open after the last closing, 80 validation meshes (triangulation facing the {label})")
    print(f"{len(loops)} loops; median {sorted(int(r['edges']) for r in loops)[len(loops) // 2]} edges, "
          f"median radius {sorted(float(r['radius_spacings']) for r in loops)[len(loops) // 2]:.0f} point spacings")
    print("| fan | triangulation | loops |")
    print("|---|---|---:|")
    for (f, t), n in collections.Counter(reason(r["fan"], r["triangulation"]) for r in loops).most_common():
        print(f"| {f} | {t} | {n} |")

gt = {r["name"]: int(r["gt_holes"]) for r in csv.DictReader(open(os.path.join(here, "val80_gt_holes.csv")))}
closed = [n for n, h in gt.items() if h == 0]
print(f"\nGround truth: {sum(gt.values()) / len(gt):.2f} holes a mesh; {len(closed)} of {len(gt)} closed")
base = load_rows(os.path.join(here, "val80_base.per_mesh.csv"), SURFACE_KEYS)
keys = ["cd", "nc", "ef1", "holes"]
print("\n80 validation meshes (paired differences from base, mean ± s.e.); the last column: holes a mesh on the meshes whose ground truth is closed")
print("| arm | CD x100 | NC | ECD x100 | EF1 | faces | holes | CD vs base | NC vs base | EF1 vs base | holes vs base | holes, closed gt |")
print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
points = []
for arm in ARMS:
    rows = load_rows(os.path.join(here, f"val80_{arm}.per_mesh.csv"), SURFACE_KEYS)
    # An arm whose mesh lost every face has no figures for it: left out of its means.
    on_closed = [rows[n]["holes"] for n in closed if rows[n]["holes"] is not None]
    line = arm_row(arm, rows, None if arm == "base" else base, keys)
    print(line[:-1] + f"| {sum(on_closed) / len(on_closed):.2f} |")
    if arm != "base":
        points.append((arm, paired_rows(rows, base, "holes"), paired_rows(rows, base, "cd")))

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    sys.exit(0)
fig, ax = plt.subplots(figsize=(7, 4))
for i, (arm, (dh, sh), (dc, sc)) in enumerate(points):
    ax.errorbar(dh, dc, xerr=sh, yerr=sc, fmt="o", capsize=3)
    # Arms that close nothing sit on top of each other: their labels step down.
    ax.annotate(arm, (dh, dc), textcoords="offset points", xytext=(5, 6 - 9 * (i % 4)), fontsize=8)
# Unguarded trimming costs 30-100x what the guarded arms do: a linear axis near zero, log beyond.
ax.set_yscale("symlog", linthresh=0.1)
finish_paired_plot(fig, ax, "holes a mesh, paired difference from 254c467", "CD x100, paired difference",
                   "Trimming crumpled rims before closing: fewer holes cost distance",
                   os.path.join(here, "trim_and_close.png"), dpi=100)
