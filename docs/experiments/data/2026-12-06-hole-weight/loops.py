"""Where the holes of generated meshes are: per boundary loop of each OBJ given, its number of
edges and on how many of its rim faces a fan around the loop's centroid would fold (normals
more than about 143 degrees apart, FOLD_COS -0.8, as `geometry::topology::folds`), then a
summary over all loops. For docs/experiments/2026-12-06-hole-weight.md:
    meshflow eval generate --split val --meshes DIR -o RUN.json
    meshflow convert DIR/K.ours.glb K.obj   (for the meshes whose ground truth has no hole)
    python3 loops.py K.obj ...
Loops are walked against their faces, as close_holes walks them; where several meet at a
vertex the walk may cut them differently."""
import statistics
import sys
from collections import defaultdict

import numpy as np

FOLD_COS = -0.8


def load_obj(path):
    positions, faces = [], []
    for line in open(path):
        s = line.split()
        if s and s[0] == "v":
            positions.append([float(x) for x in s[1:4]])
        elif s and s[0] == "f":
            faces.append([int(x.split("/")[0]) - 1 for x in s[1:4]])
    return np.array(positions), faces


def loops_of(faces):
    walked = {}
    for i, (a, b, c) in enumerate(faces):
        for e in ((a, b), (b, c), (c, a)):
            walked[e] = i
    boundary = [e for e in walked if (e[1], e[0]) not in walked]
    # A boundary edge (u, v) of a face is walked v -> u by its loop.
    after = defaultdict(list)
    for u, v in boundary:
        after[v].append(u)
    used, loops = set(), []
    for u, v in boundary:
        if (u, v) in used:
            continue
        used.add((u, v))
        loop, at = [v], u
        while at != v:
            loop.append(at)
            nxt = [w for w in after[at] if (w, at) not in used]
            if not nxt:
                break
            used.add((nxt[0], at))
            at = nxt[0]
        loops.append(loop)
    return loops, walked


rows = []
for path in sys.argv[1:]:
    positions, faces = load_obj(path)
    loops, walked = loops_of(faces)
    normal = lambda p: np.cross(p[1] - p[0], p[2] - p[0])
    for loop in loops:
        k = len(loop)
        centre = positions[loop].mean(axis=0)
        folds = 0
        for i in range(k):
            a, b = loop[i], loop[(i + 1) % k]
            n = normal([positions[a], positions[b], centre])
            m = normal(positions[faces[walked[(b, a)]]])
            if np.linalg.norm(n) > 0 and np.dot(n, m) / (np.linalg.norm(n) * np.linalg.norm(m)) < FOLD_COS:
                folds += 1
        rows.append((k, folds))
        print(f"{path}: loop of {k} edges, a centroid fan folds onto {folds} rim faces")
ks = [k for k, _ in rows]
print(f"{len(rows)} loops; median {statistics.median(ks)} edges, {sum(k >= 16 for k in ks)} of 16 or more; "
      f"a centroid fan folds onto a median {statistics.median(f / k for k, f in rows):.2f} of the rim faces; "
      f"{sum(f == 0 for _, f in rows)} loops without a fold")
