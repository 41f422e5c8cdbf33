#!/usr/bin/env python3
"""Render meshes side by side to one PNG, to look at reconstructions by eye.

    python3 scripts/render_meshes.py OUT.png A.obj B.obj [C.obj ...] [--cols 2]

Each mesh (OBJ, as written by `meshflow convert` / `reconstruct -o x.obj`) is drawn flat-shaded
with its wireframe, from the same 3/4 view, scaled to fit its panel; an OBJ without faces (a
point cloud) is drawn as its points. Needs numpy and matplotlib.
"""

import argparse
import sys

import numpy as np


def read_obj(path):
    verts, faces = [], []
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                verts.append([float(x) for x in parts[1:4]])
            elif parts[0] == "f":
                idx = [int(p.split("/")[0]) - 1 for p in parts[1:]]
                for k in range(1, len(idx) - 1):
                    faces.append([idx[0], idx[k], idx[k + 1]])
    return np.array(verts, dtype=float).reshape(-1, 3), np.array(faces, dtype=int).reshape(-1, 3)


def fit_view(ax, v):
    """Equal-aspect limits around the points and the shared 3/4 view."""
    lo, hi = v.min(axis=0), v.max(axis=0)
    c, r = (lo + hi) / 2, (hi - lo).max() / 2
    ax.set_xlim(c[0] - r, c[0] + r)
    ax.set_ylim(c[1] - r, c[1] + r)
    ax.set_zlim(c[2] - r, c[2] + r)
    ax.view_init(elev=20, azim=-60)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("meshes", nargs="+")
    ap.add_argument("--cols", type=int, default=2)
    ap.add_argument("--titles", nargs="*")
    args = ap.parse_args()

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    n = len(args.meshes)
    cols = min(args.cols, n)
    rows = (n + cols - 1) // cols
    fig = plt.figure(figsize=(3.2 * cols, 3.2 * rows), dpi=100)
    light = np.array([0.4, 0.5, 0.75])
    light /= np.linalg.norm(light)
    for i, path in enumerate(args.meshes):
        v, f = read_obj(path)
        ax = fig.add_subplot(rows, cols, i + 1, projection="3d")
        ax.set_axis_off()
        title = args.titles[i] if args.titles and i < len(args.titles) else path.split("/")[-1]
        ax.set_title(f"{title}\n{len(v)} v, {len(f)} f", fontsize=8)
        # Y-up model frame: show Y as the vertical axis.
        v = v[:, [0, 2, 1]] if len(v) else v
        if len(f) == 0:
            # A point cloud (or an empty mesh): draw the points.
            if len(v):
                ax.scatter(v[:, 0], v[:, 1], v[:, 2], s=0.5, c="#4a6fa5", depthshade=False)
                fit_view(ax, v)
            continue
        tri = v[f]
        normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        length = np.linalg.norm(normal, axis=1, keepdims=True)
        normal = normal / np.maximum(length, 1e-12)
        shade = 0.25 + 0.75 * np.abs(normal @ light)
        colors = np.stack([shade * 0.55, shade * 0.7, shade * 0.9, np.ones_like(shade)], axis=1)
        poly = Poly3DCollection(tri, facecolors=colors, edgecolors=(0.1, 0.1, 0.1, 0.5), linewidths=0.3)
        ax.add_collection3d(poly)
        fit_view(ax, v)
    fig.tight_layout()
    fig.savefig(args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
