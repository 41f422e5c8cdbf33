#!/usr/bin/env python3
"""Scores every candidate of run.sh's one-sample runs: holes, components and CD x100 to the
ground truth (from the eval JSON), and the distance keep_best ranks by: the Chamfer distance
(sum of the two means) between 2048 area-uniform samples of the mesh and the input points,
x100. Usage: candidates.py RUN_DIR K OUT.csv. Needs numpy, scipy and trimesh."""
import json
import sys

import numpy as np
import trimesh
from scipy.spatial import cKDTree

run_dir, k, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
with open(out, "w") as f:
    f.write("mesh,candidate,holes,components,cd_x100,input_cd_x100,faces\n")
    for j in range(k):
        run = f"{run_dir}/cand_seed{8 * j}"
        for i, m in enumerate(json.load(open(run + ".json"))["per_mesh"]):
            ours = m["ours"]
            if ours is None:
                continue
            points = trimesh.load(f"{run}/{i}.points.ply").vertices
            mesh = trimesh.load(f"{run}/{i}.ours.glb", force="mesh")
            samples, _ = trimesh.sample.sample_surface(mesh, 2048, seed=0)
            to_input = cKDTree(points).query(samples)[0].mean()
            from_input = cKDTree(samples).query(points)[0].mean()
            t = ours["pred_topology"]
            f.write(f"{i},{j},{t['holes']},{t['components']},{ours['chamfer_x100']:.4f},"
                    f"{(to_input + from_input) * 100:.4f},{m['faces_made']}\n")
