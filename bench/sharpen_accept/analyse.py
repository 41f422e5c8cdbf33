#!/usr/bin/env python3
"""Which sharpened meshes generation should keep: the acceptance ratio of
`--sharpen-accept` (sharpened distance to the input points over the fitted mesh's) swept
after the fact over two runs of the same meshes and seeds:

    meshflow eval generate --split val --sharpen-accept 1e9 -o DIR/always.json
    meshflow eval generate --split val --no-sharpen -o DIR/fitted.json
    meshflow eval generate --split val -o DIR/rounds.json        (optional: the default,
                                                                 the last acceptable round)
    python3 bench/sharpen_accept/analyse.py DIR

For each ratio, a mesh scores as sharpened when its distance ratio is at most the ratio,
else as fitted. Writes DIR/accept.csv and DIR/accept.png (CD, NC, EF1 and the share kept
against the ratio; per_mesh.csv has both arms' figures per mesh) and prints the table.
"""
import csv
import json
import math
import os
import sys


def main(out):
    always = json.load(open(os.path.join(out, "always.json")))["per_mesh"]
    fitted = json.load(open(os.path.join(out, "fitted.json")))["per_mesh"]
    assert [m["name"] for m in always] == [m["name"] for m in fitted]
    rows, names = [], []
    for s, f in zip(always, fitted):
        if not (s["ours"] and f["ours"]):
            continue
        before, after = s["sharpen"]["input_distance_before"], s["sharpen"]["input_distance_after"]
        ratio = after / before if before and before > 0 and after is not None else math.inf
        pick = lambda m: (m["ours"]["chamfer_x100"], m["ours"]["normal_consistency"],
                          m["ours"]["sharp"]["edge_f_score"]["f_score"],
                          m["ours"]["sharp"]["edge_chamfer_x100"],
                          m["ours"]["pred_topology"]["holes"], m["ours"]["pred_topology"]["faces"])
        rows.append((ratio, pick(s), pick(f)))
        names.append(s["name"])
    ratios = [1.0, 1.02, 1.05, 1.1, 1.2, 1.3, 1.5, 2.0, math.inf]
    table = []
    for r in ratios:
        chosen = [(s if ratio <= r else f) for ratio, s, f in rows]
        n = len(chosen)
        # ECD is undefined (None) where neither mesh has a sharp edge: left out of its mean.
        mean = [sum(v) / len(v) for v in ([c[i] for c in chosen if c[i] is not None] for i in range(6))]
        kept = sum(ratio <= r for ratio, _, _ in rows) / n
        table.append([r, kept] + mean)
    with open(os.path.join(out, "accept.csv"), "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["accept_ratio", "share_sharpened", "cd_x100", "nc", "ef1", "ecd_x100", "holes", "faces"])
        for t in table:
            w.writerow([f"{v:.4f}" if isinstance(v, float) and math.isfinite(v) else v for v in t])
    with open(os.path.join(out, "per_mesh.csv"), "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["name", "distance_ratio"] + [f"{arm}_{k}" for arm in ("sharpened", "fitted")
                                                  for k in ("cd_x100", "nc", "ef1", "ecd_x100", "holes", "faces")])
        for name, (ratio, s, f) in zip(names, rows):
            w.writerow([name, f"{ratio:.4f}"] + ["" if v is None else f"{v:.4f}" for v in s + f])
    print(f"{len(rows)} meshes")
    print("ratio   kept   CD x100  NC      EF1     ECD x100 holes  faces")
    for t in table:
        print(f"{t[0]:<7} {t[1]:.3f}  {t[2]:.3f}    {t[3]:.4f}  {t[4]:.4f}  {t[5]:.3f}   {t[6]:.2f}   {t[7]:.1f}")
    path = os.path.join(out, "rounds.json")
    if os.path.exists(path):
        rounds = json.load(open(path))["per_mesh"]
        kept = [m["sharpen"]["rounds_kept"] for m in rounds]
        ours = [m["ours"] for m in rounds if m["ours"]]
        mean = lambda f: sum(map(f, ours)) / len(ours)
        ecds = [c["sharp"]["edge_chamfer_x100"] for c in ours if c["sharp"]["edge_chamfer_x100"] is not None]
        ecd = sum(ecds) / len(ecds)
        print(f"last acceptable round: CD x100 {mean(lambda c: c['chamfer_x100']):.3f}  "
              f"NC {mean(lambda c: c['normal_consistency']):.4f}  "
              f"EF1 {mean(lambda c: c['sharp']['edge_f_score']['f_score']):.4f}  "
              f"ECD x100 {ecd:.3f}  "
              f"holes {mean(lambda c: c['pred_topology']['holes']):.2f}")
        print("rounds kept (0 = none):", {r: kept.count(r) for r in sorted(set(kept))})
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    xs = [min(t[0], 3.0) for t in table]
    fig, axes = plt.subplots(1, 4, figsize=(14, 3.2))
    for ax, k, name in zip(axes, [2, 3, 4, 1], ["CD x100", "NC", "EF1", "share sharpened"]):
        ax.plot(xs, [t[k] for t in table], "o-")
        ax.set_xlabel("accept ratio (3 = always)")
        ax.set_title(name)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "accept.png"), dpi=100)


if __name__ == "__main__":
    main(sys.argv[1])
