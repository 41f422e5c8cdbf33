"""docs/experiments/2026-11-27-dit-on-h100.md: validation flow loss against training examples
seen since the 10,000-step DiT, for the three H100 arms (bench/dit_gpu/run.sh) and the CPU
continuation that ships (weights/dit.continue.train.json). Draws dit_gpu.png and prints the
table: `python3 bench/dit_gpu/plot.py [DIR [PNG]]`. DIR holds the H100 arms' ARM.metrics.jsonl
(default: the entry's data folder, docs/experiments/data/2026-11-27-dit-on-h100/); PNG defaults
to dit_gpu.png there. The arms' configurations are the ARM.config.json beside this script; the
CPU continuation's log and that of the DiT they continue are read from their own entries'
data folders."""
import json, os, sys
import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
BENCH = os.path.dirname(HERE)
DATA = os.path.join(os.path.dirname(BENCH), 'docs', 'experiments', 'data')
DIR = sys.argv[1] if len(sys.argv) > 1 else os.path.join(DATA, '2026-11-27-dit-on-h100')
PNG = sys.argv[2] if len(sys.argv) > 2 else os.path.join(DIR, 'dit_gpu.png')
# (label, configuration, training log)
ARMS = [(label, os.path.join(HERE, f'{arm}.config.json'), os.path.join(DIR, f'{arm}.metrics.jsonl'))
        for label, arm in [('H100 b16, lr 1e-4', 'b16'), ('H100 b64, lr 2e-4', 'b64'),
                           ('H100 b256, lr 3e-4', 'b256')]]
ARMS.append(('CPU b16, lr 1e-4 (shipped)',
             os.path.join(BENCH, 'vae_latent64', 'dit32_continued.config.json'),
             os.path.join(DATA, '2026-11-27-dit-trained-longer', 'dit32_continued.metrics.jsonl')))

def rows(path):
    return [json.loads(l) for l in open(path) if l.strip()]

fig, ax = plt.subplots(figsize=(7, 4.2))
print('| arm | steps | examples | wall s | examples/s | val flow loss (last) |')
print('|---|---:|---:|---:|---:|---:|')
for label, config, log in ARMS:
    cfg = json.load(open(config))
    rs = rows(log)
    val = [r for r in rs if 'val_loss' in r]
    train = [r for r in rs if 'lr' in r]
    b = cfg['batch_size']
    ax.plot([r['step'] * b for r in val], [r['val_loss'] for r in val], marker='o', ms=3, label=label)
    wall = train[-1]['elapsed_s']
    print(f"| {label} | {train[-1]['step']} | {train[-1]['step'] * b} | {wall:.0f} | "
          f"{train[-1]['step'] * b / wall:.0f} | {val[-1]['val_loss']:.4f} |")
# Where every arm started: the last validation of the 10,000-step DiT they continue.
start = [r for r in rows(os.path.join(DATA, '2026-11-25-dit-10000-steps', 'dit.metrics.jsonl'))
         if 'val_loss' in r][-1]
ax.axhline(start['val_loss'], color='gray', ls=':', label=f"the DiT they continue ({start['val_loss']:.3f})")
ax.set_xlabel('training examples since the shipped DiT')
ax.set_ylabel('validation flow loss')
ax.set_title('The shipped DiT, continued: three H100 arms and the CPU run')
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(PNG, dpi=110)
