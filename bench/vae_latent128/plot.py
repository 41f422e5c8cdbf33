"""The VAE at latent_dim 128 against the shipped 64, the shipped two-stage recipe otherwise
(stage 1: the whole VAE, 10,000 steps; stage 2: the decoder alone with a vertex block, 16,000
steps), seed and data the same, step for step on validation (64 meshes). `python3
bench/vae_latent128/plot.py [DIR [PNG]]` writes PNG (default: latent128.png in DIR) and prints
the table. Logs: the 64-wide run's stage 1 in docs/experiments/data/2026-11-26-latent-64/
(metrics.jsonl) and its stage 2 in bench/vae_latent64/position80/ld64_vertex.metrics.jsonl, the
128-wide run's in DIR (base.metrics.jsonl, vertex.metrics.jsonl: validation lines and every
10th step; default: the experiment's data folder, docs/experiments/data/2026-11-28-latent-128/)."""
import json, os, sys
import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(os.path.dirname(os.path.dirname(HERE)), 'docs', 'experiments', 'data')
DIR = sys.argv[1] if len(sys.argv) > 1 else os.path.join(DATA, '2026-11-28-latent-128')
PNG = sys.argv[2] if len(sys.argv) > 2 else os.path.join(DIR, 'latent128.png')
L64 = os.path.join(HERE, '..', 'vae_latent64')
runs = [('latent_dim 64 (shipped)', (os.path.join(DATA, '2026-11-26-latent-64', 'metrics.jsonl'),
                                     os.path.join(L64, 'position80', 'ld64_vertex.metrics.jsonl'))),
        ('latent_dim 128', (os.path.join(DIR, 'base.metrics.jsonl'),
                            os.path.join(DIR, 'vertex.metrics.jsonl')))]


def validation(logs):
    """Validation lines of both stages, stage 2's steps counted on from stage 1's last."""
    rows, offset = [], 0
    for path in logs:
        if not os.path.exists(path):
            continue
        stage = [json.loads(l) for l in open(path) if 'val_loss' in l]
        for r in stage:
            r['step'] += offset
        rows += stage
        offset = stage[-1]['step'] if stage else offset
    return rows


curves = {name: validation(logs) for name, logs in runs}
fig, axes = plt.subplots(1, 3, figsize=(15, 4.2))
for name, rows in curves.items():
    s = [r['step'] for r in rows]
    axes[0].plot(s, [r.get('edge_f1_best_tau', r['edge_f1']) for r in rows], label=name)
    axes[1].plot(s, [r['val_position'] for r in rows], label=name)
    axes[2].plot(s, [r['val_normal'] for r in rows], label=name)
for ax, title in zip(axes, ['edge F1 (best tau of the grid)', 'position MSE', 'normal MSE']):
    ax.set_title(title)
    ax.set_xlabel('step (stage 2 from 10,000)')
    ax.axvline(10000, color='grey', lw=0.5)
    ax.grid(alpha=0.3)
axes[1].set_yscale('log')
axes[2].set_yscale('log')
axes[0].legend()
fig.tight_layout()
fig.savefig(PNG, dpi=90)

by_step = {name: {r['step']: r for r in rows} for name, rows in curves.items()}
names = list(by_step)
print('| step | edge F1, best tau (64 / 128) | position MSE (64 / 128) | normal MSE (64 / 128) |')
print('|---:|---|---|---|')
common = sorted(set(by_step[names[0]]) & set(by_step[names[1]]))
for step in common:
    if step % 2000 and step != common[-1]:
        continue
    a, b = by_step[names[0]][step], by_step[names[1]][step]
    f1 = lambda r: r.get('edge_f1_best_tau', r['edge_f1'])
    print(f"| {step:,} | {f1(a):.3f} / {f1(b):.3f} | {a['val_position']:.5f} / {b['val_position']:.5f} "
          f"| {a['val_normal']:.4f} / {b['val_normal']:.4f} |")
