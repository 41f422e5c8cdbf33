"""The end-to-end reproduction (`bash scripts/train_vae.sh RUN`, commit f9b9fd3, 2026-11-28) against the runs it
replaces. Stage 2: 7,000 steps here against the 16,000 of the VAE shipped until commit 8e0d5bb
(bench/vae_latent64/position80/ld64_vertex); stage 3: this stage 2 continued by the pair-head
stage against the same stage on the 16,000-step stage 2 (bench/vae_pair_lr/e_lr3e4).
Validation (64 meshes) edge F1 at the best tau of the grid and position MSE against steps.
`python3 bench/vae_repro/plot.py [PNG]` (reads the thinned logs beside it; PNG defaults to
docs/experiments/data/2026-11-28-vae-recipe-147-minutes/repro.png)."""
import json, os, sys
import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
PNG = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
    HERE, '..', '..', 'docs', 'experiments', 'data', '2026-11-28-vae-recipe-147-minutes', 'repro.png')


def val(path):
    return [r for r in map(json.loads, open(path)) if 'val_loss' in r]


stages = [
    ('stage 2 (decoder, vertex block)', [
        ('7,000 steps (this command)', os.path.join(HERE, 'vertex.metrics.jsonl')),
        ('16,000 steps (shipped until 8e0d5bb)', os.path.join(HERE, '..', 'vae_latent64', 'position80', 'ld64_vertex.metrics.jsonl'))]),
    ('stage 3 (pair head, lr 3e-4)', [
        ('on the 7,000-step stage 2 (this command)', os.path.join(HERE, 'pair.metrics.jsonl')),
        ('on the 16,000-step stage 2 (shipped until 8e0d5bb)', os.path.join(HERE, '..', 'vae_pair_lr', 'e_lr3e4.metrics.jsonl'))]),
]
fig, axes = plt.subplots(2, 2, figsize=(11, 7.5))
for col, (title, runs) in enumerate(stages):
    for label, path in runs:
        rows = val(path)
        steps = [r['step'] for r in rows]
        axes[0, col].plot(steps, [r['edge_f1_best_tau'] for r in rows], marker='.', label=label)
        axes[1, col].plot(steps, [r['val_position'] for r in rows], marker='.', label=label)
        last = rows[-1]
        print(f"{title}, {label}: step {last['step']}, best-tau F1 {last['edge_f1_best_tau']:.4f}, "
              f"position {last['val_position']:.5f}, normal {last['val_normal']:.5f}")
    axes[0, col].set_title(title)
    axes[0, col].set_ylabel('validation edge F1 (best tau)')
    axes[1, col].set_ylabel('validation position MSE')
    axes[1, col].set_yscale('log')
    for ax in axes[:, col]:
        ax.set_xlabel('step')
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(PNG, dpi=110)
print('wrote', PNG)
