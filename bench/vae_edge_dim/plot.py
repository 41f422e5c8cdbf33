"""Wider edge embeddings (run.sh): the shipped VAE continued decoder-only with 32 (control), 64
or 128 edge-embedding channels, the arms at once with the same wall-clock budget. Draws
validation edge F1 at the best tau of the grid, position and normal MSE against wall minutes
into edge_dim.png and prints each arm's validations at every 1,000 steps.
`python3 bench/vae_edge_dim/plot.py [--steps] [DIR | ARM.metrics.jsonl ...] [PNG]`: each DIR
holds ARM.metrics.jsonl or ARM/metrics.jsonl, and a log can also be named alone (default: the
logs of the edge-width arms, validation lines and every 10th step, in the experiment's data
folder, docs/experiments/data/2026-11-28-edge-embedding-width/); PNG (a name ending in .png)
defaults to edge_dim.png in the first DIR. --steps draws against steps instead of wall minutes
(docs/experiments/data/2026-11-28-pair-head: its third arm started later, beside the other two;
the pair-head lr arms against that third arm: D/2026-11-28-pair-head-lr
bench/vae_pair_lr/e_lr3e4.metrics.jsonl D/2026-11-28-pair-head/c_pair64_context.metrics.jsonl,
with D for docs/experiments/data)."""
import glob, json, os, sys
import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(os.path.dirname(os.path.dirname(HERE)), 'docs', 'experiments', 'data')
STEPS = '--steps' in sys.argv
ARGS = [a for a in sys.argv[1:] if a != '--steps']
LOGS = [a for a in ARGS if a.endswith('.metrics.jsonl')]
DIRS = [a for a in ARGS if not a.endswith('.png') and a not in LOGS]
if not ARGS:
    DIRS = [os.path.join(DATA, '2026-11-28-edge-embedding-width')]
PNGS = [a for a in ARGS if a.endswith('.png')]
PNG = PNGS[0] if PNGS else os.path.join((DIRS or [os.path.dirname(LOGS[0])])[0], 'edge_dim.png')
LABELS = {'a_edge32': '32 channels (control)', 'b_edge64': '64 channels',
          'a_control': 'as shipped (control)', 'b_pair64': 'pair head, hidden 64',
          'c_pair64_context': 'pair head, hidden 64, with the pair context (lr 1e-4)',
          'c_edge128': '128 channels',
          'd_lr2e4': 'pair head with context, lr 2e-4', 'e_lr3e4': 'pair head with context, lr 3e-4'}


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
# The stage-2 VAE's last validation (bench/vae_latent64/): every arm here continues it.
shipped = [json.loads(l) for l in open(os.path.join(HERE, '..', 'vae_latent64', 'position80', 'ld64_vertex.metrics.jsonl'))
           if 'val_loss' in l][-1]
fig, axes = plt.subplots(1, 3, figsize=(17, 4.4))
for ax, key in zip(axes, ['edge_f1_best_tau', 'val_position', 'val_normal']):
    ax.axhline(shipped[key], color='grey', ls='--', lw=1, label=f'stage-2 VAE, where these runs start ({shipped[key]:.4g})')
print('| arm | step | wall min | edge P / R / F1 at tau 0.6 | best-tau F1 (tau) | position MSE | normal MSE |')
print('|---|---:|---:|---|---|---:|---:|')
for arm in sorted(paths):
    val = load(paths[arm])
    label = LABELS.get(arm, arm)
    t = [r['step'] if STEPS else r['elapsed_s'] / 60 for r in val]
    for ax, key in zip(axes, ['edge_f1_best_tau', 'val_position', 'val_normal']):
        ax.plot(t, [r[key] for r in val], marker='.', label=label)
    for r in val:
        if r['step'] % 1000 == 0 or r is val[-1]:
            print(f"| {label} | {r['step']:,} | {r['elapsed_s'] / 60:.0f} | {r['edge_precision']:.3f} / "
                  f"{r['edge_recall']:.3f} / {r['edge_f1']:.3f} | {r['edge_f1_best_tau']:.4f} "
                  f"({r['best_tau']:g}) | {r['val_position']:.5f} | {r['val_normal']:.5f} |")
for ax, title in zip(axes, ['validation edge F1 at the best tau of the grid (pooled, 64 meshes)',
                            'validation position MSE (model frame)', 'validation normal MSE']):
    ax.set_title(title, fontsize=10)
    ax.set_xlabel('steps' if STEPS else 'wall minutes (the arms at once, 2 cores)')
    ax.grid(alpha=.3); ax.legend(fontsize=8)
fig.tight_layout(); fig.savefig(PNG, dpi=110)
