"""Tables and plot of docs/experiments/2026-12-07-hole-count.md: holes counted per fan of faces
(the surface split where it pinches) instead of by walking the rims, on the first 80
validation meshes (paired against main's build, every arm's holes in the new count) and the
hard-surface set at seeds 0 to 4, and on the test split.
    python3 analyse.py   (needs matplotlib)"""
import csv
import os
import sys

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, "..", "..", "..", "..", "bench"))
from paired import finish_paired_plot, load_rows, mean_of, mean_se, paired_rows  # noqa: E402

KEYS = ["cd", "nc", "ecd", "ef1", "faces", "holes", "boundary_edges", "sharpened"]
DIGITS = {"cd": 3, "nc": 4, "ecd": 2, "ef1": 4, "faces": 1, "holes": 3, "boundary_edges": 1, "sharpened": 3}
ARMS = {
    "main": "277bea2: holes counted by walking the rims, everywhere",
    "fan_everywhere": "holes counted per fan, everywhere (the choice too)",
    "shipped": "holes counted per fan; the choice counts rim loops (shipped)",
}
rows = {arm: load_rows(os.path.join(here, f"val80_{arm}.per_mesh.csv"), KEYS) for arm in ARMS}

print("First 80 validation meshes: means (holes of every arm counted per fan; sharpened: share of")
print("meshes whose sharpening was accepted), then per-mesh differences from main (mean ± s.e.)")
print("| arm | " + " | ".join(KEYS) + " |")
print("|---|" + "---:|" * len(KEYS))
for arm in ARMS:
    print(f"| {arm} | " + " | ".join(f"{mean_of(rows[arm], k):.{DIGITS[k]}f}" for k in KEYS) + " |")
    if arm != "main":
        cells = [f"{m:+.{DIGITS[k]}f} ± {se:.{DIGITS[k]}f}" for k in KEYS
                 for m, se in [paired_rows(rows[arm], rows["main"], k)]]
        print(f"| {arm} vs main | " + " | ".join(cells) + " |")
main_walk = load_rows(os.path.join(here, "val80_main.per_mesh.csv"), ["holes", "rim_loops"])
walk = [r["rim_loops"] for r in main_walk.values()]
print(f"\nmain's own report (rims walked): {sum(walk) / len(walk):.3f} holes a mesh; the same meshes per fan "
      f"{mean_of(rows['main'], 'holes'):.3f}; meshes where the two differ: "
      f"{sum(r['rim_loops'] != r['holes'] for r in main_walk.values())}")

# The test split (244 meshes, `meshflow eval generate --split test`): main's meshes recounted
# per fan, the shipped build's run (bench/sharpen_eval/test_sharpened.json compacts it).
test = {arm: load_rows(os.path.join(here, f"test_{arm}.per_mesh.csv"), KEYS) for arm in ["main", "shipped"]}
print("\nTest split, 244 meshes: means, then the shipped build's per-mesh differences from main")
print("| arm | " + " | ".join(KEYS) + " |")
print("|---|" + "---:|" * len(KEYS))
for arm in test:
    print(f"| {arm} | " + " | ".join(f"{mean_of(test[arm], k):.{DIGITS[k]}f}" for k in KEYS) + " |")
print("| shipped vs main | " + " | ".join(
    f"{m:+.{DIGITS[k]}f} ± {se:.{DIGITS[k]}f}" for k in KEYS for m, se in [paired_rows(test["shipped"], test["main"], k)]) + " |")
test_walk = load_rows(os.path.join(here, "test_main.per_mesh.csv"), ["rim_loops"])
print(f"main's own report (rims walked): {sum(r['rim_loops'] for r in test_walk.values()) / len(test_walk):.3f} holes a mesh")

hs = list(csv.DictReader(open(os.path.join(here, "hard_surface.csv"))))
print("\nHard-surface set, seeds 0 to 4: means over shapes and seeds; differences from main by shape and seed")
print("| input | arm | CD x100 | NC | EF1 | faces / gt | holes | boundary edges | CD vs main | holes vs main | boundary edges vs main |")
print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
for inp in ["clean", "noise1"]:
    main = {(r["seed"], r["shape"]): r for r in hs if r["arm"] == "main" and r["input"] == inp}
    for arm in ARMS:
        rs = [r for r in hs if r["arm"] == arm and r["input"] == inp]
        m = {k: sum(float(r[k]) for r in rs) / len(rs) for k in ["cd", "nc", "ef1", "holes", "boundary_edges"]}
        ratio = sum(float(r["faces"]) / float(r["gt_faces"]) for r in rs) / len(rs)
        diffs = ["", "", ""] if arm == "main" else [
            "{:+.3f} ± {:.3f}".format(*mean_se([float(r[k]) - float(main[(r["seed"], r["shape"])][k]) for r in rs]))
            for k in ["cd", "holes", "boundary_edges"]]
        print(f"| {inp} | {arm} | {m['cd']:.3f} | {m['nc']:.3f} | {m['ef1']:.3f} | {ratio:.2f}x | {m['holes']:.2f} | "
              f"{m['boundary_edges']:.1f} | " + " | ".join(diffs) + " |")

# One plot: the paired changes from main on the validation meshes, per arm.
import matplotlib  # noqa: E402
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

shown = [("cd", "CD x100", 1.0), ("nc", "NC x10", 10.0), ("faces", "faces / 10", 0.1),
         ("holes", "holes", 1.0), ("boundary_edges", "boundary edges / 10", 0.1)]
fig, ax = plt.subplots(figsize=(7.2, 4.2))
width = 0.38
for i, arm in enumerate(["fan_everywhere", "shipped"]):
    ms = [paired_rows(rows[arm], rows["main"], k) for k, _, _ in shown]
    xs = [j + (i - 0.5) * width for j in range(len(shown))]
    ax.bar(xs, [m * s for (m, _), (_, _, s) in zip(ms, shown)], width,
           yerr=[se * s for (_, se), (_, _, s) in zip(ms, shown)], label=arm, capsize=3)
ax.set_xticks(range(len(shown)))
ax.set_xticklabels([label for _, label, _ in shown])
ax.legend()
finish_paired_plot(fig, ax, "measure (scaled to share an axis)", "change from main, per mesh (mean ± s.e.)",
                   "Holes per fan: 80 validation meshes against 277bea2", os.path.join(here, "hole_count.png"),
                   x_zero=False)
