"""Candidate seeds derived from the seed and the candidate's index instead of seed + j: the
tables and the plot of docs/experiments/2026-12-07-candidate-seeds.md from the files beside
this file.
    python3 analyse.py [DIR]"""
import csv
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../../../bench"))
from paired import compact_changes, diff_cells, load_rows, mean_cells, mean_se, SURFACE_KEYS  # noqa: E402

here = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../../..")
# old: 45d159b (candidate j of input k of n seeded by seed + k + j n). new: the same tree with
# candidate_seed (candidate j of input k seeded by Rng::derived(seed + k, j), the first by seed + k).
ARMS = ["old", "new"]

# 1. `meshflow generate FILE --seed S` for S = 0..9: how many different meshes ten seeds give.
cli = list(csv.DictReader(open(os.path.join(here, "cli_seeds.csv"))))
shapes = list(dict.fromkeys(r["shape"] for r in cli))
print("`meshflow generate tests/fixtures/hard_surface/points/SHAPE.ply --seed S`, S = 0..9: faces per seed")
print("| shape | old | different meshes | new | different meshes |")
print("|---|---|---:|---|---:|")
for shape in shapes:
    rs = sorted((r for r in cli if r["shape"] == shape), key=lambda r: int(r["seed"]))
    cells = []
    for arm in ARMS:
        cells.append(", ".join(r[f"{arm}_faces"] + ("+h" * int(r[f"{arm}_holes"])) for r in rs))
        cells.append(str(len({r[f"{arm}_glb_md5"] for r in rs})))
    print(f"| {shape} | " + " | ".join(cells) + " |")

# 2. The hard-surface set (`meshflow eval generate --input tests/fixtures/hard_surface [--noise
# 0.01] --seed S`), S = 0..9: means over its 8 shapes and 10 seeds, and new minus old per shape
# and seed.
hs = list(csv.DictReader(open(os.path.join(here, "hard_surface.csv"))))
KEYS = ["cd", "nc", "ecd", "ef1", "faces", "holes"]


def value(r, key):
    return float(r[key]) / float(r["gt_faces"]) if key == "faces" else float(r[key])


print("\nHard-surface set, 8 shapes x 10 seeds: means (faces as a multiple of the ground truth's)"
      " and new minus old (paired by shape and seed, mean ± s.e.)")
print("| input | arm | CD x100 | NC | ECD x100 | EF1 | faces / gt | holes |")
print("|---|---|---:|---:|---:|---:|---:|---:|")
for inp, label in [("clean", "clean"), ("noise1", "1% noise")]:
    by = {arm: {(r["shape"], r["seed"]): r for r in hs if r["arm"] == arm and r["input"] == inp} for arm in ARMS}
    for arm in ARMS:
        cells = [f"{sum(value(r, k) for r in by[arm].values()) / len(by[arm]):.3f}" for k in KEYS]
        print(f"| {label} | {arm} | " + " | ".join(cells) + " |")
    cells = []
    for k in KEYS:
        m, se = mean_se([value(by["new"][x], k) - value(by["old"][x], k) for x in by["old"]])
        cells.append(f"{m:+.3f} ± {se:.3f}")
    print(f"| {label} | new - old | " + " | ".join(cells) + " |")

print("\nPer shape, clean: seeds of 10 at the ground truth's face count, then mean EF1 (old / new)")
print("| shape | gt faces | old | new | EF1 old | EF1 new |")
print("|---|---:|---:|---:|---:|---:|")
for shape in dict.fromkeys(r["shape"] for r in hs):
    rs = {arm: [r for r in hs if r["arm"] == arm and r["input"] == "clean" and r["shape"] == shape] for arm in ARMS}
    gt = rs["old"][0]["gt_faces"]
    exact = [sum(r["faces"] == r["gt_faces"] for r in rs[arm]) for arm in ARMS]
    ef1 = [sum(float(r["ef1"]) for r in rs[arm]) / len(rs[arm]) for arm in ARMS]
    print(f"| {shape} | {gt} | {exact[0]} | {exact[1]} | {ef1[0]:.3f} | {ef1[1]:.3f} |")

# Seeds that share candidates under the old rule: input k of the 8 at seed S drew seeds
# S + k + 8 j, so seed 8 drew 11 of seed 0's 12 candidates (and 9 of 1's).
print("\nShapes whose mesh (faces and CD) at seed 8 (9) is the one at seed 0 (1)")
for arm in ARMS:
    for inp in ["clean", "noise1"]:
        for a, b in [("0", "8"), ("1", "9")]:
            at = {s: {r["shape"]: (r["faces"], r["cd"]) for r in hs
                      if r["arm"] == arm and r["input"] == inp and r["seed"] == s} for s in (a, b)}
            same = [shape for shape in at[a] if at[a][shape] == at[b][shape]]
            print(f"{arm}, {inp}, seeds {a} and {b}: {len(same)} of 8")

# 3. The validation split (226 meshes): new against old, per mesh. Old is the base arm of the
# far-surface entry (fce0d0b's build, the same pipeline as 45d159b's).
val = {"old": os.path.join(here, "../2026-12-07-far-surface/val_base.per_mesh.csv"),
       "new": os.path.join(here, "val_new.per_mesh.csv")}
if all(os.path.exists(p) for p in val.values()):
    rows = {arm: load_rows(p, SURFACE_KEYS) for arm, p in val.items()}
    print("\nValidation split: means, then new minus old per mesh (mean ± s.e.)")
    print("| arm | CD x100 | NC | ECD x100 | EF1 | faces | holes |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for arm in ARMS:
        print(f"| {arm} | " + " | ".join(mean_cells(rows[arm])) + " |")
    print("| new - old | " + " | ".join(diff_cells(rows["new"], rows["old"], SURFACE_KEYS)) + " |")

# 4. The test split with Poisson + QEM at our face counts (bench/sharpen_eval/run_test.sh,
# compacted by compact.py), clean, with 1% noise and with 30% missing: new (this folder)
# against the shipped runs at 45d159b (read from git).
for prefix, label in [("test", "clean"), ("test_noise1", "1% noise"), ("test_missing30", "30% missing")]:
    new_test = os.path.join(here, f"{prefix}_sharpened.json")
    if not os.path.exists(new_test):
        continue
    old_json = subprocess.run(["git", "-C", root, "show", f"45d159b:bench/sharpen_eval/{prefix}_sharpened.json"],
                              capture_output=True, text=True, check=True).stdout
    old = {m["name"]: m for m in json.loads(old_json)["per_mesh"]}
    new = {m["name"]: m for m in json.load(open(new_test))["per_mesh"]}
    compact_changes(old, new, f"Test split, {label}: new minus old")

# The plot: faces per seed from `meshflow generate` (left) and the hard-surface set's clean
# faces per seed (right), old dashed, new solid.
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

fig, axes = plt.subplots(1, 2, figsize=(11, 4))
for shape in shapes:
    rs = sorted((r for r in cli if r["shape"] == shape), key=lambda r: int(r["seed"]))
    seeds = [int(r["seed"]) for r in rs]
    line, = axes[0].plot(seeds, [int(r["new_faces"]) for r in rs], "o-", label=f"{shape}, new")
    axes[0].plot(seeds, [int(r["old_faces"]) for r in rs], "s--", color=line.get_color(), alpha=0.6,
                 label=f"{shape}, old")
axes[0].set_xlabel("--seed")
axes[0].set_ylabel("faces")
axes[0].set_title("meshflow generate on one shape, per seed")
axes[0].legend(fontsize=7, ncol=2)
for shape in dict.fromkeys(r["shape"] for r in hs):
    rs = {arm: sorted((r for r in hs if r["arm"] == arm and r["input"] == "clean" and r["shape"] == shape),
                      key=lambda r: int(r["seed"])) for arm in ARMS}
    line, = axes[1].plot([int(r["seed"]) for r in rs["new"]],
                         [int(r["faces"]) / int(r["gt_faces"]) for r in rs["new"]], "o-", label=shape)
    axes[1].plot([int(r["seed"]) for r in rs["old"]], [int(r["faces"]) / int(r["gt_faces"]) for r in rs["old"]],
                 "s--", color=line.get_color(), alpha=0.5)
axes[1].set_yscale("log")
axes[1].set_xlabel("--seed")
axes[1].set_ylabel("faces / ground truth's (log)")
axes[1].set_title("eval generate, hard-surface set, clean (old dashed)")
axes[1].legend(fontsize=7, ncol=2)
fig.tight_layout()
fig.savefig(os.path.join(here, "candidate_seeds.png"), dpi=110)
