#!/usr/bin/env python3
"""Sharpening with and without the coverage guard, per validation mesh: one PNG, one table.

Usage: python3 analyse.py BEFORE.json AFTER.json OUTDIR  (two `meshflow eval generate` outputs)
"""
import json
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

before, after, out = json.load(open(sys.argv[1])), json.load(open(sys.argv[2])), sys.argv[3]


def per_mesh(d):
    rows = []
    for m in d["per_mesh"]:
        o = m["ours"]
        if not o:
            rows.append(None)
            continue
        rows.append(dict(cd=o["chamfer_x100"], nc=o["normal_consistency"],
                         ef1=o["sharp"]["edge_f_score"]["f_score"], ecd=o["sharp"]["edge_chamfer_x100"],
                         faces=o["pred_topology"]["faces"], holes=o["pred_topology"]["holes"],
                         rounds=m["sharpen"]["rounds_kept"], accepted=m["sharpen"]["accepted"]))
    return rows


a, b = per_mesh(before), per_mesh(after)
pairs = [(x, y) for x, y in zip(a, b) if x and y]
def mean(rows, k):
    # ECD is None where neither mesh has sharp edges (the summary leaves those out too).
    values = [r[k] for r in rows if r[k] is not None]
    return sum(values) / max(len(values), 1)
lines = ["| arm | meshes | CD x100 | NC | ECD x100 | EF1 | faces | holes | last round kept | earlier round | none |",
         "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
for name, rows in (("without the guard", [p[0] for p in pairs]), ("with the guard", [p[1] for p in pairs])):
    last = sum(1 for r in rows if r["rounds"] == 8)
    none = sum(1 for r in rows if r["rounds"] == 0)
    lines.append(f"| {name} | {len(rows)} | {mean(rows, 'cd'):.3f} | {mean(rows, 'nc'):.4f} | {mean(rows, 'ecd'):.2f} | "
                 f"{mean(rows, 'ef1'):.4f} | {mean(rows, 'faces'):.1f} | {mean(rows, 'holes'):.2f} | {last} | {len(rows) - last - none} | {none} |")
# Where it changed what was kept.
moved = [(x, y) for x, y in pairs if x["rounds"] != y["rounds"]]
lines.append("")
lines.append(f"meshes whose kept round changed: {len(moved)}; on them NC {mean([m[0] for m in moved], 'nc'):.4f} -> "
             f"{mean([m[1] for m in moved], 'nc'):.4f}, EF1 {mean([m[0] for m in moved], 'ef1'):.4f} -> {mean([m[1] for m in moved], 'ef1'):.4f}, "
             f"CD {mean([m[0] for m in moved], 'cd'):.3f} -> {mean([m[1] for m in moved], 'cd'):.3f}" if moved else "none changed")
open(f"{out}/table.md", "w").write("\n".join(lines) + "\n")
print("\n".join(lines))

fig, ax = plt.subplots(1, 3, figsize=(15, 4.6))
for k, (key, label) in enumerate((("nc", "NC"), ("ef1", "EF1"), ("cd", "CD x100"))):
    xs, ys = [p[0][key] for p in pairs], [p[1][key] for p in pairs]
    c = ["tab:blue" if p[0]["rounds"] == p[1]["rounds"] else "tab:red" for p in pairs]
    ax[k].scatter(xs, ys, s=9, c=c)
    lo, hi = min(xs + ys), max(xs + ys)
    ax[k].plot([lo, hi], [lo, hi], "k--", lw=0.8)
    ax[k].set_xlabel(f"{label}, without the guard")
    ax[k].set_ylabel(f"{label}, with the guard")
    ax[k].set_title(f"{label} per validation mesh (red: kept round changed)")
fig.tight_layout()
fig.savefig(f"{out}/coverage.png", dpi=90)
