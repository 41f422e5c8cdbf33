"""Validation curves of the shipped VAE continued at a capacity of 2,048 vertices (issue 53;
docs/experiments/2026-12-04-capacity-2048.md): validation loss and edge F1 (at the model's
threshold and at the best one) against wall time, one line per run.
`python3 bench/capacity_2048/plot.py [METRICS ...]` writes capacity_2048.png beside the first
METRICS and prints one table per run; METRICS default to the entry's data folder's
vae.metrics.jsonl (the decoder alone) and vae_whole.metrics.jsonl (the whole VAE), where
present."""
import json, os, sys
import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(os.path.dirname(os.path.dirname(HERE)), 'docs', 'experiments', 'data',
                    '2026-12-04-capacity-2048')
LABELS = {'vae.metrics.jsonl': 'decoder alone', 'vae_whole.metrics.jsonl': 'whole VAE'}
paths = sys.argv[1:] or [p for p in (os.path.join(DATA, n) for n in LABELS) if os.path.exists(p)]
PNG = os.path.join(os.path.dirname(paths[0]), 'capacity_2048.png')

fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
for k, path in enumerate(paths):
    rows = [json.loads(l) for l in open(path)]
    elapsed = {r['step']: r['elapsed_s'] for r in rows if 'lr' in r}
    val = [dict(r, minutes=elapsed.get(r['step'], float('nan')) / 60) for r in rows if 'val_loss' in r]
    label = LABELS.get(os.path.basename(path), os.path.basename(path))
    colour = f'C{k}'
    minutes = [r['minutes'] for r in val]
    axes[0].plot(minutes, [r['val_loss'] for r in val], 'o-', color=colour, label=label)
    axes[1].plot(minutes, [r['edge_f1'] for r in val], 'o-', color=colour, label=f"{label}, model's threshold")
    axes[1].plot(minutes, [r['edge_f1_best_tau'] for r in val], 's--', color=colour, label=f'{label}, best threshold')
    print(f'{label} ({path})')
    print('| step | minutes | val loss | edge F1 | F1 at best tau (tau) |')
    print('|---:|---:|---:|---:|---:|')
    for r in val:
        print(f"| {r['step']} | {r['minutes']:.0f} | {r['val_loss']:.3f} | {r['edge_f1']:.3f} | "
              f"{r['edge_f1_best_tau']:.3f} ({r['best_tau']}) |")
axes[0].set(xlabel='minutes (batch 8)', ylabel='validation loss', title='64 validation meshes <= 2,048 vertices')
axes[1].set(xlabel='minutes (batch 8)', ylabel='edge F1', title='decoder edge F1, same meshes')
for ax in axes:
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(PNG, dpi=110)
print(f'wrote {PNG}')
