#!/usr/bin/env python3
"""f16 against f32 weights (issue 54): test-split generation with each precision over two
seeds, side by side. DIR holds `meshflow eval generate --split test --seed S [--weights W]
-o DIR/{f32,f16}_sS.json` for S in 0 and 1 (W: a folder with the f32 files, and one with the
same files rounded by scripts/half-weights.mjs). Prints each arm's means, the paired f16 - f32
difference per seed with its standard error, the seed-to-seed difference for scale, and
writes DIR/per_mesh.csv.

Usage: python3 bench/weights_precision/compare.py DIR
"""
import csv
import json
import math
import os
import sys

KEYS = ["cd", "nc", "ecd", "ef1", "holes", "faces"]


def load(path):
    out = []
    for m in json.load(open(path))["per_mesh"]:
        o = m.get("ours")
        out.append(None if not o else dict(
            cd=o["chamfer_x100"], nc=o["normal_consistency"], ecd=o["sharp"]["edge_chamfer_x100"],
            ef1=o["sharp"]["edge_f_score"]["f_score"], holes=o["pred_topology"]["holes"],
            faces=o["pred_topology"]["faces"]))
    return out


def paired(a, b, key):
    d = [b[i][key] - a[i][key] for i in range(min(len(a), len(b)))
         if a[i] and b[i] and a[i][key] is not None and b[i][key] is not None]
    m = sum(d) / len(d)
    se = math.sqrt(sum((v - m) ** 2 for v in d) / (len(d) - 1) / len(d))
    return m, se


def main(folder):
    arms = {k: load(os.path.join(folder, f"{k}.json")) for k in ["f32_s0", "f16_s0", "f32_s1", "f16_s1"]}
    print("arm     " + "  ".join(f"{k:>8s}" for k in KEYS))
    for name, rows in arms.items():
        means = []
        for k in KEYS:
            v = [r[k] for r in rows if r and r[k] is not None]
            means.append(sum(v) / len(v))
        print(f"{name:7s} " + "  ".join(f"{m:8.4f}" for m in means))
    for label, a, b in [("f16 - f32, seed 0", "f32_s0", "f16_s0"), ("f16 - f32, seed 1", "f32_s1", "f16_s1"),
                        ("seed 1 - seed 0, f32", "f32_s0", "f32_s1")]:
        cells = [f"{k} {m:+.4f} ({se:.4f})" for k in KEYS for m, se in [paired(arms[a], arms[b], k)]]
        print(f"{label:21s} " + "  ".join(cells))
        same = sum(1 for x, y in zip(arms[a], arms[b]) if x and y and x == y)
        print(f"{'':21s} meshes with every figure equal: {same} of {len(arms[a])}")
    with open(os.path.join(folder, "per_mesh.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["mesh", "arm"] + KEYS)
        for i in range(len(arms["f32_s0"])):
            for name, rows in arms.items():
                if rows[i]:
                    w.writerow([i, name] + [rows[i][k] for k in KEYS])


if __name__ == "__main__":
    main(sys.argv[1])
