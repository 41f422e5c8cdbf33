#!/usr/bin/env python3
"""Summary of bench/sharpen_eval/run_test.sh's output folder: means of CD, NC, ECD, EF1,
faces and topology for today's pipeline (--no-sharpen), the sharpened one, Poisson + QEM at
the sharpened face counts and the VAE bound, over the meshes every arm has, and over the
subset whose ground truth is closed; and the ground truth's own holes, which artists' meshes
have (open parts), beside the arms' figure.

Usage: python3 bench/sharpen_eval/summarize.py OUT
"""
import json
import os
import sys


def row(c):
    return dict(cd=c["chamfer_x100"], nc=c["normal_consistency"],
                ecd=c["sharp"]["edge_chamfer_x100"], ef1=c["sharp"]["edge_f_score"]["f_score"],
                faces=c["pred_topology"]["faces"], gtf=c["gt_topology"]["faces"],
                nm=c["pred_topology"]["non_manifold_edges"],
                iw=c["pred_topology"]["inconsistent_winding_edges"],
                holes=c["pred_topology"]["holes"], gt_holes=c["gt_topology"]["holes"],
                closed=c["gt_topology"]["boundary_edges"] == 0)


def mean(rows, key):
    values = [r[key] for r in rows if r[key] is not None]
    return sum(values) / max(len(values), 1)


def main(out):
    sharpened = json.load(open(os.path.join(out, "sharpened.json")))
    arms = {}
    today = None
    if os.path.exists(os.path.join(out, "today.json")):
        today = json.load(open(os.path.join(out, "today.json")))
        arms["today"] = [row(m["ours"]) if m["ours"] else None for m in today["per_mesh"]]
    arms["sharpened"] = [row(m["ours"]) if m["ours"] else None for m in sharpened["per_mesh"]]
    poisson = []
    for k in range(len(sharpened["per_mesh"])):
        path = os.path.join(out, "meshes", f"{k}.poisson.cmp.json")
        poisson.append(row(json.load(open(path))) if os.path.exists(path) and os.path.getsize(path) else None)
    arms["poisson_qem"] = poisson
    arms["vae"] = [row(m["vae"]) if m.get("vae") else None for m in sharpened["per_mesh"]]
    n = len(sharpened["per_mesh"])
    every = [i for i in range(n) if all(arms[a][i] is not None for a in arms)]
    print(f"noise {sharpened['noise']} missing {sharpened['missing']}: {n} meshes, {len(every)} with every arm")
    for subset, idx in [("all", every), ("closed", [i for i in every if arms["sharpened"][i]["closed"]])]:
        print(subset, len(idx))
        for arm in arms:
            rs = [arms[arm][i] for i in idx]
            if not rs:
                continue
            ratio = sum(r["faces"] / r["gtf"] for r in rs) / len(rs)
            print(f"  {arm:12s} CD {mean(rs, 'cd'):.3f} NC {mean(rs, 'nc'):.4f} ECD {mean(rs, 'ecd'):.3f} "
                  f"EF1 {mean(rs, 'ef1'):.4f} faces {mean(rs, 'faces'):.1f} ratio {ratio:.2f} "
                  f"nm {mean(rs, 'nm'):.2f} iw {mean(rs, 'iw'):.2f} holes {mean(rs, 'holes'):.2f}")
        print(f"  {'ground truth':12s} holes {mean([arms['sharpened'][i] for i in idx], 'gt_holes'):.2f}")
    print("mean times, sharpened", sharpened["mean_times"])
    if today:
        print("mean times, today", today["mean_times"])
    kept = [m["sharpen"]["rounds_kept"] for m in sharpened["per_mesh"] if "sharpen" in m]
    if kept:
        print("sharpening kept: the last round on", kept.count(max(kept)), "meshes, an earlier one on",
              sum(0 < k < max(kept) for k in kept), ", none on", kept.count(0))


if __name__ == "__main__":
    main(sys.argv[1])
