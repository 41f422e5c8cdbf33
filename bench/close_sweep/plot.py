"""Hole closing on the validation split: Chamfer distance against holes per mesh, one point per
arm (from each arm's `meshflow eval generate --split val FLAGS -o FILE`; the `build` column says
which experimental build ran it, empty for the shipped code). Arms are lettered in the CSV's
order; the legend names them.

    python3 bench/close_sweep/plot.py [CSV [PNG]]

CSV defaults to the closing arms of commit 2aa87ed, 2026-11-25
(docs/experiments/data/2026-11-25-hole-closing/arms.csv); the attempts without folds of commit
0a07452, 2026-11-26, are docs/experiments/data/2026-11-26-hole-closing-alternatives/arms.csv.
PNG defaults to the CSV's name with .png, beside it.
"""
import csv
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]
DATA = ROOT / "docs" / "experiments" / "data"
CSV = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else DATA / "2026-11-25-hole-closing" / "arms.csv"
PNG = pathlib.Path(sys.argv[2]) if len(sys.argv) > 2 else CSV.with_suffix(".png")
ALTERNATIVES = CSV.resolve().parent.name == "2026-11-26-hole-closing-alternatives"
rows = list(csv.DictReader(open(CSV)))
fig, ax = plt.subplots(figsize=(11, 5))
for i, r in enumerate(rows):
    letter = chr(ord("A") + i)
    x, y = float(r["holes"]), float(r["chamfer_x100"])
    folds = "any fold" in r["arm"] or "deg" in r["arm"]
    shipped = "default" in r["arm"] or "shipped" in r["arm"]
    ax.scatter(x, y, s=60 if shipped else 30,
               marker="*" if shipped else ("x" if folds else "o"),
               label=f"{letter}: {r['arm']}")
    ax.annotate(letter, (x, y), textcoords="offset points", xytext=(4, 4), fontsize=8)
ax.axvline(1.5, color="grey", ls="--", lw=0.8)
ax.set_xlabel("holes per mesh (validation split, 226 meshes; dashed: issue 15's target)")
ax.set_ylabel("Chamfer distance x100")
ax.set_title("Closing the holes completion leaves (x: arms that accept folded faces)"
             if not ALTERNATIVES else "Fewer holes without folded faces: what each way costs")
ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
fig.tight_layout()
fig.savefig(PNG, dpi=110, bbox_inches="tight")
