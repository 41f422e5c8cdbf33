#!/usr/bin/env python3
"""Plot and table of the steps-against-candidates sweep (run.sh).

Left: validation CD x100 against holes per mesh. The measured arms (arms.csv: `meshflow eval
generate --split val --steps S --samples K`, each a point), and, from the per-candidate
table (candidates_val_s7.csv), the choice keep_best makes among the first K candidates,
replayed for hole weights w from 0 (distance alone) to holes first: score = distance to the
input x (1 + w x holes). Right: the same arms' CD and holes against the whole generation's
time on the lantern scan (`meshflow bench generate --steps S --samples K`, CPU, medians).

    python3 bench/samples_sweep/plot.py [DIR [PNG]]

Reads arms.csv and candidates_val_s7.csv from DIR, each from the experiment's data folder
(docs/experiments/data/2026-11-26-candidates-and-steps/samples_sweep/, the default DIR) where
DIR lacks it; writes PNG (default: sweep.png in DIR) and prints the tables."""
import csv
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
LOGGED = ROOT / "docs" / "experiments" / "data" / "2026-11-26-candidates-and-steps" / "samples_sweep"
DIR = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else LOGGED
PNG = pathlib.Path(sys.argv[2]) if len(sys.argv) > 2 else DIR / "sweep.png"


def source(name):
    return DIR / name if (DIR / name).exists() else LOGGED / name


arms = list(csv.DictReader(open(source("arms.csv"))))
rows = np.array([[float(r[k]) for k in ("mesh", "candidate", "holes", "cd_x100", "input_cd_x100")]
                 for r in csv.DictReader(open(source("candidates_val_s7.csv")))])
n, k_max = int(rows[:, 0].max()) + 1, int(rows[:, 1].max()) + 1
holes, cd, icd = (np.full((n, k_max), np.nan) for _ in range(3))
for m, j, h, c, d in rows:
    holes[int(m), int(j)], cd[int(m), int(j)], icd[int(m), int(j)] = h, c, d


def replay(k, w):
    """Mean CD and holes of the candidate kept among the first k, hole weight w."""
    if w is None:  # holes first, then distance
        pick = [np.lexsort((icd[i, :k], holes[i, :k]))[0] for i in range(n)]
    else:
        pick = [np.argmin(icd[i, :k] * (1 + w * holes[i, :k])) for i in range(n)]
    r = np.arange(n)
    return cd[r, pick].mean(), holes[r, pick].mean()


weights = [0, 0.1, 0.2, 0.3, 0.5, 0.7, 1.0, 2.0, None]
fig, (ax, bx) = plt.subplots(1, 2, figsize=(13, 5.2))
print("replayed on the validation split (7 steps): CD x100 / holes")
print("| hole weight w | " + " | ".join(f"K = {k}" for k in (4, 8, 12)) + " |")
print("|---|" + "---:|" * 3)
table = {k: [replay(k, w) for w in weights] for k in (4, 8, 12)}
for i, w in enumerate(weights):
    label = "holes first" if w is None else f"{w}"
    print(f"| {label} | " + " | ".join(f"{table[k][i][0]:.3f} / {table[k][i][1]:.2f}" for k in (4, 8, 12)) + " |")
for k, colour in zip((4, 8, 12), ("tab:blue", "tab:orange", "tab:green")):
    c, h = zip(*table[k])
    ax.plot(h, c, "-o", color=colour, ms=3, label=f"7 steps, {k} candidates, w from 0 to holes first")
    ax.annotate("w = 0.5", (h[4], c[4]), fontsize=7, xytext=(4, 4), textcoords="offset points")
for a in arms:
    if a["split"] != "val":
        continue
    ax.plot(float(a["holes"]), float(a["cd_x100"]), "k^" if a["rule"] == "weight 0.5" else "ks", ms=5)
    ax.annotate(a["name"], (float(a["holes"]), float(a["cd_x100"])), fontsize=7,
                xytext=(4, -8), textcoords="offset points")
ax.axvline(1.5, color="grey", ls=":", lw=1)
ax.set_xlabel("holes per mesh (validation)")
ax.set_ylabel("CD x100 (validation)")
ax.set_title("Which candidate to keep (squares: holes first; triangles: w = 0.5)")
ax.legend(fontsize=7)
timed = [a for a in arms if a["split"] == "val" and a["lantern_s"]]
for a in timed:
    t = float(a["lantern_s"])
    bx.plot(t, float(a["cd_x100"]), "o", color="tab:blue")
    bx.plot(t, float(a["holes"]), "s", color="tab:red")
    bx.annotate(a["name"], (t, float(a["holes"])), fontsize=7, xytext=(4, 4), textcoords="offset points")
bx.plot([], [], "o", color="tab:blue", label="CD x100")
bx.plot([], [], "s", color="tab:red", label="holes per mesh")
bx.set_xlabel("whole generation on the lantern scan, s (CPU, 2 threads, median)")
bx.set_title("What the arms cost")
bx.legend(fontsize=7)
fig.tight_layout()
fig.savefig(PNG, dpi=110)
print("\nmeasured arms")
print("| arm | split | steps | candidates | rule | CD x100 | HD x100 | faces | holes | components | lantern s |")
print("|---|---|---:|---:|---|---:|---:|---:|---:|---:|---:|")
for a in arms:
    print(f"| {a['name']} | {a['split']} | {a['steps']} | {a['samples']} | {a['rule']} | {a['cd_x100']} | "
          f"{a['hd_x100']} | {a['faces']} | {a['holes']} | {a['components']} | {a['lantern_s'] or '-'} |")
