"""Tables and plot of docs/experiments/2026-12-07-membrane-close.md: the membrane arms on the
first 80 validation meshes (paired against base), what became of the membrane patches tried,
and the census of the loops left open.
    python3 analyse.py   (needs matplotlib)"""
import csv
import os
import statistics
import sys

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, "..", "..", "..", "..", "bench"))
from paired import SURFACE_KEYS, arm_row, finish_paired_plot, load_rows, paired_rows  # noqa: E402

ARMS = ["base", "m6", "g10", "n15"]
rows = {arm: load_rows(os.path.join(here, f"val80_{arm}.per_mesh.csv"), SURFACE_KEYS) for arm in ARMS}

# 1. The arms, means over the 80 meshes, then per-mesh differences from base.
keys = ["cd", "nc", "ef1", "holes"]
print("| arm | CD x100 | NC | ECD x100 | EF1 | faces | holes | CD vs base | NC vs base | EF1 vs base | holes vs base |")
print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
for arm in ARMS:
    print(arm_row(arm, rows[arm], None if arm == "base" else rows["base"], keys))
for arm in ARMS[1:]:
    changed = sum(1 for n in rows[arm] if rows[arm][n] != rows["base"].get(n))
    print(f"{arm}: {changed} of {len(rows[arm])} meshes change")

# 2. The membrane patches each arm tried (every candidate, every closing), by outcome.
print()
print("| arm | outcome | patches |")
print("|---|---|---:|")
with open(os.path.join(here, "membrane_outcomes.csv")) as f:
    for r in csv.DictReader(f):
        print(f"| {r['arm']} | {r['outcome']} | {r['patches']} |")

# 3. The census: groups of loops left open in base's meshes, by the input points beside their
# rim that our surface does not cover, and by whether the ground truth is open.
census = list(csv.DictReader(open(os.path.join(here, "census.csv"))))
print()
print("| ground truth | groups (meshes) | < 5 uncovered points by the rim | 5-19 | 20 or more | median uncovered | median rim, spacings |")
print("|---|---:|---:|---:|---:|---:|---:|")
for flag, label in [("0", "closed"), ("1", "open")]:
    g = [r for r in census if r["gt_open"] == flag]
    u = [int(r["uncovered_near"]) for r in g]
    bands = [sum(lo <= x < hi for x in u) for lo, hi in [(0, 5), (5, 20), (20, 10**9)]]
    print(f"| {label} | {len(g)} ({len({r['mesh'] for r in g})}) | " + " | ".join(map(str, bands))
          + f" | {statistics.median(u):.0f} | {statistics.median(float(r['rim_len_sp']) for r in g):.0f} |")
shares = {r["mesh"]: float(r["uncovered_share"]) for r in census}
print(f"input points farther than 2 spacings from our surface, meshes with an open loop: "
      f"median {statistics.median(shares.values()):.3f}, mean {sum(shares.values()) / len(shares):.3f}")

# The plot: CD against holes, paired changes from base per arm (mean ± s.e.).
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

fig, ax = plt.subplots(figsize=(5.5, 4))
for arm in ARMS[1:]:
    (dh, sh), (dc, sc) = (paired_rows(rows[arm], rows["base"], k) for k in ("holes", "cd"))
    ax.errorbar(dh, dc, xerr=sh, yerr=sc, fmt="o", capsize=3, label=arm)
ax.legend()
finish_paired_plot(fig, ax, "holes a mesh, change from base", "CD x100, change from base",
                   "Membrane closing, 80 validation meshes", os.path.join(here, "membrane_close.png"))
