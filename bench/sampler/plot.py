"""Generated validation CD against DiT evaluations per candidate, for each sampler (issue 14).

`python3 bench/sampler/plot.py [DIR [PNG]]` reads the `meshflow eval generate --split val`
results in DIR (`val_*.json`; default: the experiment's data folder,
docs/experiments/data/2026-11-27-second-order-sampling/) and the Euler runs scored before (from
their own entries' data folders), prints one table (every seed) and draws PNG (seed 0; default
`sampler.png` in DIR).
Each file's options say its solver, steps, seed and schedule (`to-zero`, the default, or
`reference`: the schedule for S + 1 cut at its last time, t ~ 0.009); the other time grids are
in the name (`_g1`: S steps evenly spaced in t from 1 to 0; `_g2`: the same in shifted time,
shift 2).
"""

import glob
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(os.path.dirname(os.path.dirname(HERE)), "docs", "experiments", "data")
DIR = sys.argv[1] if len(sys.argv) > 1 else os.path.join(DATA, "2026-11-27-second-order-sampling")
PNG = sys.argv[2] if len(sys.argv) > 2 else os.path.join(DIR, "sampler.png")
# The Euler runs scored before this sweep (commits 0a88870 of 2026-11-26, c80fa83 and a47b9c5 of
# 2026-11-27), in the data folders of their entries.
EARLIER = [
    "2026-11-27-dit-trained-longer/generate_eval_val_dit32_continued.json",
    "2026-11-27-dit-trained-longer/generate_eval_val_dit32_continued_seed1.json",
    "2026-11-27-larger-dit-latent-64/generate_eval_val_dit_big.json",
    "2026-11-27-larger-dit-latent-64/generate_eval_val_dit_big_steps28.json",
    "2026-11-26-latent-64/generate_eval_val_dit_continued.json",
]
# The pairs by their DiT's sha256 (first 12 hex digits), as
# docs/experiments/2026-11-27-second-order-sampling.md names them.
PAIRS = {
    "8c75a5506a58": "shipped",
    "fc10553c7da3": "64-wide, large DiT",
    "5ec0a3ed8edf": "64-wide, DiT continued",
}


def evaluations(solver, steps, grid):
    # Heun's step to t = 0 is an Euler step: the last one, on every grid but `reference`.
    if solver == "heun" and grid != "reference":
        return 2 * steps - 1
    return steps if solver == "euler" else 2 * steps


def arms():
    files = [os.path.join(DATA, f) for f in EARLIER]
    files += sorted(glob.glob(os.path.join(DIR, "val_*.json")))
    for path in files:
        d = json.load(open(path))
        name = os.path.basename(path).split(".")[0]
        o = d["options"]
        grid = name.split("_g")[1].split("_")[0] if "_g" in name else o["schedule"]
        solver = o.get("solver", "euler")
        ours = d["all"]["ours"]
        yield {
            "pair": PAIRS[d["weights_dit_sha256"][:12]],
            "seed": o["seed"],
            "samples": o["samples"],
            "solver": solver,
            "steps": o["steps"],
            "grid": grid,
            "evals": evaluations(solver, o["steps"], grid),
            "cd": ours["chamfer_x100"],
            "hd": ours["hausdorff_x100"],
            "holes": ours["holes"],
            "faces": ours["faces_out"],
            "sample_s": d["mean_times"]["sample_s"],
            "meshes": d["all"]["meshes"],
        }


def main():
    rows = sorted(arms(), key=lambda r: (r["pair"], r["grid"], r["samples"], r["solver"], r["evals"], r["seed"]))
    print(
        "| pair | solver | steps | time grid | DiT evaluations | candidates | seed | val CD x100 | HD x100 | holes "
        "| faces | sampling s/mesh |"
    )
    print("|---|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        print(
            f"| {r['pair']} | {r['solver']} | {r['steps']} | {r['grid']} | {r['evals']} | {r['samples']} | {r['seed']} | "
            f"{r['cd']:.3f} | "
            f"{r['hd']:.2f} | {r['holes']:.2f} | {r['faces']:.1f} | {r['sample_s']:.2f} |"
        )
    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    colours = {"shipped": "tab:blue", "64-wide, DiT continued": "tab:orange", "64-wide, large DiT": "tab:green"}
    markers = {"euler": "o", "heun": "^", "midpoint": "s"}
    lines = {}
    for r in rows:
        if r["seed"] == 0:
            lines.setdefault((r["pair"], r["solver"], r["grid"], r["samples"]), []).append(r)
    for (pair, solver, grid, samples), rs in sorted(lines.items()):
        rs.sort(key=lambda r: r["evals"])
        xs, ys = [r["evals"] for r in rs], [r["cd"] for r in rs]
        if samples != 12:
            # Other candidate counts: hollow, dotted, labelled.
            ax.plot(xs, ys, marker=markers[solver], color=colours[pair], markerfacecolor="none", linestyle=":")
            for x, y in zip(xs, ys):
                ax.annotate(f"{samples} candidates", (x, y), textcoords="offset points", xytext=(6, -3), fontsize=7)
        elif grid == "to-zero":
            ax.plot(xs, ys, marker=markers[solver], color=colours[pair], label=f"{pair}, {solver}")
        else:
            # Other time grids: hollow, labelled by their shift.
            ax.plot(xs, ys, marker=markers[solver], color=colours[pair], markerfacecolor="none", linestyle="none")
            for x, y in zip(xs, ys):
                ax.annotate(grid if grid == "reference" else f"grid {grid}", (x, y), textcoords="offset points", xytext=(6, -3), fontsize=7)
    ax.set_xscale("log", base=2)
    ticks = sorted({r["evals"] for r in rows})
    ax.set_xticks(ticks, [str(t) for t in ticks])
    ax.minorticks_off()
    ax.set_xlabel("DiT evaluations per candidate")
    ax.set_ylabel("validation CD x100 (seed 0)")
    ax.set_title("Generated CD against sampling cost, by solver")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(PNG, dpi=120)


if __name__ == "__main__":
    main()
