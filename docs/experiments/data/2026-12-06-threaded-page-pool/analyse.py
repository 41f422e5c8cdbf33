"""The table and plot of docs/experiments/2026-12-06-threaded-page-pool.md from the four
bench/page_ab.mjs --isolated runs in this folder: `python3 analyse.py [DIR]` writes table.txt
and threaded_page.png into DIR (default: here)."""
import json
import pathlib
import statistics
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

STAGES = ["condition_s", "sample_s", "decode_s", "extract_s", "fit_s"]
here = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).parent)
runs = ["908c217_vs_side_by_side", "side_by_side_vs_pool", "908c217_vs_pool", "pool_vs_talc"]
lines = ["| run | tab | generation (median) | sample | decode | fit | stages summed | not in a stage |",
         "|---|---|---:|---:|---:|---:|---:|---:|"]
fig, axes = plt.subplots(1, len(runs), figsize=(16, 4), sharey=True)
for ax, run in zip(axes, runs):
    d = json.loads((here / f"{run}.json").read_text())
    for tab in d["tabs"]:
        rs = tab["runs"]
        med = lambda f: statistics.median(f(r) for r in rs)
        whole = med(lambda r: r["generate_s"])
        summed = med(lambda r: sum(r["stages_s"][k] for k in STAGES))
        lines.append(f"| {run} | {tab['name']} | {whole:.2f} s | {med(lambda r: r['stages_s']['sample_s']):.2f} s | "
                     f"{med(lambda r: r['stages_s']['decode_s']):.2f} s | {med(lambda r: r['stages_s']['fit_s']):.2f} s | "
                     f"{summed:.2f} s | {whole - summed:.2f} s |")
        style = "o-" if "threads" in tab["name"] else "s--"
        ax.plot(range(1, len(rs) + 1), [r["generate_s"] for r in rs], style, label=tab["name"])
    cli = [c["process_s"] for c in d["cli"]]
    lines.append(f"| {run} | CLI (process) | {statistics.median(cli):.2f} s | "
                 f"{statistics.median(c['stages_s']['sample_s'] for c in d['cli']):.2f} s | | | | |")
    ax.plot(range(1, len(cli) + 1), cli, "k:", label="CLI (process)")
    ax.set_title(run.replace("_", " "), fontsize=9)
    ax.set_xlabel("round")
    ax.legend(fontsize=7)
axes[0].set_ylabel("click to mesh (s)")
fig.suptitle("lantern scan, the isolated page on 2 threads and on 2 workers (?threads=0), two builds a run")
fig.tight_layout()
fig.savefig(here / "threaded_page.png", dpi=90)
(here / "table.txt").write_text("\n".join(lines) + "\n")
print("\n".join(lines))
