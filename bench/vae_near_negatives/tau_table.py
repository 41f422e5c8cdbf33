"""Validation edge F1 (mean per mesh and pooled) and CD of each arm's VAE against tau, from
tau_sweep.sh's files: `python3 bench/vae_near_negatives/tau_table.py OUT` prints one table and
each arm's best tau."""
import glob, json, os, re, sys
from collections import defaultdict

OUT = sys.argv[1]
rows = defaultdict(dict)
for path in glob.glob(os.path.join(OUT, '*_tau*.json')):
    arm, tau = re.match(r'(.+)_tau(-?[0-9.]+)\.json', os.path.basename(path)).groups()
    rows[arm][float(tau)] = json.load(open(path))['all']
taus = sorted({t for r in rows.values() for t in r})
print('| VAE | ' + ' | '.join(f'tau {t:g}' for t in taus) + ' | best: tau, F1, P / R, pooled F1, CD x100 |')
print('|---|' + '---:|' * len(taus) + '---|')
for arm in sorted(rows):
    r = rows[arm]
    cells = [f"{r[t]['edge_f1']:.3f}" if t in r else '' for t in taus]
    best = max(r, key=lambda t: r[t]['edge_f1'])
    b = r[best]
    print(f"| {arm} | " + ' | '.join(cells) +
          f" | {best:g}, {b['edge_f1']:.3f}, {b['edge_precision']:.3f} / {b['edge_recall']:.3f}, "
          f"{b['edge_f1_pooled']:.3f}, {b['chamfer_x100']:.3f} |")

# The extraction at each tau: faces and holes move with it, so compare CD at equal faces.
print()
gt_faces = next(iter(next(iter(rows.values())).values()))['faces_in']
print(f"| VAE | tau | edge F1 | the mesh's edges F1 | CD x100 | faces (gt {gt_faces:.1f}) | holes |")
print('|---|---:|---:|---:|---:|---:|---:|')
for arm in sorted(rows):
    for t in sorted(rows[arm]):
        r = rows[arm][t]
        print(f"| {arm} | {t:g} | {r['edge_f1']:.3f} | {r['mesh_edge_f1']:.3f} | {r['chamfer_x100']:.3f} | "
              f"{r['faces_out']:.0f} | {r['holes']:.1f} |")
