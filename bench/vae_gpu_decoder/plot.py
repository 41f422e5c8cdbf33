"""Validation curves of the decoder-only arms trained on an H100 (ARM/metrics.jsonl in DIR)
beside the two CPU stages of the VAE shipped then (docs/experiments/data/2026-11-24-vae-stage-1/
and 2026-11-25-vae-decoder-stage/), against meshes seen (steps x batch):
`python3 bench/vae_gpu_decoder/plot.py [DIR [PNG]]` writes PNG (default: gpu_decoder.png in DIR)
and prints the table. DIR defaults to the experiment's data folder,
docs/experiments/data/2026-11-26-gpu-decoder/; the arms' configurations stay beside this
script (ARM/config.json)."""
import json, os, sys
import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(os.path.dirname(os.path.dirname(HERE)), 'docs', 'experiments', 'data')
DIR = sys.argv[1] if len(sys.argv) > 1 else os.path.join(DATA, '2026-11-26-gpu-decoder')
PNG = sys.argv[2] if len(sys.argv) > 2 else os.path.join(DIR, 'gpu_decoder.png')


def curve(path, batch, offset=0):
    rows = [json.loads(l) for l in open(path)]
    val = [r for r in rows if 'val_loss' in r]
    train = [r for r in rows if 'lr' in r]
    elapsed = {r['step']: r['elapsed_s'] for r in train}
    return [dict(r, meshes=offset + r['step'] * batch, elapsed_s=elapsed.get(r['step'], float('nan'))) for r in val]


# name, metrics, batch, meshes already seen by the weights it started from, label
runs = [
    ('stage 1 (shipped encoder; CPU)', os.path.join(DATA, '2026-11-24-vae-stage-1', 'vae.metrics.jsonl'), 8, 0),
    ('stage 2: shipped decoder (CPU)',
     os.path.join(DATA, '2026-11-25-vae-decoder-stage', 'vae_decoder.metrics.jsonl'), 8, 80_000),
    ('H100: shipped decoder, continued', os.path.join(DIR, 'cont', 'metrics.jsonl'), 32, 192_000),
    ('H100: new decoder 256 x 4', os.path.join(DIR, 'w256d4', 'metrics.jsonl'), 32, 0),
    ('H100: new decoder 192 x 6', os.path.join(DIR, 'w192d6', 'metrics.jsonl'), 32, 0),
]
cpu_more = os.path.join(DIR, 'w256d4_cpu', 'metrics.jsonl')
if os.path.exists(cpu_more):
    runs.append(('256 x 4, continued on the CPU', cpu_more, 16, 55_840))

fig, axes = plt.subplots(1, 3, figsize=(16, 4.6))
print('| run | meshes seen | wall s | val edge F1 | P / R | position MSE | normal MSE |')
print('|---|---:|---:|---:|---|---:|---:|')
for name, path, batch, offset in runs:
    c = curve(path, batch, offset)
    x = [r['meshes'] / 1000 for r in c]
    for ax, key in zip(axes, ['edge_f1', 'val_position', 'val_normal']):
        ax.plot(x, [r[key] for r in c], label=name, lw=1.4)
    last = c[-1]
    print(f"| {name} | {last['meshes']:,} | {last['elapsed_s']:.0f} | {last['edge_f1']:.3f} | "
          f"{last['edge_precision']:.3f} / {last['edge_recall']:.3f} | {last['val_position']:.5f} | {last['val_normal']:.4f} |")
for ax, title in zip(axes, ['validation edge F1', 'validation position MSE', 'validation normal MSE']):
    ax.set_title(title); ax.set_xlabel('meshes seen (thousands)'); ax.grid(alpha=.3)
axes[1].set_yscale('log'); axes[2].set_yscale('log'); axes[1].set_ylim(4e-3, 3e-2); axes[2].set_ylim(1.5e-2, 0.3)
axes[0].set_ylim(0.3, 0.7)
axes[0].legend(fontsize=8, loc='lower right')
fig.tight_layout()
fig.savefig(PNG, dpi=110)
