"""Folded edges and holes per input of bench/folds/fixtures.sh, before (1b6a30b, the
2026-12-03 run) and after fold-free closing: one plot, fold_free_closing.png, and the sums.

    python3 analyse.py
"""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

STAGES = ["defaults", "--no-sharpen", "--no-sharpen --no-close-holes", "--no-close-holes"]


def before():
    rows = {}
    lines = open("fixtures_before.txt").read().split("\n")[1:]
    for line in filter(None, lines):
        name, *v = line.split()
        v = list(map(int, v))
        rows[name] = [(v[2 * i], v[2 * i + 1]) for i in range(4)]
    return rows


def after():
    rows = {}
    for line in filter(None, open("fixtures_after.txt").read().split("\n")):
        name, *cells = line.split()
        rows[name] = [tuple(map(int, c.split("/"))) for c in cells]
    return rows


b, a = before(), after()
names = list(b)
print("| stages | folded edges before | after | holes before | after |")
print("|---|---:|---:|---:|---:|")
for i, stage in enumerate(STAGES):
    fb = sum(b[n][i][0] for n in names)
    fa = sum(a[n][i][0] for n in names)
    hb = sum(b[n][i][1] for n in names)
    ha = sum(a[n][i][1] for n in names)
    print(f"| {stage} | {fb} | {fa} | {hb} | {ha} |")

fig, axes = plt.subplots(2, 1, figsize=(11, 7), sharex=True)
x = range(len(names))
w = 0.4
for ax, k, title in [(axes[0], 0, "folded edges"), (axes[1], 1, "holes")]:
    ax.bar([i - w / 2 for i in x], [b[n][0][k] for n in names], w, label="before (1b6a30b)")
    ax.bar([i + w / 2 for i in x], [a[n][0][k] for n in names], w, label="fold-free closing")
    ax.set_ylabel(title)
    ax.legend()
axes[0].set_title("meshflow generate at the defaults, per input (bench/folds/fixtures.sh)")
axes[1].set_xticks(list(x))
axes[1].set_xticklabels(names, rotation=60, ha="right", fontsize=8)
fig.tight_layout()
fig.savefig("fold_free_closing.png", dpi=90)
