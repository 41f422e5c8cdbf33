#!/usr/bin/env python3
"""Compacts a bench/sharpen_eval/run_test.sh output folder into the files kept in the
repository: PREFIX_sharpened.json (the run's header and, per mesh, the surface measures and
topology of ours), PREFIX_sharpened_poisson_qem.csv (the same for Poisson + QEM) and, with
--folds, each mesh's folded edges (ours, Poisson + QEM and the ground truth, counted by
`meshflow inspect --json`, TopologyReport::folded_edges).

Usage: python3 bench/sharpen_eval/compact.py OUT PREFIX [--folds MESHFLOW]
"""
import json
import os
import subprocess
import sys


def folded(meshflow, path):
    if not meshflow or not os.path.exists(path):
        return None
    out = subprocess.run([meshflow, "inspect", "--json", path], capture_output=True, text=True)
    return json.loads(out.stdout)["topology"].get("folded_edges") if out.returncode == 0 else None


def measures(c):
    return dict(cd_x100=c["chamfer_x100"], hd_x100=c["hausdorff_x100"], nc=c["normal_consistency"],
                ecd_x100=c["sharp"]["edge_chamfer_x100"], ef1=c["sharp"]["edge_f_score"]["f_score"],
                faces=c["pred_topology"]["faces"], holes=c["pred_topology"]["holes"],
                non_manifold=c["pred_topology"]["non_manifold_edges"])


def main(out, prefix, meshflow):
    run = json.load(open(os.path.join(out, "sharpened.json")))
    meshes = os.path.join(out, "meshes")
    per_mesh = []
    for k, m in enumerate(run["per_mesh"]):
        row = {"name": m["name"], "gt_vertices": m["gt_vertices"], "faces_made": m["faces_made"],
               "sharpen_rounds_kept": m.get("sharpen", {}).get("rounds_kept")}
        if m["ours"]:
            row.update(measures(m["ours"]))
        row["folded_edges"] = folded(meshflow, os.path.join(meshes, f"{k}.ours.glb"))
        row["gt_folded_edges"] = folded(meshflow, os.path.join(meshes, f"{k}.gt.glb"))
        per_mesh.append(row)
    kept = {k: v for k, v in run.items() if k not in ("per_mesh", "all")}
    kept["per_mesh"] = per_mesh
    with open(f"{prefix}_sharpened.json", "w") as f:
        json.dump(kept, f, indent=1)
    with open(f"{prefix}_sharpened_poisson_qem.csv", "w") as f:
        f.write("index,cd_x100,hd_x100,nc,ecd_x100,ef1,faces,holes,non_manifold,folded_edges\n")
        for k in range(len(run["per_mesh"])):
            path = os.path.join(meshes, f"{k}.poisson.cmp.json")
            if not (os.path.exists(path) and os.path.getsize(path)):
                continue
            r = measures(json.load(open(path)))
            fo = folded(meshflow, os.path.join(meshes, f"{k}.poisson.ply"))
            f.write(",".join(str(v) for v in [k, *r.values(), "" if fo is None else fo]) + "\n")


if __name__ == "__main__":
    args = sys.argv[1:]
    meshflow = None
    if "--folds" in args:
        i = args.index("--folds")
        meshflow = args[i + 1]
        del args[i:i + 2]
    main(*args, meshflow)
