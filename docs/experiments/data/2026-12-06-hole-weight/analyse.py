"""The candidate choice's hole weight: the table and the plot of
docs/experiments/2026-12-06-hole-weight.md from the per-mesh CSVs beside this file.
    python3 analyse.py [DIR]"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../../../bench"))
from paired import load_rows, mean_of as mean, paired_rows as paired  # noqa: E402

here = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
KEYS = ["cd", "nc", "ecd", "ef1", "faces", "holes"]
# Arm name and the weight each hole adds to a candidate's distance to the input.
ARMS = [("w0.5", 0.5), ("w1", 1), ("w2", 2), ("w4", 4), ("holes_first", 1e6)]


def load(arm):
    return load_rows(os.path.join(here, f"val_{arm}.per_mesh.csv"), KEYS)


base = load("w0.5")
print("| arm | CD x100 | NC | ECD x100 | EF1 | faces | holes | meshes with holes | CD vs 0.5 | NC vs 0.5 | holes vs 0.5 |")
print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
points = []
for arm, w in ARMS:
    rows = load(arm)
    with_holes = sum(1 for r in rows.values() if r["holes"])
    line = (f"| {arm} | {mean(rows, 'cd'):.3f} | {mean(rows, 'nc'):.4f} | {mean(rows, 'ecd'):.2f} | "
            f"{mean(rows, 'ef1'):.4f} | {mean(rows, 'faces'):.1f} | {mean(rows, 'holes'):.3f} | {with_holes} |")
    (dc, sc), (dn, sn), (dh, sh) = (paired(rows, base, k) for k in ("cd", "nc", "holes"))
    line += f" {dc:+.3f} ± {sc:.3f} | {dn:+.4f} ± {sn:.4f} | {dh:+.3f} ± {sh:.3f} |"
    points.append((arm, dh, sh, dc, sc))
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
ax.axhline(0, color="grey", lw=0.5)
ax.axvline(0, color="grey", lw=0.5)
ax.set_xlabel("holes a mesh, paired change from the shipped weight 0.5 (mean ± s.e.)")
ax.set_ylabel("CD x100, paired change (mean ± s.e.)")
ax.set_title("Validation split, 226 meshes: the hole weight of the candidate choice")
fig.tight_layout()
fig.savefig(os.path.join(here, "hole_weight.png"), dpi=110)
