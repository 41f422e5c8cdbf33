"""Shifted neighbourhoods for the input points' planes: one table and one plot.

    python3 analyse.py [--from-json DIR]

With `--from-json DIR` (holding `val_ARM.json` from `meshflow eval generate --split val -o`)
it first writes `val_ARM.per_mesh.csv` here; then, from those CSVs, each arm's validation
means and its paired per-mesh difference against `base` (mean and standard error: the same
meshes and seeds in every arm), into shifted_planes.md and shifted_planes.png beside it.
"""
import csv
import json
import math
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

here = pathlib.Path(__file__).parent
sys.path.insert(0, str(here.parents[3] / "bench"))
from paired import mean_se  # noqa: E402  (bench/paired.py)
ARMS = ["base", "shift", "shift2", "shift3"]
NAMES = {
    "base": "own planes (shipped)",
    "shift": "every point shifted",
    "shift2": "shifted above 2x the median variation",
    "shift3": "shifted above 2x, in the quadrics only",
}
KEYS = ["cd", "nc", "ecd", "ef1", "faces", "holes"]

if len(sys.argv) == 3 and sys.argv[1] == "--from-json":
    for arm in ARMS:
        rows = json.load(open(pathlib.Path(sys.argv[2]) / f"val_{arm}.json"))["per_mesh"]
        with open(here / f"val_{arm}.per_mesh.csv", "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["name"] + KEYS)
            for m in rows:
                o = m["ours"]
                ecd = o["sharp"]["edge_chamfer_x100"]
                w.writerow([m["name"], f"{o['chamfer_x100']:.7g}",
                            f"{o['normal_consistency']:.7g}",
                            "" if ecd is None else f"{ecd:.7g}",
                            f"{o['sharp']['edge_f_score']['f_score']:.7g}",
                            m["faces_made"], o["pred_topology"]["holes"]])

data = {}
for arm in ARMS:
    with open(here / f"val_{arm}.per_mesh.csv") as f:
        data[arm] = list(csv.DictReader(f))


def column(arm, key):
    return [float(r[key]) if r[key] != "" else math.nan for r in data[arm]]


lines = ["| arm | " + " | ".join(KEYS) + " |", "|---|" + "---:|" * len(KEYS)]
diffs = {}
for arm in ARMS:
    cells = []
    for key in KEYS:
        x, y = column("base", key), column(arm, key)
        pairs = [(a, b) for a, b in zip(x, y) if not (math.isnan(a) or math.isnan(b))]
        mean = sum(b for _, b in pairs) / len(pairs)
        dm, se = mean_se([b - a for a, b in pairs])
        diffs[(arm, key)] = (dm, se)
        cells.append(f"{mean:.4g}" + ("" if arm == "base" else f" ({dm:+.3g} ± {se:.2g})"))
    lines.append(f"| {NAMES[arm]} | " + " | ".join(cells) + " |")
(here / "shifted_planes.md").write_text("\n".join(lines) + "\n")
print("\n".join(lines))

fig, axes = plt.subplots(1, 4, figsize=(13, 3.2))
for ax, key in zip(axes, ["cd", "nc", "ecd", "ef1"]):
    arms = ARMS[1:]
    m = [diffs[(a, key)][0] for a in arms]
    e = [diffs[(a, key)][1] for a in arms]
    ax.bar(range(len(arms)), m, yerr=e, capsize=4, color="tab:gray")
    ax.axhline(0, color="k", lw=0.8)
    ax.set_xticks(range(len(arms)), ["all", "> 2x", "> 2x,\nquadrics"])
    ax.set_title(f"{key} against own planes" + (" (lower better)" if key in ("cd", "ecd") else ""))
fig.suptitle("226 validation meshes, paired difference per mesh (mean ± s.e.)")
fig.tight_layout()
fig.savefig(here / "shifted_planes.png", dpi=110)
