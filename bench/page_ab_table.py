"""The table of `node bench/page_ab.mjs` runs: per tab the median click-to-mesh time and fit
stage, its ratio to the first tab's, and the CLI's process time.
    python3 bench/page_ab_table.py RUN.json [RUN.json ...]"""
import json
import statistics
import sys

for path in sys.argv[1:]:
    run = json.load(open(path))
    print(f"{path}: {run['input'].split('/')[-1]}, {len(run['cli'])} rounds, {run['chromium']}")
    first = statistics.median(r["generate_s"] for r in run["tabs"][0]["runs"])
    for tab in run["tabs"]:
        times = [r["generate_s"] for r in tab["runs"]]
        fit = statistics.median(r["stages_s"]["fit_s"] for r in tab["runs"])
        t = statistics.median(times)
        print(f"  {tab['name']}: {t:.2f} s ({min(times):.2f}-{max(times):.2f}; {t / first:.2f}x the first tab), "
              f"fit stage {fit:.2f} s, {tab['runs'][0]['faces']} faces")
    cli = [c["process_s"] for c in run["cli"]]
    print(f"  CLI process: {statistics.median(cli):.2f} s ({min(cli):.2f}-{max(cli):.2f}), {run['cli'][0]['faces']} faces")
