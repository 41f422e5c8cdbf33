"""Does more DiT training close the generation gap of the 64-wide VAE? Flow loss on validation
against training step, and the generated validation CD (12 candidates of 7 steps, `meshflow eval
generate --split val`) at each checkpoint that was evaluated, for:

- the 64-wide DiT: dit.* (10,000 steps at lr 3e-4), then dit_continued.* (4,000 more at 1e-4),
  then dit_continued2.* (10,000 more at 1e-4), each stage started from the last one's weights;
- a larger DiT on the 64-wide latents, width 240 and depth 8 (9.6 M parameters against 4.7 M),
  10,000 steps at lr 3e-4 from scratch (dit_big.*; commit c80fa83, 2026-11-27);
- the shipped 32-wide DiT (docs/experiments/data/2026-11-25-dit-10000-steps/dit.metrics.jsonl),
  and the same continued 4,000 steps at 1e-4 (dit32_continued.*), the control for "more steps"
  on the shipped latents.

Each CD is `meshflow eval generate --split val` at seed 0 and, where a `*_seed1.json` file
exists, again with `--seed 1` (the same weights, other sampling noise): the spread between
the two is the noise of one evaluation. `python3 bench/vae_latent64/plot_dit.py [PNG]` writes
PNG (default: docs/experiments/data/2026-11-27-dit-trained-longer/dit_longer.png) and prints the
table. The logs and evaluations are read from the data folders of the entries that ran them:
docs/experiments/data/2026-11-26-latent-64/ (dit.*, dit_continued.*), 2026-11-27-dit-trained-longer/
(dit_continued2.*, dit32_continued.*, the shipped pair's evaluations) and
2026-11-27-larger-dit-latent-64/ (dit_big.*). Flow losses of the two latent widths are not
comparable with each other (different latent scales); the CDs are."""
import json, os, sys
import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(os.path.dirname(os.path.dirname(HERE)), 'docs', 'experiments', 'data')
PNG = sys.argv[1] if len(sys.argv) > 1 else os.path.join(DATA, '2026-11-27-dit-trained-longer', 'dit_longer.png')
ENTRIES = ['2026-11-26-latent-64', '2026-11-27-dit-trained-longer', '2026-11-27-larger-dit-latent-64']


def find(name):
    """The file of that name in the data folder of the entry that logged it."""
    for entry in ENTRIES:
        path = os.path.join(DATA, entry, name)
        if os.path.exists(path):
            return path
    return os.path.join(DATA, ENTRIES[0], name)


def val_losses(stages):
    """(step, val_loss) of consecutive stages, each stage's steps counted on from the last."""
    rows, offset = [], 0
    for path in stages:
        stage = [json.loads(l) for l in open(path) if 'val_loss' in l]
        rows += [(offset + r['step'], r['val_loss']) for r in stage]
        offset += max(json.loads(l)['step'] for l in open(path))
    return rows


def ours(name):
    return json.load(open(find(name)))['all']['ours']


def seed1(name):
    """The same evaluation with `--seed 1`: the sampling noise, not the weights, differs."""
    return name.replace('.json', '_seed1.json')


ARMS = {
    'latent_dim 64': dict(
        stages=[find(f) for f in
                ('dit.metrics.jsonl', 'dit_continued.metrics.jsonl', 'dit_continued2.metrics.jsonl')],
        evals=[(10_000, 'generate_eval_val.json'), (14_000, 'generate_eval_val_dit_continued.json'),
               (24_000, 'generate_eval_val_dit_continued2.json')]),
    'latent_dim 64, larger DiT (width 240, depth 8)': dict(
        stages=[find('dit_big.metrics.jsonl')],
        evals=[(10_000, 'generate_eval_val_dit_big.json')]),
    'latent_dim 32 (shipped: 10,000 + 4,000 steps)': dict(
        stages=[os.path.join(DATA, '2026-11-25-dit-10000-steps', 'dit.metrics.jsonl'),
                find('dit32_continued.metrics.jsonl')],
        evals=[(10_000, 'generate_eval_val_shipped.json'), (14_000, 'generate_eval_val_dit32_continued.json')]),
}

fig, (ax_loss, ax_cd) = plt.subplots(1, 2, figsize=(12, 4.4))
print('| DiT | steps | flow val loss | val CD x100, seed 0 / 1 | mean | holes, seed 0 / 1 |')
print('|---|---:|---:|---|---:|---|')
for name, arm in ARMS.items():
    losses = val_losses(arm['stages'])
    ax_loss.plot(*zip(*losses), label=name, lw=1.4)
    loss_at = dict(losses)
    steps, means = [], []
    for step, f in arm['evals']:
        # Seed 0 is the file named in ARMS; a second sampling seed, where run, beside it.
        seeds = [ours(f)] + ([ours(seed1(f))] if os.path.exists(find(seed1(f))) else [])
        cds = [o['chamfer_x100'] for o in seeds]
        steps.append(step); means.append(sum(cds) / len(cds))
        ax_cd.scatter([step] * len(cds), cds, s=12, color='grey', zorder=3)
        cd_text = ' / '.join(f'{c:.3f}' for c in cds)
        holes_text = ' / '.join(f"{o['holes']:.2f}" for o in seeds)
        print(f"| {name} | {step:,} | {loss_at.get(step, float('nan')):.4f} | {cd_text} | {means[-1]:.3f} | {holes_text} |")
    ax_cd.plot(steps, means, 'o-', label=f'{name}, mean over seeds')
for ax in (ax_loss, ax_cd):
    ax.set_xlabel('DiT training step (batch 16)'); ax.grid(alpha=.3); ax.legend(fontsize=8, loc='upper right')
    for boundary in (10_000, 14_000):
        ax.axvline(boundary, color='grey', lw=0.8, ls=':')
ax_loss.set_title('flow-matching loss, validation'); ax_loss.set_yscale('log')
ax_cd.set_title('generated CD x100, validation (grey: each sampling seed)')
fig.tight_layout(); fig.savefig(PNG, dpi=110)
