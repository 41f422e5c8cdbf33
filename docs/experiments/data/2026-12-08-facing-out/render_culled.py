"""culled.png of docs/experiments/2026-12-08-facing-out.md: GLBs drawn as a viewer with
back-face culling draws a single-sided material (only faces whose winding faces the camera),
each as written and wound the other way.
    python3 render_culled.py OUT.png NAME=FILE.glb ...   (needs trimesh, matplotlib)"""
import sys

import matplotlib
import numpy as np
import trimesh

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402


def draw(ax, m, title, flip):
    v = m.vertices - m.bounds.mean(0)
    v /= np.abs(v).max()
    f = m.faces[:, ::-1] if flip else m.faces
    el, az = np.radians(25), np.radians(-60)
    eye = np.array([np.cos(el) * np.cos(az), np.sin(el), np.cos(el) * np.sin(az)])  # Y up
    t = v[f]
    n = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
    keep = (n @ eye) > 0
    unit = n[keep] / np.linalg.norm(n[keep], axis=1)[:, None]
    shade = np.clip(unit @ np.array([0.3, 0.8, 0.5]), 0, 1) * 0.7 + 0.25
    ax.add_collection3d(Poly3DCollection(t[keep][:, :, [0, 2, 1]], facecolors=plt.cm.Blues(shade),
                                         edgecolor="k", linewidths=0.2))
    ax.set_xlim(-1, 1), ax.set_ylim(-1, 1), ax.set_zlim(-1, 1)
    ax.view_init(25, -60)
    ax.set_axis_off()
    ax.set_title(f"{title}: {keep.sum()} of {len(f)} faces drawn", fontsize=8)


out, pairs = sys.argv[1], [a.split("=", 1) for a in sys.argv[2:]]
fig = plt.figure(figsize=(12, 3 * len(pairs)))
for i, (name, path) in enumerate(pairs):
    m = trimesh.load(path, force="mesh", process=False)
    draw(fig.add_subplot(len(pairs), 2, 2 * i + 1, projection="3d"), m, f"{name} as shipped", False)
    draw(fig.add_subplot(len(pairs), 2, 2 * i + 2, projection="3d"), m, f"{name} wound the other way", True)
plt.tight_layout()
plt.savefig(out, dpi=90)
