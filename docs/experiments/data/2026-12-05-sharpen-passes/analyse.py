"""Sharpening passes sweep: one table and one plot from `meshflow eval generate` JSONs.

    python3 analyse.py DIR     # DIR holds val_pN.json and hs_pN.json for each arm N

Per arm: the validation split's means (CD, NC, ECD, EF1, faces / gt, holes, the fit stage's
mean time) and, against the 8-pass arm (the default), the paired per-mesh difference of CD and EF1 with its
standard error (the same meshes and seeds in every arm, so the pairing removes the meshes'
own spread); then the hard-surface set's means. Writes passes.md and passes.png beside it.
"""
import json
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

src = pathlib.Path(sys.argv[1])
here = pathlib.Path(__file__).parent
sys.path.insert(0, str(here.parents[3] / "bench"))
from paired import paired  # noqa: E402  (bench/paired.py)
arms = sorted(int(p.stem[5:]) for p in src.glob("val_p*.json"))
KEYS = [
    ("chamfer_x100", "CD x100", 3),
    ("normal_consistency", "NC", 4),
    ("edge_chamfer_x100", "ECD x100", 2),
    ("edge_f_score", "EF1", 3),
    ("faces_ratio", "faces / gt", 2),
    ("holes", "holes", 2),
]


def load(name):
    return json.loads((src / name).read_text())


val = {p: load(f"val_p{p}.json") for p in arms}
hs = {p: load(f"hs_p{p}.json") for p in arms if (src / f"hs_p{p}.json").exists()}
ref = val[8] if 8 in val else val[max(arms)]  # the shipped default
lines = ["| passes | " + " | ".join(k[1] for k in KEYS)
         + " | fit stage (mean per mesh) | CD vs 8 (paired) | EF1 vs 8 (paired) |",
         "|---:|" + "---:|" * (len(KEYS) + 3)]
for p in arms:
    o = val[p]["all"]["ours"]
    cd = paired(val[p], ref, "chamfer_x100")
    ef = paired(val[p], ref, "edge_f_score")
    lines.append(f"| {p} | " + " | ".join(f"{o[k]:.{d}f}" for k, _, d in KEYS)
                 + f" | {val[p]['mean_times']['fit_s']:.3f} s"
                 + f" | {cd[0]:+.3f} ± {cd[1]:.3f} | {ef[0]:+.4f} ± {ef[1]:.4f} |")
lines += ["", "| hard-surface set, passes | " + " | ".join(k[1] for k in KEYS) + " |",
          "|---:|" + "---:|" * len(KEYS)]
for p, h in sorted(hs.items()):
    o = h["all"]["ours"]
    lines.append(f"| {p} | " + " | ".join(f"{o[k]:.{d}f}" for k, _, d in KEYS) + " |")
(here / "passes.md").write_text("\n".join(lines) + "\n")
print("\n".join(lines))

fig, axes = plt.subplots(1, 6, figsize=(21, 3.4))
for ax, (key, label, _) in zip(axes, KEYS[:5] + [("fit_s", "fit stage, s", 3)]):
    ys = [val[p]["mean_times"]["fit_s"] if key == "fit_s" else val[p]["all"]["ours"][key]
          for p in arms]
    ax.plot(arms, ys, "o-", label="validation (226)")
    if key != "fit_s" and hs:
        ax2 = ax.twinx()
        ax2.plot(sorted(hs), [hs[p]["all"]["ours"][key] for p in sorted(hs)], "s--",
                 color="tab:orange", label="hard-surface (8)")
        ax2.tick_params(axis="y", colors="tab:orange")
    ax.set_xlabel("sharpening passes")
    ax.set_title(label)
    ax.set_xticks(arms)
axes[0].legend(loc="best", fontsize=8)
fig.suptitle("Sharpening passes: validation split (blue, left axis) and hard-surface set "
             "(orange, right axis)")
fig.tight_layout()
fig.savefig(here / "passes.png", dpi=110)
