"""The VAE at latent_dim 64 against the shipped latent_dim 32, same two-stage recipe, seed and
data, step for step: stage 1 trains the whole VAE for 10,000 steps, stage 2 the decoder alone
for 14,000 more (its steps are drawn after stage 1's). `python3 bench/vae_latent64/plot.py
[DIR [PNG]]` writes PNG (default: latent64.png in DIR) and prints the table. Logs: the VAE
shipped then in docs/experiments/data/2026-11-24-vae-stage-1/ (vae.metrics.jsonl) and
2026-11-25-vae-decoder-stage/ (vae_decoder.metrics.jsonl), the 64-wide one's in DIR
(metrics.jsonl, decoder.metrics.jsonl: stage 2's validation lines and every 10th step; default:
the experiment's data folder, docs/experiments/data/2026-11-26-latent-64/)."""
import json, os, sys
import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(os.path.dirname(os.path.dirname(HERE)), 'docs', 'experiments', 'data')
DIR = sys.argv[1] if len(sys.argv) > 1 else os.path.join(DATA, '2026-11-26-latent-64')
PNG = sys.argv[2] if len(sys.argv) > 2 else os.path.join(DIR, 'latent64.png')
runs = [('latent_dim 32 (shipped)', (os.path.join(DATA, '2026-11-24-vae-stage-1', 'vae.metrics.jsonl'),
                                      os.path.join(DATA, '2026-11-25-vae-decoder-stage', 'vae_decoder.metrics.jsonl'))),
        ('latent_dim 64', (os.path.join(DIR, 'metrics.jsonl'), os.path.join(DIR, 'decoder.metrics.jsonl')))]


def validation(logs):
    """Validation lines of both stages, stage 2's steps counted on from stage 1's last."""
    stage1, stage2 = logs
    rows = [json.loads(l) for l in open(stage1) if 'val_loss' in l]
    offset = rows[-1]['step']
    for l in open(stage2):
        if 'val_loss' in l:
            r = json.loads(l); r['step'] += offset; rows.append(r)
    return rows


curves = {}
fig, axes = plt.subplots(1, 3, figsize=(16, 4.6))
for name, logs in runs:
    val = validation(logs)
    curves[name] = {r['step']: r for r in val}
    for ax, key in zip(axes, ['edge_f1', 'val_position', 'val_normal']):
        ax.plot([r['step'] for r in val], [r[key] for r in val], label=name, lw=1.4)
for ax, title in zip(axes, ['validation edge F1', 'validation position MSE', 'validation normal MSE']):
    ax.set_title(title); ax.set_xlabel('step (batch 8); stage 2 (decoder alone) after 10,000')
    ax.axvline(10_000, color='grey', lw=0.8, ls=':'); ax.grid(alpha=.3)
axes[1].set_yscale('log'); axes[2].set_yscale('log'); axes[0].legend(loc='lower right')
fig.tight_layout(); fig.savefig(PNG, dpi=110)
a, b = (curves[n] for n, _ in runs)
common = sorted(set(a) & set(b))
print('| step | F1 (32 / 64) | position MSE (32 / 64) | normal MSE (32 / 64) |')
print('|---:|---|---|---|')
for step in common:
    if step % 4000 == 0 or step in (10_000, common[-1]):
        x, y = a[step], b[step]
        print(f"| {step:,} | {x['edge_f1']:.3f} / {y['edge_f1']:.3f} | {x['val_position']:.5f} / {y['val_position']:.5f} | {x['val_normal']:.4f} / {y['val_normal']:.4f} |")
