"""Per group of boundary loops of our meshes (the connected boundary edges: loops that share
a vertex count as one): the input points within 3 spacings of its rim that our surface does not
cover (farther than 2 spacings from it), and whether the ground truth is open anywhere. A hole
where the input goes on has such points beside its rim; a hole the input has too has none.
    python3 hole_census.py DIR > census.csv   (needs numpy, scipy, trimesh)
DIR: a `meshflow eval generate --meshes DIR` folder (K.ours.glb, K.points.ply, K.gt.glb).
Our surface is measured through 60,000 area samples of it (a fifth of a spacing apart on
these meshes), not exactly: trimesh's exact query needs rtree."""
import collections
import glob
import os
import sys

import numpy as np
import trimesh
from scipy.spatial import cKDTree


def load(path):
    """A mesh with its vertices welded by position (a GLB splits them by normal)."""
    m = trimesh.load(path, force="mesh", process=False)
    m.merge_vertices(merge_tex=True, merge_norm=True)
    return m


def boundary_groups(m):
    """The edges with one face, grouped by the vertices they share."""
    u, c = np.unique(m.edges_sorted, axis=0, return_counts=True)
    parent = {}

    def find(x):
        while parent.setdefault(x, x) != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    rims = u[c == 1]
    for a, b in rims:
        parent[find(a)] = find(b)
    groups = collections.defaultdict(list)
    for a, b in rims:
        groups[find(a)].append((a, b))
    return list(groups.values())


def main(d):
    print("mesh,loop,edges,rim_len_sp,uncovered_near,points_near,gt_open,uncovered_share")
    for f in sorted(glob.glob(os.path.join(d, "*.ours.glb")), key=lambda p: int(os.path.basename(p).split(".")[0])):
        k = os.path.basename(f).split(".")[0]
        m = load(f)
        pts = np.asarray(trimesh.load(os.path.join(d, f"{k}.points.ply"), process=False).vertices)
        tree = cKDTree(pts)
        sp = np.median(tree.query(pts, k=2)[0][:, 1])
        surface, _ = trimesh.sample.sample_surface(m, 60000, seed=0)
        uncovered = cKDTree(surface).query(pts)[0] > 2 * sp
        gt_open = int(len(boundary_groups(load(os.path.join(d, f"{k}.gt.glb")))) > 0)
        far = cKDTree(pts[uncovered]) if uncovered.any() else None
        for i, edges in enumerate(boundary_groups(m)):
            samples, length = [], 0.0
            for a, b in edges:
                p, q = m.vertices[a], m.vertices[b]
                length += np.linalg.norm(q - p)
                n = max(2, int(np.linalg.norm(q - p) / (0.5 * sp)))
                samples.extend(p + (q - p) * t for t in np.linspace(0, 1, n))
            near = {x for lst in tree.query_ball_point(samples, 3 * sp) for x in lst}
            near_far = {x for lst in far.query_ball_point(samples, 3 * sp) for x in lst} if far else set()
            print(f"{k},{i},{len(edges)},{length / sp:.1f},{len(near_far)},{len(near)},{gt_open},{uncovered.mean():.4f}")


if __name__ == "__main__":
    main(sys.argv[1])
