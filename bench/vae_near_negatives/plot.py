"""Near-negative weighting of the adjacency loss: the shipped decoder continued with each arm's
weights at the same wall-clock budget (run.sh: round 1, three arms at once; round 2, two longer
arms at once). Draws validation edge F1 at the shipped tau = 0.6 and at the best tau of a grid
(logged from round 2 on), that best tau and the position error against wall time into
near_negatives.png, and prints each arm's last validation.
`python3 bench/vae_near_negatives/plot.py [DIR | ARM.metrics.jsonl ...] [PNG]`: each DIR holds
ARM.metrics.jsonl or ARM/metrics.jsonl, and a log can also be named alone (default: the logs of
both rounds, validation lines and every 10th step, in the experiment's data folder,
docs/experiments/data/2026-11-27-near-non-edges/); PNG (a name ending in .png) is where the
plot goes (default near_negatives.png in the first DIR, or beside the first log)."""
import glob, json, os, sys
import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(os.path.dirname(os.path.dirname(HERE)), 'docs', 'experiments', 'data')
ARGS = sys.argv[1:]
LOGS = [a for a in ARGS if a.endswith('.metrics.jsonl')]
DIRS = [a for a in ARGS if not a.endswith('.png') and a not in LOGS]
if not ARGS:
    DIRS = [os.path.join(DATA, '2026-11-27-near-non-edges')]
PNGS = [a for a in ARGS if a.endswith('.png')]
PNG = PNGS[0] if PNGS else os.path.join((DIRS or [os.path.dirname(LOGS[0])])[0], 'near_negatives.png')
LABELS = {'a_control': 'round 1: control (non-edges 0.25)', 'b_near1': 'round 1: near 1.0',
          'c_near3': 'round 1: near 3.0', 'd_near3_long': 'round 2: near 3.0, lr 2e-4',
          'e_near10_long': 'round 2: near 10.0, lr 2e-4',
          'a_near10': 'near 10.0 (control)', 'b_near10_vertex1': 'near 10.0 + 1 vertex block'}


def load(path):
    rows = [json.loads(l) for l in open(path)]
    elapsed = {r['step']: r['elapsed_s'] for r in rows if 'elapsed_s' in r}
    val = [r for r in rows if 'val_loss' in r]
    for r in val:  # validation lines carry no time: take the last step line's at or before
        r['elapsed_s'] = elapsed[max(s for s in elapsed if s <= r['step'])]
    return val


paths = {}
for DIR in DIRS:
    paths.update({os.path.basename(p)[:-len('.metrics.jsonl')]: p
                  for p in glob.glob(os.path.join(DIR, '*.metrics.jsonl'))})
    paths.update({os.path.basename(os.path.dirname(p)): p
                  for p in glob.glob(os.path.join(DIR, '*', 'metrics.jsonl'))})
paths.update({os.path.basename(p)[:-len('.metrics.jsonl')]: p for p in LOGS})
COLORS = dict(zip(LABELS, ['tab:blue', 'tab:orange', 'tab:green', 'tab:red', 'tab:purple',
                          'tab:purple', 'tab:brown']))
fig, axes = plt.subplots(1, 4, figsize=(21, 4.4))
# The shipped decoder's last validation (stage 2, docs/experiments/data/2026-11-25-vae-decoder-stage/):
# its F1 is flat in tau (the tau sweep of the whole split), so its F1 at 0.6 stands for its best.
shipped = [json.loads(l) for l in open(os.path.join(DATA, '2026-11-25-vae-decoder-stage', 'vae_decoder.metrics.jsonl'))
           if 'val_loss' in l][-1]['edge_f1']
for ax in axes[:2]:
    ax.axhline(shipped, color='grey', ls='--', lw=1, label=f'shipped decoder ({shipped:.3f})')
print('| arm | steps | wall s | edge P / R / F1 at tau 0.6 | best F1 (tau) |')
print('|---|---:|---:|---|---|')
for arm in sorted(paths):
    val = load(paths[arm])
    label = LABELS.get(arm, arm)
    t = [r['elapsed_s'] / 60 for r in val]
    c = COLORS.get(arm)
    axes[0].plot(t, [r['edge_f1'] for r in val], marker='.', label=label, color=c)
    best = [r for r in val if 'edge_f1_best_tau' in r]
    if best:
        tb = [r['elapsed_s'] / 60 for r in best]
        axes[1].plot(tb, [r['edge_f1_best_tau'] for r in best], marker='.', label=label, color=c)
        axes[2].plot(tb, [r['best_tau'] for r in best], marker='.', label=label, color=c)
    axes[3].plot(t, [r['val_position'] for r in val], marker='.', label=label, color=c)
    last = val[-1]
    b = f"{last['edge_f1_best_tau']:.3f} ({last['best_tau']:g})" if 'edge_f1_best_tau' in last else ''
    print(f"| {label} | {last['step']:,} | {last['elapsed_s']:.0f} | {last['edge_precision']:.3f} / "
          f"{last['edge_recall']:.3f} / {last['edge_f1']:.3f} | {b} |")
for ax, title in zip(axes, ['validation edge F1 at tau 0.6 (pooled, 64 meshes)',
                            'validation edge F1 at the best tau of the grid',
                            'that best tau', 'validation position MSE (model frame)']):
    ax.set_title(title); ax.set_xlabel('wall minutes (arms of a round at once, 2 cores)')
    ax.grid(alpha=.3)
axes[0].legend(loc='lower left', fontsize=8); axes[1].legend(loc='lower right', fontsize=8)
fig.tight_layout(); fig.savefig(PNG, dpi=110)
