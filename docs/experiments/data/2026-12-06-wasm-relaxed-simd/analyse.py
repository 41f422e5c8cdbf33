"""The table and plot of docs/experiments/2026-12-06-wasm-relaxed-simd.md from run1.json and
run2.json (bench/page_ab.mjs output; run1 from a draft of it with the same fields):
`python3 analyse.py [DIR]` writes table.txt and relaxed_simd.png into DIR (default: here)."""
import json
import pathlib
import statistics
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

here = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).parent)
runs = {name: json.loads((here / f"{name}.json").read_text()) for name in ("run1", "run2")}
lines = ["| run | arm | generation (median) | sample stage | fit stage | rounds faster than shipped |",
         "|---|---|---:|---:|---:|---:|"]
fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
for ax, (run, d) in zip(axes, runs.items()):
    tabs = {t["name"]: t["runs"] for t in d["tabs"]}
    for name, rs in tabs.items():
        med = lambda f: statistics.median(f(r) for r in rs)
        base = tabs[name.replace("relaxed", "shipped")]
        faster = sum(r["generate_s"] < b["generate_s"] for r, b in zip(rs, base))
        lines.append(f"| {run} | {name} | {med(lambda r: r['generate_s']):.2f} s | "
                     f"{med(lambda r: r['stages_s']['sample_s']):.2f} s | {med(lambda r: r['stages_s']['fit_s']):.2f} s | "
                     f"{faster if 'relaxed' in name else ''}{'/' + str(len(rs)) if 'relaxed' in name else ''} |")
        ax.plot(range(1, len(rs) + 1), [r["generate_s"] for r in rs], "o-" if "relaxed" in name else "s--", label=name)
    cli = [c["process_s"] for c in d["cli"]]
    lines.append(f"| {run} | CLI (process) | {statistics.median(cli):.2f} s | "
                 f"{statistics.median(c['stages_s']['sample_s'] for c in d['cli']):.2f} s | "
                 f"{statistics.median(c['stages_s']['fit_s'] for c in d['cli']):.2f} s | |")
    ax.plot(range(1, len(cli) + 1), cli, "k:", label="CLI (process)")
    ax.set_title(run)
    ax.set_xlabel("round")
axes[0].set_ylabel("click to mesh (s)")
axes[1].legend(fontsize=8)
fig.suptitle("lantern scan, page's CPU path without isolation: gemm with and without relaxed-SIMD FMA")
fig.tight_layout()
fig.savefig(here / "relaxed_simd.png", dpi=90)
(here / "table.txt").write_text("\n".join(lines) + "\n")
print("\n".join(lines))
