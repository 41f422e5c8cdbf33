"""Validation curves of the shipped VAE's decoder continued at a capacity of 2,048 vertices
(issue 53; docs/experiments/2026-12-04-capacity-2048.md): validation loss, edge F1 at the
model's threshold and at the best one, against steps and wall time.
`python3 bench/capacity_2048/plot.py [METRICS [PNG]]` writes PNG (default: capacity_2048.png
beside METRICS) and prints the table; METRICS defaults to the entry's data folder,
docs/experiments/data/2026-12-04-capacity-2048/vae.metrics.jsonl."""
import json, os, sys
import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(os.path.dirname(os.path.dirname(HERE)), 'docs', 'experiments', 'data',
                    '2026-12-04-capacity-2048')
METRICS = sys.argv[1] if len(sys.argv) > 1 else os.path.join(DATA, 'vae.metrics.jsonl')
PNG = sys.argv[2] if len(sys.argv) > 2 else os.path.join(os.path.dirname(METRICS), 'capacity_2048.png')

rows = [json.loads(l) for l in open(METRICS)]
elapsed = {r['step']: r['elapsed_s'] for r in rows if 'lr' in r}
val = [dict(r, minutes=elapsed.get(r['step'], float('nan')) / 60) for r in rows if 'val_loss' in r]

fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
steps = [r['step'] for r in val]
axes[0].plot(steps, [r['val_loss'] for r in val], 'o-')
axes[0].set(xlabel='step (batch 8)', ylabel='validation loss', title='loss, 64 validation meshes <= 2,048 vertices')
axes[1].plot(steps, [r['edge_f1'] for r in val], 'o-', label="at the model's threshold")
axes[1].plot(steps, [r['edge_f1_best_tau'] for r in val], 's--', label='at the best threshold')
axes[1].set(xlabel='step (batch 8)', ylabel='edge F1', title='decoder edge F1, same meshes')
axes[1].legend()
for ax in axes:
    ax.grid(alpha=0.3)
fig.tight_layout()
fig.savefig(PNG, dpi=110)
print(f'wrote {PNG}')
print('| step | minutes | val loss | edge F1 | F1 at best tau (tau) |')
print('|---:|---:|---:|---:|---:|')
for r in val:
    print(f"| {r['step']} | {r['minutes']:.0f} | {r['val_loss']:.3f} | {r['edge_f1']:.3f} | "
          f"{r['edge_f1_best_tau']:.3f} ({r['best_tau']}) |")
