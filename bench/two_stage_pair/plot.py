"""The DiT trained on the two-stage VAE's latents (shipped since commit c94f408, 2026-11-29) against the DiT
shipped before it, on the three-stage VAE's latents.

Both are `weights/dit.train.json` (192 x 6, reading 256 input points, 6,000 steps of 16 at
lr 3e-4); the earlier one ran in one pass per batch (bench/dit_points/points.metrics.jsonl),
this one in two half-batches at once. Validation flow loss by step, with the training's token
positions (solid) and with inference's (dashed). The two latent spaces differ, so the losses
compare how well each DiT learns its own VAE's latents, not the VAEs.
`python3 bench/two_stage_pair/plot.py [METRICS] [PNG]` (defaults: dit.metrics.jsonl and
dit_loss.png beside this script)."""
import json, os, sys
import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
NEW = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, 'dit.metrics.jsonl')
PNG = sys.argv[2] if len(sys.argv) > 2 else os.path.join(HERE, 'dit_loss.png')
SHIPPED = os.path.join(HERE, '..', 'dit_points', 'points.metrics.jsonl')


def val(path):
    rows = {}
    for r in map(json.loads, open(path)):
        if 'val_loss' in r:
            rows[r['step']] = r  # a resumed run logs a step again: keep the last
    return [rows[s] for s in sorted(rows)]


fig, ax = plt.subplots(figsize=(7, 4.5))
for path, label, colour in [(SHIPPED, 'DiT until c94f408 (three-stage VAE)', 'tab:blue'),
                            (NEW, 'DiT since c94f408 (two-stage VAE)', 'tab:orange')]:
    rows = val(path)
    steps = [r['step'] for r in rows]
    ax.plot(steps, [r['val_loss'] for r in rows], color=colour, label=f'{label}, training positions')
    ax.plot(steps, [r['val_loss_inference_positions'] for r in rows], color=colour, ls='--',
            label=f'{label}, inference positions')
ax.set_xlabel('step (batch 16)')
ax.set_ylabel('validation flow loss')
ax.grid(alpha=0.3)
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(PNG, dpi=110)
print(PNG)
