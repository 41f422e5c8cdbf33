"""BENCHMARKS.md "The shipped DiT, trained 4,000 steps longer" (its H100 part): validation flow
loss against training examples seen since the 10,000-step DiT, for the three H100 arms
(bench/dit_gpu/run.sh) and the CPU continuation that ships (weights/dit.continue.train.json).
Draws dit_gpu.png and prints the table: `python3 bench/dit_gpu/plot.py`."""
import json, os
import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
ARMS = [('H100 b16, lr 1e-4', 'b16'), ('H100 b64, lr 2e-4', 'b64'), ('H100 b256, lr 3e-4', 'b256'),
        ('CPU b16, lr 1e-4 (shipped)', '../vae_latent64/dit32_continued')]

def rows(path):
    return [json.loads(l) for l in open(path) if l.strip()]

fig, ax = plt.subplots(figsize=(7, 4.2))
print('| arm | steps | examples | wall s | examples/s | val flow loss (last) |')
print('|---|---:|---:|---:|---:|---:|')
for label, stem in ARMS:
    cfg = json.load(open(os.path.join(HERE, f'{stem}.config.json')))
    rs = rows(os.path.join(HERE, f'{stem}.metrics.jsonl'))
    val = [r for r in rs if 'val_loss' in r]
    train = [r for r in rs if 'lr' in r]
    b = cfg['batch_size']
    ax.plot([r['step'] * b for r in val], [r['val_loss'] for r in val], marker='o', ms=3, label=label)
    wall = train[-1]['elapsed_s']
    print(f"| {label} | {train[-1]['step']} | {train[-1]['step'] * b} | {wall:.0f} | "
          f"{train[-1]['step'] * b / wall:.0f} | {val[-1]['val_loss']:.4f} |")
# Where every arm started: the last validation of the 10,000-step DiT they continue.
start = [r for r in rows(os.path.join(HERE, '..', 'training', 'dit.metrics.jsonl')) if 'val_loss' in r][-1]
ax.axhline(start['val_loss'], color='gray', ls=':', label=f"the DiT they continue ({start['val_loss']:.3f})")
ax.set_xlabel('training examples since the shipped DiT')
ax.set_ylabel('validation flow loss')
ax.set_title('The shipped DiT, continued: three H100 arms and the CPU run')
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(os.path.join(HERE, 'dit_gpu.png'), dpi=110)
