"""Removing the vertices a flat face does not need at the end of sharpening: the tables and the
plot of docs/experiments/2026-12-07-redundant-vertices.md from the files beside this file.
    python3 analyse.py [DIR]"""
import csv
import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../../../bench"))
from paired import compact_changes, finish_paired_plot, hard_surface_table, json_at  # noqa: E402

here = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
# base: 8fce4f2 (the shipped pipeline). removed: the same with remove_redundant_vertices on the
# kept round of sharpening (a quarter of a point spacing).
ARMS = ["base", "removed"]
rows = list(csv.DictReader(open(os.path.join(here, "hard_surface.csv"))))
hard_surface_table(rows, ARMS)

print("\nPer shape: faces at seeds 0, 2, 3 (base -> removed) and the vertices removed")
print("| shape | clean | removed | 1% noise | removed |")
print("|---|---|---:|---|---:|")
for shape in sorted({r["shape"] for r in rows}):
    cells = []
    for inp in ["clean", "noise1"]:
        per_arm = {arm: sorted((r for r in rows if r["arm"] == arm and r["input"] == inp and r["shape"] == shape),
                               key=lambda r: r["seed"]) for arm in ARMS}
        cells.append(", ".join(f"{a['faces']} -> {b['faces']}" if a["faces"] != b["faces"] else a["faces"]
                               for a, b in zip(per_arm["base"], per_arm["removed"])))
        cells.append(str(sum(int(r["removed"]) for r in per_arm["removed"])))
    print(f"| {shape} | " + " | ".join(cells) + " |")

# The clean test split: removed (this folder's test_removed_sharpened.json) against the shipped
# run at 98154af (read from git), per mesh; both compacted by bench/sharpen_eval/compact.py, both
# on the 2-core AMD EPYC VM.
shipped = {m["name"]: m for m in json_at("98154af", "bench/sharpen_eval/test_sharpened.json")["per_mesh"]}
removed = {m["name"]: m for m in json.load(open(os.path.join(here, "test_removed_sharpened.json")))["per_mesh"]}
changed = compact_changes(shipped, removed, "Test split, clean: removed against the shipped run")

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    sys.exit(0)
# One plot: per test mesh that changes, the faces taken off against the change of its CD (which
# the removal leaves but for the samples' positions on the new faces).
fig, ax = plt.subplots(figsize=(6, 4))
x = [removed[n]["faces"] - shipped[n]["faces"] for n in changed]
y = [removed[n]["cd_x100"] - shipped[n]["cd_x100"] for n in changed]
ax.plot(x, y, "o", ms=3, alpha=0.6)
finish_paired_plot(fig, ax, "faces, removed minus shipped", "CD x100, removed minus shipped",
                   f"Test split, the {len(changed)} meshes that change", os.path.join(here, "redundant_vertices.png"))
