"""Paired per-mesh differences between two `meshflow eval generate` runs on the same meshes,
samples and seeds (the pairing removes the meshes' own spread): shared by the experiment
log's analysis scripts (docs/experiments/data/*/analyse.py), which import it from here.
    python3 bench/paired.py RUN.json > RUN.per_mesh.csv
writes a run's per-mesh CSV, the file those scripts read."""
import csv
import math


def per_mesh(o, key):
    """A per-mesh figure: the edge F-score sits under `sharp`, the rest at the top."""
    return o["sharp"]["edge_f_score"]["f_score"] if key == "edge_f_score" else o[key]


def mean_se(d):
    """The mean of the differences `d` and its standard error."""
    n = len(d)
    mean = sum(d) / n
    sd = math.sqrt(sum((x - mean) ** 2 for x in d) / (n - 1))
    return mean, sd / math.sqrt(n)


def paired(a, b, key):
    """`key` of run `a` minus run `b`, per mesh (both with faces): mean and standard error."""
    return mean_se([per_mesh(x["ours"], key) - per_mesh(y["ours"], key)
                    for x, y in zip(a["per_mesh"], b["per_mesh"])
                    if x["ours"] and y["ours"] and x["name"] == y["name"]])


def load_rows(path, keys):
    """The per-mesh CSV at `path` (an experiment's `NAME.per_mesh.csv`: a `name` column, then
    figures) as {name: {key: float, or None where empty}} for `keys`."""
    with open(path) as f:
        return {r["name"]: {k: float(r[k]) if r[k] else None for k in keys} for r in csv.DictReader(f)}


def mean_of(rows, key):
    """The mean of `key` over the rows of `load_rows` that have it."""
    v = [r[key] for r in rows.values() if r[key] is not None]
    return sum(v) / len(v)


def paired_rows(a, b, key):
    """`key` of rows `a` minus rows `b` (both from `load_rows`), per mesh that both have it:
    mean and standard error."""
    return mean_se([a[n][key] - b[n][key] for n in a
                    if n in b and a[n][key] is not None and b[n][key] is not None])


def load_gt_faces(path):
    """An experiment's `*_gt_faces.csv` (`name`, `gt_faces`) as {name: ground-truth faces}."""
    with open(path) as f:
        return {r["name"]: float(r["gt_faces"]) for r in csv.DictReader(f)}


def faces_per_gt(rows, gt):
    """Our faces per ground-truth face over rows of `load_rows`: the mean of the meshes' ratios,
    as BENCHMARKS.md gives it (`gt` from `load_gt_faces`)."""
    return sum(r["faces"] / gt[n] for n, r in rows.items()) / len(rows)


def json_at(commit, path):
    """The JSON file at `path` (from the repository's root) as commit `commit` had it: a
    shipped run in bench/ that a later run has since replaced, read from git."""
    import json
    import os
    import subprocess

    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    text = subprocess.run(["git", "-C", root, "show", f"{commit}:{path}"],
                          capture_output=True, text=True, check=True).stdout
    return json.loads(text)


# The surface figures an experiment's per-mesh CSV carries, in the order its tables print them.
SURFACE_KEYS = ["cd", "nc", "ecd", "ef1", "faces", "holes"]


# The decimals a table gives each of them.
DIGITS = {"cd": 3, "nc": 4, "ecd": 2, "ef1": 4, "faces": 1, "holes": 3}


def mean_cells(rows):
    """The means of `SURFACE_KEYS` over rows of `load_rows`, formatted as table cells."""
    return [f"{mean_of(rows, k):.{DIGITS[k]}f}" for k in SURFACE_KEYS]


def diff_cells(a, b, keys):
    """`keys` of rows `a` minus rows `b` (both from `load_rows`), per mesh, as table cells
    ("mean ± s.e." with each key's `DIGITS`)."""
    return [f"{m:+.{DIGITS[k]}f} ± {se:.{DIGITS[k]}f}" for k in keys for m, se in [paired_rows(a, b, k)]]


def arm_row(arm, rows, base, keys):
    """A table line for `arm`: the means of `SURFACE_KEYS` over its `rows` (`mean_cells`), then
    `keys` of `rows` minus `base` (`diff_cells`), empty where `base` is None (the base arm)."""
    diffs = [""] * len(keys) if base is None else diff_cells(rows, base, keys)
    return f"| {arm} | " + " | ".join(mean_cells(rows) + diffs) + " |"


def paired_cells(a, b):
    """CD, NC and holes of rows `a` minus rows `b` as table cells ("mean ± s.e."), and the
    (holes mean, holes s.e., CD mean, CD s.e.) that the experiments' plots draw."""
    (dc, sc), (dn, sn), (dh, sh) = (paired_rows(a, b, k) for k in ("cd", "nc", "holes"))
    return [f"{dc:+.3f} ± {sc:.3f}", f"{dn:+.4f} ± {sn:.4f}", f"{dh:+.3f} ± {sh:.3f}"], (dh, sh, dc, sc)


def finish_paired_plot(fig, ax, xlabel, ylabel, title, path, dpi=110, x_zero=True):
    """The frame every experiment's plot of paired changes shares (zero lines through both
    axes, or the y axis only without `x_zero`, as a bar chart wants; labels, title), then the
    figure written to `path`."""
    ax.axhline(0, color="grey", lw=0.5)
    if x_zero:
        ax.axvline(0, color="grey", lw=0.5)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    fig.tight_layout()
    fig.savefig(path, dpi=dpi)


def hard_surface_table(rows, arms, seeds=("0", "2", "3")):
    """Prints the Markdown table of the hard-surface set's means over its shapes, per input
    (clean, 1% noise), arm and seed, then the seeds' mean in bold (CD, NC, ECD, EF1, faces as a
    multiple of the ground truth's), from `rows` of an experiment's `hard_surface.csv` (arm,
    input, seed, shape, cd, nc, ecd, ef1, faces, gt_faces). Returns each (arm, input)'s EF1 per
    seed, which the plots draw."""

    def seed_means(arm, inp, key):
        out = []
        for s in seeds:
            rs = [r for r in rows if r["arm"] == arm and r["input"] == inp and r["seed"] == s]
            v = [float(r[key]) / (float(r["gt_faces"]) if key == "faces" else 1.0) for r in rs]
            out.append(sum(v) / len(v))
        return out

    print(f"Hard-surface set, means over its 8 shapes (seed {' / '.join(seeds)}, then their mean)")
    print("| input | arm | CD x100 | NC | ECD x100 | EF1 | faces / gt |")
    print("|---|---|---|---|---|---|---|")
    ef1 = {}
    for inp, label in [("clean", "clean"), ("noise1", "1% noise")]:
        for arm in arms:
            cells = []
            for key in ["cd", "nc", "ecd", "ef1", "faces"]:
                per_seed = seed_means(arm, inp, key)
                mean = sum(per_seed) / len(per_seed)
                if key == "ef1":
                    ef1[(arm, inp)] = per_seed
                fmt = "{:.2f}x" if key == "faces" else "{:.3f}"
                cells.append(" / ".join(fmt.format(v) for v in per_seed) + " (**" + fmt.format(mean) + "**)")
            print(f"| {label} | {arm} | " + " | ".join(cells) + " |")
    return ef1


def compact_changes(before, after, label):
    """Prints, for two compacted test-split runs (bench/sharpen_eval/compact.py's per-mesh
    lists as {name: figures}), how many meshes change (their faces, or their CD beyond the
    last digits, which two machines round differently) and each figure's paired difference
    `after` minus `before` (mean ± s.e.) under the heading `label`. Returns the names that
    change."""
    changed = [n for n, g in after.items() if n in before and (
        g["faces"] != before[n]["faces"] or abs(g["cd_x100"] - before[n]["cd_x100"]) > 1e-5)]
    print(f"\n{label} (paired, mean ± s.e.; {len(changed)} of {len(after)} meshes change)")
    for key in ["cd_x100", "nc", "ecd_x100", "ef1", "faces", "holes"]:
        pairs = [(before[n][key], g[key]) for n, g in after.items()
                 if n in before and before[n][key] is not None and g[key] is not None]
        m, se = mean_se([b - a for a, b in pairs])
        print(f"{key}: {sum(a for a, _ in pairs) / len(pairs):.4f} -> {sum(b for _, b in pairs) / len(pairs):.4f}, "
              f"{m:+.4f} ± {se:.4f}")
    return changed


def write_rows(run_path, out):
    """The per-mesh figures of the `meshflow eval generate` JSON at `run_path` as the CSV that
    `load_rows` reads (`name`, then `SURFACE_KEYS`; empty where a mesh got no faces), to the
    text stream `out`."""
    import json

    writer = csv.writer(out)
    writer.writerow(["name"] + SURFACE_KEYS)
    for m in json.load(open(run_path))["per_mesh"]:
        o = m["ours"]
        if not o:
            writer.writerow([m["name"]] + [""] * len(SURFACE_KEYS))
            continue
        writer.writerow([m["name"], o["chamfer_x100"], o["normal_consistency"],
                         o["sharp"]["edge_chamfer_x100"], per_mesh(o, "edge_f_score"),
                         m["faces_made"], o["pred_topology"]["holes"]])


if __name__ == "__main__":
    # python3 bench/paired.py RUN.json > RUN.per_mesh.csv
    import sys

    write_rows(sys.argv[1], sys.stdout)
