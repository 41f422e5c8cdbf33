"""How many input points of the hard-surface set's thin-walled shapes have the two sides of a
wall among their 24 nearest points, by the trial's rule (trial.patch, `same_sheet`): the
points' offsets across their best-fitting plane fall into two groups with a gap of at least
half the median point spacing and twice either group's own spread.
    python3 sheet_count.py   (from the repository root or anywhere; needs numpy, scipy, trimesh)"""
import os

import numpy as np
import trimesh
from scipy.spatial import cKDTree

root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "..")
for name in ["hollow_box", "table"]:
    p = np.asarray(trimesh.load(os.path.join(root, f"tests/fixtures/hard_surface/points/{name}.ply")).vertices)
    tree = cKDTree(p)
    spacing = np.median(tree.query(p, 2)[0][:, 1])
    _, near = tree.query(p, 24)
    split = 0
    for i in range(len(p)):
        q = p[near[i]]
        c = q - q.mean(0)
        normal = np.linalg.eigh(c.T @ c)[1][:, 0]
        o = np.sort((q - q[0]) @ normal)
        gaps = o[3:len(o) - 2] - o[2:len(o) - 3]
        k = int(np.argmax(gaps)) + 3
        gap = o[k] - o[k - 1]
        if gap >= 0.5 * spacing and gap >= 2 * max(o[k - 1] - o[0], o[-1] - o[k]):
            split += 1
    print(f"{name}: spacing {spacing:.4f}, {split} of {len(p)} points with two sheets among their 24 nearest")
