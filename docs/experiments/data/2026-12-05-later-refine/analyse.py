"""Splits in sharpening's later rounds: one table and one plot from `meshflow eval generate`
JSONs.

    python3 analyse.py DIR     # DIR holds val_ARM.json (and hs_ARM.json) per arm,
                               # ARM = pN_lrK: N passes, K splits in each round after the first

Per arm: the validation split's means (CD, NC, ECD, EF1, faces / gt, holes, the fit stage's
mean time) and, against the shipped arm (p8_lr2), the paired per-mesh differences of CD, NC
and EF1 with their standard errors (the same meshes, seeds and candidates in every arm, so the
pairing removes the meshes' own spread); then the hard-surface set's means. Writes
later_refine.md and later_refine.png beside this script: each measure against the fit stage's
time, one point per arm.
"""
import json
import pathlib
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

src = pathlib.Path(sys.argv[1])
here = pathlib.Path(__file__).parent
sys.path.insert(0, str(here.parents[3] / "bench"))
from paired import paired  # noqa: E402  (bench/paired.py)
SHIPPED = "p8_lr2"
KEYS = [
    ("chamfer_x100", "CD x100", 3),
    ("normal_consistency", "NC", 4),
    ("edge_chamfer_x100", "ECD x100", 2),
    ("edge_f_score", "EF1", 3),
    ("faces_ratio", "faces / gt", 2),
    ("holes", "holes", 2),
]


def order(arm):
    passes, later = map(int, re.fullmatch(r"p(\d+)_lr(\d+)", arm).groups())
    return (later, passes)


def load(name):
    return json.loads((src / name).read_text())


arms = sorted((p.stem[4:] for p in src.glob("val_p*_lr*.json")), key=order)
val = {a: load(f"val_{a}.json") for a in arms}
hs = {a: load(f"hs_{a}.json") for a in sorted((p.stem[3:] for p in src.glob("hs_p*_lr*.json")), key=order)}
ref = val[SHIPPED]
lines = ["| arm (passes, later splits) | " + " | ".join(k[1] for k in KEYS)
         + " | fit stage (mean per mesh) | CD vs shipped | NC vs shipped | EF1 vs shipped |",
         "|---|" + "---:|" * (len(KEYS) + 4)]
for a in arms:
    o = val[a]["all"]["ours"]
    diffs = [paired(val[a], ref, k) for k in ("chamfer_x100", "normal_consistency", "edge_f_score")]
    lines.append(f"| {a} | " + " | ".join(f"{o[k]:.{d}f}" for k, _, d in KEYS)
                 + f" | {val[a]['mean_times']['fit_s']:.3f} s | "
                 + " | ".join(f"{m:+.4f} ± {s:.4f}" for m, s in diffs) + " |")
lines += ["", "| hard-surface set | " + " | ".join(k[1] for k in KEYS) + " | fit stage |",
          "|---|" + "---:|" * (len(KEYS) + 1)]
for a, h in hs.items():
    o = h["all"]["ours"]
    lines.append(f"| {a} | " + " | ".join(f"{o[k]:.{d}f}" for k, _, d in KEYS)
                 + f" | {h['mean_times']['fit_s']:.3f} s |")
(here / "later_refine.md").write_text("\n".join(lines) + "\n")
print("\n".join(lines))

fig, axes = plt.subplots(1, 5, figsize=(19, 3.6))
for ax, (key, label, _) in zip(axes, KEYS[:5]):
    for a in arms:
        x = val[a]["mean_times"]["fit_s"]
        y = val[a]["all"]["ours"][key]
        ax.plot([x], [y], "o", color="C0" if a.endswith("lr2") else "C1")
        ax.annotate(a, (x, y), fontsize=7, xytext=(3, 3), textcoords="offset points")
    ax.set_xlabel("fit stage per mesh, s (validation)")
    ax.set_title(label)
fig.suptitle("validation split (226 meshes): blue = every round split twice (shipped: p8_lr2), "
             "orange = later rounds split once or not at all", fontsize=9)
fig.tight_layout()
fig.savefig(here / "later_refine.png", dpi=110)
