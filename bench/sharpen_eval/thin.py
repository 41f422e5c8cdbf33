#!/usr/bin/env python3
"""Thins a run_test.sh output folder into what bench/sharpen_eval/ keeps: the sharpened arm's
report without its per-mesh sample details (NAME.json) and Poisson + QEM's per-mesh figures
(NAME_poisson_qem.csv).

Usage: python3 bench/sharpen_eval/thin.py OUT NAME
"""
import csv
import json
import os
import sys


def figures(c):
    return dict(cd_x100=c["chamfer_x100"], nc=c["normal_consistency"],
                ecd_x100=c["sharp"]["edge_chamfer_x100"], ef1=c["sharp"]["edge_f_score"]["f_score"],
                faces=c["pred_topology"]["faces"], holes=c["pred_topology"]["holes"],
                non_manifold=c["pred_topology"]["non_manifold_edges"])


def main(out, name):
    here = os.path.dirname(os.path.abspath(__file__))
    report = json.load(open(os.path.join(out, "sharpened.json")))
    report["per_mesh"] = [
        dict(name=m["name"], gt_vertices=m["gt_vertices"], faces_made=m["faces_made"],
             sharpen_rounds_kept=m["sharpen"]["rounds_kept"],
             **(figures(m["ours"]) if m["ours"] else {}))
        for m in report["per_mesh"]
    ]
    with open(os.path.join(here, f"{name}.json"), "w") as fh:
        json.dump(report, fh, indent=1)
    with open(os.path.join(here, f"{name}_poisson_qem.csv"), "w", newline="") as fh:
        w = None
        for k in range(len(report["per_mesh"])):
            path = os.path.join(out, "meshes", f"{k}.poisson.cmp.json")
            if not (os.path.exists(path) and os.path.getsize(path)):
                continue
            row = dict(index=k, **figures(json.load(open(path))))
            if w is None:
                w = csv.DictWriter(fh, fieldnames=list(row))
                w.writeheader()
            w.writerow(row)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
