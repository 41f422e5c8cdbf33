"""The refinement sweep of issue 15's holes (validation split, `meshflow eval generate --split
val FLAGS`; rows in refine.csv): Chamfer distance against holes per mesh, one point per arm.
`python3 bench/complete_sweep/plot_refine.py [CSV [PNG]]`: CSV defaults to
docs/experiments/data/2026-11-25-refined-completion/refine.csv, PNG to refine.png beside it."""
import csv
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

ROOT = Path(__file__).resolve().parents[2]
CSV = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "docs/experiments/data/2026-11-25-refined-completion/refine.csv"
PNG = Path(sys.argv[2]) if len(sys.argv) > 2 else CSV.with_name("refine.png")
rows = list(csv.DictReader(open(CSV)))
fig, ax = plt.subplots(figsize=(7, 4.5))
for r in rows:
    x, y = float(r["holes"]), float(r["cd_x100"])
    shipped = r["arm"] == "N"
    ax.scatter(x, y, s=60 if shipped else 30, color="C3" if shipped else "C0")
    ax.annotate(r["arm"], (x, y), textcoords="offset points", xytext=(5, 3), fontsize=9)
ax.set_xlabel("holes per mesh (validation, 226 meshes)")
ax.set_ylabel("CD x100")
ax.set_title("completion and refinement arms (A: before; N: the default)")
ax.grid(alpha=0.3)
fig.tight_layout()
fig.savefig(PNG, dpi=110)
