"""One decoder stage against the shipped two: validation edge F1 (at the best tau of the grid)
and position MSE against decoder-only wall time, for the arms of run.sh and for the shipped
path (stage 2, then stage 3 from its end; docs/experiments/data/2026-11-25-vae-decoder-stage/
and 2026-11-27-vertex-attention/). Stage 2 logged F1 at tau 0.6 only, which the whole-split tau
sweep found flat in tau for it, so that stands for its best.
`python3 bench/vae_one_stage/plot.py [--steps] [DIR ...] [PNG]`: each DIR holds
ARM.metrics.jsonl or ARM/metrics.jsonl (default: the thinned logs of
docs/experiments/data/2026-11-27-one-decoder-stage/, which one_stage.png there draws; with D
for docs/experiments/data: the position-weight pair, `plot.py D/2026-11-27-one-decoder-stage/position_weight`,
which writes position_weight.png beside it; the full-length position weights, `plot.py --steps
D/2026-11-27-position-weight/position_full`; latent 64 against 32 at the shipped recipe,
`plot.py --steps D/2026-11-27-latent-64-decoder/position80 bench/vae_latent64/position80`);
PNG (a name ending in .png) defaults to DIR.png beside the first DIR, or one_stage.png for the
default. Prints each curve's last validation. `--steps` puts training steps on the x axis
instead of wall time, for arms that did not run under the same conditions (the position_full
arms ran alone, beside CI or beside each other)."""
import glob, json, os, sys
import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(os.path.dirname(os.path.dirname(HERE)), 'docs', 'experiments', 'data')
ARGS = [a for a in sys.argv[1:] if a != '--steps']
BY_STEPS = '--steps' in sys.argv[1:]
DIRS = [a for a in ARGS if not a.endswith('.png')]
PNGS = [a for a in ARGS if a.endswith('.png')]
# Default: one_stage.png beside the logs of the one-stage arms, else DIR.png beside the first DIR.
DEFAULT = os.path.join(DATA, '2026-11-27-one-decoder-stage')
PNG = PNGS[0] if PNGS else (
    os.path.join(DEFAULT, 'one_stage.png') if not DIRS else os.path.normpath(DIRS[0]) + '.png')
DIRS = DIRS or [DEFAULT]
LABELS = {'a_vertex1': 'one stage, 1 vertex block (16,000 steps)',
          'b_vertex2': 'one stage, 2 vertex blocks (12,000 steps)',
          'c_short_position10': 'one stage, 1 block, 8,000 steps, position weight 10',
          'd_short_position20': 'one stage, 1 block, 8,000 steps, position weight 20',
          'e_vertex1_position20': 'one stage, 1 block, 16,000 steps, position weight 20',
          'f_vertex1_position40': 'one stage, 1 block, 16,000 steps, position weight 40',
          'g_vertex1_position80': 'one stage, 1 block, 16,000 steps, position weight 80',
          'h_vertex1_position160': 'one stage, 1 block, 16,000 steps, position weight 160',
          'ld64_vertex': 'latent 64: one stage, 1 block, 16,000 steps, position weight 80'}
COLOURS = ['grey', 'tab:blue', 'tab:orange', 'tab:green', 'tab:red', 'tab:purple', 'tab:brown',
           'tab:pink', 'tab:olive', 'tab:cyan']


def load(path, offset=0.0, step_offset=0):
    rows = [json.loads(l) for l in open(path)]
    elapsed = {r['step']: r['elapsed_s'] for r in rows if 'elapsed_s' in r}
    val = [r for r in rows if 'val_loss' in r]
    for r in val:  # validation lines carry no time: the last step line's at or before
        r['minutes'] = (elapsed[max(s for s in elapsed if s <= r['step'])] + offset) / 60
        r['f1'] = r.get('edge_f1_best_tau', r['edge_f1'])
        r['x'] = r['step'] + step_offset if BY_STEPS else r['minutes']
    return val


stage2 = load(os.path.join(DATA, '2026-11-25-vae-decoder-stage', 'vae_decoder.metrics.jsonl'))
stage2_s = stage2[-1]['minutes'] * 60
stage2_steps = stage2[-1]['step']
shipped = stage2 + load(os.path.join(DATA, '2026-11-27-vertex-attention', 'vae_vertex.metrics.jsonl'),
                        stage2_s, stage2_steps)
curves = {'shipped: stage 2 (alone), then stage 3 (alone)': shipped}
paths = {}
for DIR in DIRS:
    paths.update({os.path.basename(p)[:-len('.metrics.jsonl')]: p
                  for p in glob.glob(os.path.join(DIR, '*.metrics.jsonl'))})
    paths.update({os.path.basename(os.path.dirname(p)): p
                  for p in glob.glob(os.path.join(DIR, '*', 'metrics.jsonl'))})
for arm in sorted(paths):
    curves[LABELS.get(arm, arm)] = load(paths[arm])

fig, axes = plt.subplots(1, 2, figsize=(13, 4.4))
print('| decoder | steps | minutes | best-tau F1 (tau) | position MSE |')
print('|---|---:|---:|---|---:|')
assert len(curves) <= len(COLOURS), f'{len(curves)} curves, {len(COLOURS)} colours'
for (label, val), c in zip(curves.items(), COLOURS):
    t = [r['x'] for r in val]
    axes[0].plot(t, [r['f1'] for r in val], marker='.', label=label, color=c)
    axes[1].plot(t, [r['val_position'] for r in val], marker='.', label=label, color=c)
    last = val[-1]
    print(f"| {label} | {last['step']:,} | {last['minutes']:.0f} | {last['f1']:.3f} "
          f"({last.get('best_tau', 0.6):g}) | {last['val_position']:.5f} |")
axes[0].axvline(stage2_steps if BY_STEPS else stage2_s / 60, color='grey', ls=':', lw=1)
for ax, title in zip(axes, ['validation edge F1 at the best tau (pooled, 64 meshes)',
                            'validation position MSE (model frame)']):
    ax.set_title(title); ax.grid(alpha=.3)
    ax.set_xlabel('decoder-only training steps (batch 8)' if BY_STEPS
                  else 'decoder-only wall minutes (the arms at once, one core each)')
axes[0].legend(loc='lower right', fontsize=8)
axes[1].set_ylim(top=0.0075)
fig.tight_layout(); fig.savefig(PNG, dpi=110)
