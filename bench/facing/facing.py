#!/usr/bin/env python3
"""How each generated mesh faces against its ground truth, from a `meshflow eval generate
--meshes DIR` folder (K.ours.glb beside K.gt.glb).

Per mesh: 4,000 points sampled on ours by area, each point's face normal against the normal
of the ground-truth face nearest it (20,000 samples on the ground truth, the nearest one's
face): the mean cosine `facing` (1: the same side out, -1: inside out), and the ground
truth's own signed volume and whether it is closed. An artist's mesh can itself be inside
out (a negative volume), so `facing_gt_out` is `facing` times the sign of that volume.
Ours' signed volume about its own area centroid (`volume_about_centre`, the measure
`geometry::orient` turns pieces by, here over the whole mesh) is given too.

    python3 bench/facing/facing.py DIR > DIR.facing.csv

prints the CSV, and to stderr the counts: meshes inside out (`facing_gt_out` below -0.2),
facing out (above 0.2), and between.
"""
import csv
import glob
import os
import sys

import numpy as np
import trimesh
from scipy.spatial import cKDTree


def volume_about_centre(m):
    t = m.triangles
    area = m.area_faces
    centre = (m.triangles_center * area[:, None]).sum(0) / max(area.sum(), 1e-300)
    t = t - centre
    return float(np.einsum("ij,ij->i", t[:, 0], np.cross(t[:, 1], t[:, 2])).sum() / 6.0)


def main(d):
    w = csv.writer(sys.stdout)
    w.writerow(["mesh", "facing", "gt_volume", "gt_closed", "facing_gt_out", "volume_about_centre"])
    counts = {"inside out": 0, "out": 0, "between": 0}
    keys = sorted(glob.glob(f"{d}/*.ours.glb"), key=lambda s: int(os.path.basename(s).split(".")[0]))
    for f in keys:
        k = os.path.basename(f).split(".")[0]
        ours = trimesh.load(f, force="mesh", process=False)
        gt = trimesh.load(f"{d}/{k}.gt.glb", force="mesh", process=False)
        p, fi = trimesh.sample.sample_surface(ours, 4000, seed=0)
        q, gi = trimesh.sample.sample_surface(gt, 20000, seed=0)
        _, j = cKDTree(q).query(p)
        facing = float(np.einsum("ij,ij->i", ours.face_normals[fi], gt.face_normals[gi[j]]).mean())
        signed = facing * (1.0 if gt.volume >= 0 else -1.0)
        counts["inside out" if signed < -0.2 else "out" if signed > 0.2 else "between"] += 1
        w.writerow([k, f"{facing:.4f}", f"{gt.volume:.6g}", int(gt.is_watertight), f"{signed:.4f}",
                    f"{volume_about_centre(ours):.6g}"])
    print(f"{len(keys)} meshes: {counts}", file=sys.stderr)


if __name__ == "__main__":
    main(sys.argv[1])
