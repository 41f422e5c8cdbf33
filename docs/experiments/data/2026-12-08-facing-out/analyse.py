"""Tables of docs/experiments/2026-12-08-facing-out.md: generated meshes turned to face out
(`geometry::orient::orient_outward`), on the first 80 validation meshes (paired against
main's build), the test split (against main's run, bench/sharpen_eval/test_sharpened.json as
63f6cf4 has it) and the hard-surface set at seeds 0 to 9, clean and with 1% noise; how each
mesh faces against its ground truth (bench/facing/facing.py).
    python3 analyse.py"""
import csv
import os
import sys

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, "..", "..", "..", "..", "bench"))
from paired import load_rows, mean_of, paired_rows  # noqa: E402

KEYS = ["cd", "nc", "ecd", "ef1", "faces", "holes"]
DIGITS = {"cd": 3, "nc": 4, "ecd": 2, "ef1": 4, "faces": 1, "holes": 3}


def table(title, split):
    rows = {arm: load_rows(os.path.join(here, f"{split}_{arm}.per_mesh.csv"), KEYS) for arm in ("main", "shipped")}
    print(title)
    print("| arm | " + " | ".join(KEYS) + " |")
    print("|---|" + "---:|" * len(KEYS))
    for arm in rows:
        print(f"| {arm} | " + " | ".join(f"{mean_of(rows[arm], k):.{DIGITS[k]}f}" for k in KEYS) + " |")
    cells = [f"{m:+.{DIGITS[k]}f} ± {se:.{DIGITS[k]}f}" for k in KEYS
             for m, se in [paired_rows(rows["shipped"], rows["main"], k)]]
    print("| shipped - main | " + " | ".join(cells) + " |")
    changed = sum(abs(rows["shipped"][n]["cd"] - rows["main"][n]["cd"]) > 1e-9 for n in rows["main"]
                  if rows["main"][n]["cd"] is not None and rows["shipped"][n]["cd"] is not None)
    print(f"meshes whose figures changed: {changed} of {len(rows['main'])}\n")


def facing(name):
    rows = list(csv.DictReader(open(os.path.join(here, name))))
    out = [float(r["facing_gt_out"]) for r in rows]
    closed = [float(r["facing_gt_out"]) for r in rows if r["gt_closed"] == "1"]
    count = lambda v: (sum(x < -0.2 for x in v), sum(x > 0.2 for x in v), sum(-0.2 <= x <= 0.2 for x in v))
    return count(out), count(closed), len(rows), len(closed)


table("First 80 validation meshes: means, then shipped minus main per mesh (mean ± s.e.)", "val80")
table("Test split (244 meshes): the same", "test")

print("How the meshes face against their ground truth (bench/facing/facing.py; the mean cosine times the")
print("sign of the ground truth's volume): inside out (< -0.2) / out (> 0.2) / between, all meshes and the")
print("meshes whose ground truth is closed (watertight, as trimesh reads it)")
print("| run | all: in / out / between | closed ground truth: in / out / between |")
print("|---|---|---|")
for name, label in [("val80_main", "validation 80, main"), ("val80_shipped", "validation 80, shipped"),
                    ("test_main", "test split, main"), ("test_shipped", "test split, shipped")]:
    a, c, n, nc = facing(f"{name}.facing.csv")
    print(f"| {label} | {a[0]} / {a[1]} / {a[2]} of {n} | {c[0]} / {c[1]} / {c[2]} of {nc} |")

rows = list(csv.DictReader(open(os.path.join(here, "hard_surface.csv"))))
print("\nHard-surface set, seeds 0 to 9 (80 meshes an arm and input): means, and meshes whose signed")
print("volume about their centroid is negative (inside out)")
print("| input | arm | CD x100 | NC | ECD x100 | EF1 | faces | holes | inside out |")
print("|---|---|---:|---:|---:|---:|---:|---:|---|")
for inp in ("clean", "noise1"):
    for arm in ("main", "shipped"):
        r = [x for x in rows if x["arm"] == arm and x["input"] == inp]
        mean = lambda k: sum(float(x[k]) for x in r if x[k]) / sum(1 for x in r if x[k])
        inside = [f"{x['shape']} ({x['seed']})" for x in r if float(x["volume_about_centre"]) < 0]
        print(f"| {inp} | {arm} | {mean('cd'):.3f} | {mean('nc'):.4f} | {mean('ecd'):.2f} | {mean('ef1'):.4f} | "
              f"{mean('faces'):.1f} | {mean('holes'):.3f} | {len(inside)}: {', '.join(inside) or '-'} |")
