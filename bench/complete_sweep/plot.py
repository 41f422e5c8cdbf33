#!/usr/bin/env python3
"""Table and plot of the surface-completion settings sweep on the validation split.

Each arm is one `meshflow eval generate --split val FLAGS -o ARM.json` (the flags are in
ARMS below; 226 meshes, the shipped pair, default budget rule, 28 steps). Reads the JSONs
from DIR, writes sweep.md (the table) and sweep.png (Chamfer distance against holes per
mesh, one point per arm, sized by faces) into OUT (default: the experiment's data folder,
docs/experiments/data/2026-11-25-fit-and-complete/).

Usage: python3 bench/complete_sweep/plot.py DIR [OUT]
"""

import json
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ARMS = {
    "H": "no fit, no completion, no overlap test (the extraction alone)",
    "G": "fit, no completion, overlap 0.5",
    "A": "fit + completion: overlap 0.2, gap 6",
    "B": "fit + completion: overlap 0.5, gap 6",
    "C": "fit + completion: overlap 1.0, gap 6",
    "D": "fit + completion: overlap 0.5, gap 4.5",
    "E": "fit + completion: overlap 0.5, gap 8",
    "I": "fit + completion: overlap 0.5, gap 6, max edge 4",
    "F": "fit + completion: overlap 0.5, gap 6, weld 0.25 (default)",
}
FLAGS = {
    "H": "--overlap-tolerance 0 --no-complete --no-fit",
    "G": "--overlap-tolerance 0.5 --no-complete",
    "A": "--overlap-tolerance 0.2 --complete-max-gap 6 --complete-weld 0",
    "B": "--overlap-tolerance 0.5 --complete-max-gap 6 --complete-weld 0",
    "C": "--overlap-tolerance 1.0 --complete-max-gap 6 --complete-weld 0",
    "D": "--overlap-tolerance 0.5 --complete-max-gap 4.5 --complete-weld 0",
    "E": "--overlap-tolerance 0.5 --complete-max-gap 8 --complete-weld 0",
    "I": "--overlap-tolerance 0.5 --complete-max-gap 6 --complete-max-edge 4 --complete-weld 0",
    "F": "--overlap-tolerance 0.5 --complete-max-gap 6 --complete-weld 0.25",
}


def main() -> int:
    src = pathlib.Path(sys.argv[1])
    root = pathlib.Path(__file__).resolve().parents[2]
    here = (pathlib.Path(sys.argv[2]) if len(sys.argv) > 2
            else root / "docs" / "experiments" / "data" / "2026-11-25-fit-and-complete")
    rows = []
    for arm, what in ARMS.items():
        r = json.loads((src / f"sw_{arm}.json").read_text())
        o = r["all"]["ours"]
        rows.append((arm, what, FLAGS[arm], o))
    lines = [
        "| arm | setting | flags | CD x100 | HD x100 | faces | holes | components | no faces |",
        "|---|---|---|---:|---:|---:|---:|---:|---:|",
    ]
    for arm, what, flags, o in rows:
        lines.append(
            f"| {arm} | {what} | `{flags}` | {o['chamfer_x100']:.2f} | {o['hausdorff_x100']:.2f} | "
            f"{o['faces_out']:.1f} | {o['holes']:.2f} | {o['components']:.2f} | {o['no_faces']} |"
        )
    (here / "sweep.md").write_text("\n".join(lines) + "\n")
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for arm, what, _, o in rows:
        ax.scatter(o["holes"], o["chamfer_x100"], s=o["faces_out"], alpha=0.6)
        ax.annotate(arm, (o["holes"], o["chamfer_x100"]), xytext=(6, 4), textcoords="offset points")
    ax.set_xlabel("holes per mesh (boundary loops)")
    ax.set_ylabel("Chamfer distance x100")
    ax.set_title("Completion settings, validation split (226 meshes); marker area ~ faces")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(here / "sweep.png", dpi=110)
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
