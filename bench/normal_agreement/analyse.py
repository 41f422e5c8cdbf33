#!/usr/bin/env python3
"""Issue 52's normal-agreement weight on the validation split: one `meshflow eval generate
--split val` JSON per weight (DIR/wW.json, NORMAL_WEIGHT set to W in the build that wrote it),
scored per mesh against the ground truth. Prints a table of the means with each weight's
paired difference from weight 0 (and its standard error) and writes DIR/weights.png (CD, NC,
EF1 and holes against the weight) and DIR/per_mesh.csv.

Usage: python3 bench/normal_agreement/analyse.py DIR
"""
import csv
import glob
import json
import math
import os
import re
import sys


def rows(path):
    d = json.load(open(path))
    out = []
    for m in d["per_mesh"]:
        o = m.get("ours")
        if not o:
            out.append(None)
            continue
        out.append(dict(cd=o["chamfer_x100"], nc=o["normal_consistency"],
                        ecd=o["sharp"]["edge_chamfer_x100"], ef1=o["sharp"]["edge_f_score"]["f_score"],
                        holes=o["pred_topology"]["holes"], faces=o["pred_topology"]["faces"]))
    return out


def mean_se(xs):
    n = len(xs)
    m = sum(xs) / n
    var = sum((x - m) ** 2 for x in xs) / max(n - 1, 1)
    return m, math.sqrt(var / n)


def main(folder):
    arms = {}
    for path in glob.glob(os.path.join(folder, "w*.json")):
        w = float(re.match(r"w([0-9.]+)\.json", os.path.basename(path)).group(1))
        arms[w] = rows(path)
    weights = sorted(arms)
    n = min(len(a) for a in arms.values())
    every = [i for i in range(n) if all(arms[w][i] is not None for w in weights)]
    keys = ["cd", "nc", "ecd", "ef1", "holes", "faces"]
    print(f"{len(every)} meshes with every arm")
    print("weight  " + "  ".join(f"{k:>24s}" for k in keys))
    table = {}
    for w in weights:
        cells = []
        for k in keys:
            values = [arms[w][i][k] for i in every if arms[w][i][k] is not None]
            m = sum(values) / len(values)
            if w == weights[0]:
                cells.append(f"{m:24.4f}")
            else:
                diffs = [arms[w][i][k] - arms[weights[0]][i][k] for i in every
                         if arms[w][i][k] is not None and arms[weights[0]][i][k] is not None]
                dm, se = mean_se(diffs)
                cells.append(f"{m:.4f} {dm:+.4f} ({se:.4f})".rjust(24))
            table.setdefault(k, []).append(m)
        print(f"{w:<7g} " + "  ".join(cells))
    with open(os.path.join(folder, "per_mesh.csv"), "w", newline="") as f:
        out = csv.writer(f)
        out.writerow(["mesh", "weight"] + keys)
        for i in every:
            for w in weights:
                out.writerow([i, w] + [arms[w][i][k] for k in keys])
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, axes = plt.subplots(1, 4, figsize=(14, 3.2))
    for ax, k, label in zip(axes, ["cd", "nc", "ef1", "holes"], ["CD x100", "NC", "EF1", "holes"]):
        ax.plot(weights, table[k], marker="o")
        ax.set_xscale("symlog", linthresh=1)
        ax.set_xlabel("NORMAL_WEIGHT")
        ax.set_title(label)
        ax.grid(alpha=0.3)
    fig.suptitle("validation split, shipped weights, defaults otherwise")
    fig.tight_layout()
    fig.savefig(os.path.join(folder, "weights.png"), dpi=110)


if __name__ == "__main__":
    main(sys.argv[1])
