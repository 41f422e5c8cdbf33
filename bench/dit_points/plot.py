"""Does a DiT that reads the input points close the generation gap of the 64-wide VAE?

Validation flow loss against wall-clock time on the 2-core AMD EPYC VM (one thread per run) for
three DiTs on the same 64-wide latents (the latent-64 VAE of commit d693cb9, 2026-11-27; its
decoder-only stage kept stage 1's encoder, so the latents are those of commit 43a7acb,
2026-11-26):

- base: 192 x 6, 10,000 steps at lr 3e-4 (bench/vae_latent64/dit.config.json);
- big: 240 x 8, 10,000 steps (bench/vae_latent64/dit_big.config.json);
- points: 192 x 6 reading 256 input points in every block, 6,000 steps, about the base's
  wall-clock (bench/dit_points/latent64.config.json).

Left: the loss with the tokens at their training positions (their own vertices' voxels);
middle: the same validation meshes with the positions drawn as inference draws them (farthest
points of surface samples), the condition the model meets in use; right: the generated
validation CD of each arm's final weights (FINAL_CD below, from `meshflow eval generate
--split val`), which the losses do not rank.

`python3 bench/dit_points/plot.py [DIR [PNG]]` reads each arm's `<arm>.metrics.jsonl` from DIR
(default: the experiment's data folder, docs/experiments/data/2026-11-28-dit-point-attention/,
which holds base and big), else from this folder (points, the DiT that shipped with the 64-wide
VAE), writes PNG (default: curves.png in DIR) and prints one row per arm. Time is each run's own `elapsed_s` (the
processes of a resumed run joined end to end); runs shared the CPU with other jobs, so a few
percent either way is noise."""
import json, os, sys
import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(os.path.dirname(os.path.dirname(HERE)), 'docs', 'experiments', 'data')
DIR = sys.argv[1] if len(sys.argv) > 1 else os.path.join(DATA, '2026-11-28-dit-point-attention')
PNG = sys.argv[2] if len(sys.argv) > 2 else os.path.join(DIR, 'curves.png')
ARMS = [('base', 'base 192x6'), ('big', 'big 240x8'), ('points', '192x6 + 256 points')]


def curves(path):
    """(minutes, val_loss, val_loss_inference_positions) at each validation, and the run's last
    step and minutes."""
    elapsed, rows, last = {}, [], (0, 0.0)
    # A process that resumed a run without counting the earlier ones' time starts its
    # elapsed_s again from 0: those runs are joined end to end.
    offset, previous = 0.0, 0.0
    for line in open(path):
        r = json.loads(line)
        if 'elapsed_s' in r:
            if r['elapsed_s'] < previous:
                offset += previous
            previous = r['elapsed_s']
            minutes = (offset + r['elapsed_s']) / 60
            elapsed[r['step']] = minutes
            last = (r['step'], minutes)
        elif 'val_loss' in r and r['step'] in elapsed:
            rows.append((elapsed[r['step']], r['val_loss'], r.get('val_loss_inference_positions')))
    return rows, last


# Generated validation CD x100 (`meshflow eval generate --split val`, seed 0) of each arm's final
# weights with the 64-wide decoder of commit 57693dd; the larger DiT's is with the decoder of
# commit 1107f76 (marked), the
# 192 x 6 without points scored 5.089 with that one.
FINAL_CD = {'base': (4.870, ''), 'big': (5.018, " (decoder of 1107f76)"), 'points': (4.372, '')}

fig, axes = plt.subplots(1, 3, figsize=(15, 4))
print('| arm | steps | minutes | val flow loss | with inference positions |')
print('|---|---:|---:|---:|---:|')
for arm, label in ARMS:
    path = os.path.join(DIR, f'{arm}.metrics.jsonl')
    if not os.path.exists(path):
        path = os.path.join(HERE, f'{arm}.metrics.jsonl')
    if not os.path.exists(path):
        continue
    rows, (steps, minutes) = curves(path)
    axes[0].plot([r[0] for r in rows], [r[1] for r in rows], label=label)
    axes[1].plot([r[0] for r in rows], [r[2] for r in rows], label=label)
    print(f'| {label} | {steps} | {minutes:.0f} | {rows[-1][1]:.4f} | {rows[-1][2]:.4f} |')
    cd, note = FINAL_CD[arm]
    axes[2].scatter([minutes], [cd], label=label + note, s=40)
for ax, title in zip(axes[:2], ['training positions', "inference's positions"]):
    ax.set_xlabel('wall-clock minutes (one thread)')
    ax.set_ylabel('validation flow loss')
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend()
axes[2].set_xlabel('wall-clock minutes (one thread)')
axes[2].set_ylabel('generated validation CD x100 (final weights)')
axes[2].set_title('generation')
axes[2].axhline(4.393, color='grey', ls='--', lw=1)
axes[2].text(2, 4.40, "the 64-wide VAE's own reconstructions", fontsize=8, color='grey')
axes[2].axhline(4.552, color='grey', ls=':', lw=1)
axes[2].text(2, 4.56, 'the previous shipped pair', fontsize=8, color='grey')
axes[2].set_xlim(0, None)
axes[2].grid(alpha=0.3)
axes[2].legend(fontsize=8)
fig.tight_layout()
fig.savefig(PNG, dpi=110)
