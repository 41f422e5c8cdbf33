"""Stage 1 of the VAE at latent_dim 64 against the shipped stage 1 (latent_dim 32), same
schedule, seed and data, step for step: `python3 bench/vae_latent64/plot.py` writes
latent64.png and prints the table (bench/vae_latent64/metrics.jsonl: this run's log)."""
import json, os
import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
runs = [('latent_dim 32 (shipped stage 1)', os.path.join(HERE, '..', 'training', 'vae.metrics.jsonl')),
        ('latent_dim 64', os.path.join(HERE, 'metrics.jsonl'))]
curves = {}
fig, axes = plt.subplots(1, 3, figsize=(16, 4.6))
for name, path in runs:
    val = [json.loads(l) for l in open(path) if 'val_loss' in l]
    curves[name] = {r['step']: r for r in val}
    for ax, key in zip(axes, ['edge_f1', 'val_position', 'val_normal']):
        ax.plot([r['step'] for r in val], [r[key] for r in val], label=name, lw=1.4)
for ax, title in zip(axes, ['validation edge F1', 'validation position MSE', 'validation normal MSE']):
    ax.set_title(title); ax.set_xlabel('step (batch 8)'); ax.grid(alpha=.3)
axes[1].set_yscale('log'); axes[2].set_yscale('log'); axes[0].legend(loc='lower right')
fig.tight_layout(); fig.savefig(os.path.join(HERE, 'latent64.png'), dpi=110)
a, b = (curves[n] for n, _ in runs)
print('| step | F1 (32 / 64) | position MSE (32 / 64) | normal MSE (32 / 64) |')
print('|---:|---|---|---|')
for step in sorted(set(a) & set(b)):
    if step % 2000 == 0 or step == max(set(a) & set(b)):
        x, y = a[step], b[step]
        print(f"| {step:,} | {x['edge_f1']:.3f} / {y['edge_f1']:.3f} | {x['val_position']:.5f} / {y['val_position']:.5f} | {x['val_normal']:.4f} / {y['val_normal']:.4f} |")
