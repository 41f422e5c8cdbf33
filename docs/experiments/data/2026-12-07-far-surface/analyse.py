"""Far-surface collapses and where the edge F-score is lost: the tables and the plot of
docs/experiments/2026-12-07-far-surface.md from the files beside this file.
    python3 analyse.py [DIR]"""
import csv
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../../../bench"))
from paired import SURFACE_KEYS, arm_row, hard_surface_table, load_rows  # noqa: E402

here = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))

# base: fce0d0b as shipped. far2 / far3: a vertex more than 2 (3) point spacings from every
# input point may collapse with its faces turned by up to 154 (120) degrees, where the faces
# around it come no farther from the input planes (trial.patch, MESHFLOW_FAR=2,-0.9 / 3,-0.5).
# agree2: far2, and the faces around it also agree with the input's planes at least as well.
ARMS = ["base", "far2", "far3", "agree2"]
runs = {arm: load_rows(os.path.join(here, f"val_{arm}.per_mesh.csv"), SURFACE_KEYS) for arm in ARMS}
print("Validation split (226 meshes), means, then paired differences from base (mean ± s.e.)")
print("| arm | CD x100 | NC | ECD x100 | EF1 | faces | holes | CD | NC | EF1 | faces |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for arm in ARMS:
    print(arm_row(arm, runs[arm], None if arm == "base" else runs["base"], ["cd", "nc", "ef1", "faces"]))
print()
hard_surface_table(list(csv.DictReader(open(os.path.join(here, "hard_surface.csv")))), ["base", "far2", "agree2"])


def crease_table(path, keep=None):
    rows = [r for r in csv.DictReader(open(path)) if keep is None or r["mesh"] in keep]
    mean = lambda k: sum(float(r[k]) for r in rows) / len(rows)  # noqa: E731
    total = lambda k: sum(float(r[k]) for r in rows)  # noqa: E731
    return rows, mean, total


# The meshes with sharp edges on both sides differ a little between the methods: ours on
# those Poisson + QEM has too.
poisson = crease_table(os.path.join(here, "crease_loss_poisson.csv"))
tables = {"ours": crease_table(os.path.join(here, "crease_loss.csv"), {r["mesh"] for r in poisson[0]}),
          "Poisson + QEM": poisson}
print("\nValidation split: sharp-edge samples by distance to the other mesh's sharp edges (share, mean over "
      "meshes with sharp edges on both sides, their count in brackets; 0.01 of the box is EF1's threshold)")
print("| mesh | side | < 0.01 | 0.01-0.02 | 0.02-0.04 | >= 0.04 | of which the other surface is there |")
print("|---|---|---:|---:|---:|---:|---:|")
for name, (rows, mean, total) in tables.items():
    print(f"| {name} ({len(rows)}) | its edges (precision) | " + " | ".join(f"{mean(k):.3f}" for k in ["p_01", "p_02", "p_04", "p_far", "p_far_on_gt"]) + " |")
    print(f"| {name} | the ground truth's (recall) | " + " | ".join(f"{mean(k):.3f}" for k in ["r_01", "r_02", "r_04", "r_far", "r_far_on_ours"]) + " |")
print("\nSharp length by dihedral angle (share of all), and recall at 0.01 per band (each mesh by its samples there)")
print("| | 30-45 | 45-60 | 60-90 | 90-120 | 120-180 |")
print("|---|---:|---:|---:|---:|---:|")
bands = ["30", "45", "60", "90", "120"]
rows, mean, total = tables["ours"]
gt = [total(f"gt_len_{b}") for b in bands]
print("| ground truth | " + " | ".join(f"{g / sum(gt):.3f}" for g in gt) + " |")
for name, (rows, mean, total) in tables.items():
    ours = [total(f"our_len_{b}") for b in bands]
    print(f"| {name} | " + " | ".join(f"{o / sum(ours):.3f}" for o in ours) + " |")
    rec = []
    for b in bands:
        # Each mesh weighs by its share of sharp length in the band (its samples there), as
        # EF1 weighs every mesh alike.
        w = [(float(r[f"gt_len_{b}"]) / float(r["gt_length"]), float(r[f"gt_hit_{b}"])) for r in rows if r[f"gt_hit_{b}"]]
        rec.append(sum(a * h for a, h in w) / sum(a for a, _ in w))
    print(f"| {name}: recall | " + " | ".join(f"{x:.3f}" for x in rec) + " |")
print("\nEach method's sharp length by where its ends and midpoint lie (within 0.01 of the ground truth's sharp edges)")
print("| mesh | both ends and the midpoint | both ends, not the midpoint | one end | neither end | surface > 3 / > 5 spacings from the input |")
print("|---|---:|---:|---:|---:|---:|")
for name, (rows, mean, total) in tables.items():
    cats = [total(k) for k in ["len_both_ends_mid_on", "len_both_ends_mid_off", "len_one_end", "len_no_end"]]
    print(f"| {name} | " + " | ".join(f"{c / sum(cats):.3f}" for c in cats)
          + f" | {mean('area_far3'):.3f} / {mean('area_far5'):.3f} |")
medians = sorted(float(r["r_miss_to_ours_median"]) for r in tables["ours"][0] if r["r_miss_to_ours_median"])
print(f"\nA ground-truth crease sample found 0.01-0.04 off: the median of its meshes' median distances to our "
      f"surface {medians[len(medians) // 2]:.4f}")
for name, (rows, mean, total) in tables.items():
    share = lambda k: sum(float(r[k]) for r in rows if r[k]) / sum(1 for r in rows if r[k])  # noqa: E731
    print(f"{name}: ground-truth crease samples with another crease within three spacings: found (< 0.01) "
          f"{share('hit_near_other'):.3f}, missed (0.01-0.04) {share('miss_near_other'):.3f}")

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    sys.exit(0)
# One plot: the distance bands of both sides, ours beside Poisson + QEM.
fig, axes = plt.subplots(1, 2, figsize=(9, 3.6), sharey=True)
labels = ["< 0.01", "0.01-0.02", "0.02-0.04", ">= 0.04"]
for ax, (side, keys) in zip(axes, [("our sharp edges to the ground truth's (precision)", ["p_01", "p_02", "p_04", "p_far"]),
                                   ("the ground truth's to ours (recall)", ["r_01", "r_02", "r_04", "r_far"])]):
    for j, (name, (rows, mean, total)) in enumerate(tables.items()):
        ax.bar([i + 0.4 * j for i in range(4)], [mean(k) for k in keys], width=0.4, label=name)
    ax.set_xticks([i + 0.2 for i in range(4)], labels)
    ax.set_title(side, fontsize=9)
    ax.set_xlabel("distance, share of the box")
axes[0].set_ylabel("share of edge samples")
axes[0].legend()
fig.tight_layout()
fig.savefig(os.path.join(here, "crease_loss.png"), dpi=110)
