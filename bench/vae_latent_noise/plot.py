"""Latent noise in decoder training (run.sh): validation edge F1 and position MSE against wall
time for both arms, the shipped decoder's last validation as a line; writes latent_noise.png
and prints the table of reconstruction and generation on the validation split.
`python3 bench/vae_latent_noise/plot.py [DIR [PNG]]`: DIR holds ARM.metrics.jsonl,
vae_val_ARM.json and generate_val_ARM.json (default: the experiment's data folder,
docs/experiments/data/2026-11-27-latent-noise/); PNG defaults to latent_noise.png there. The
shipped decoder then was stage 2's (docs/experiments/data/2026-11-25-vae-decoder-stage/)."""
import json, os, sys
import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(os.path.dirname(os.path.dirname(HERE)), 'docs', 'experiments', 'data')
DIR = sys.argv[1] if len(sys.argv) > 1 else os.path.join(DATA, '2026-11-27-latent-noise')
PNG = sys.argv[2] if len(sys.argv) > 2 else os.path.join(DIR, 'latent_noise.png')
ARMS = ['noise0.3', 'noise0.75']
shipped = [json.loads(l) for l in open(os.path.join(DATA, '2026-11-25-vae-decoder-stage', 'vae_decoder.metrics.jsonl'))
           if 'val_loss' in l][-1]
fig, axes = plt.subplots(1, 2, figsize=(11, 4))
for arm in ARMS:
    rows = [json.loads(l) for l in open(os.path.join(DIR, f'{arm}.metrics.jsonl'))]
    elapsed = {r['step']: r['elapsed_s'] for r in rows if 'elapsed_s' in r}
    val = [r for r in rows if 'val_loss' in r]
    t = [elapsed[max(s for s in elapsed if s <= r['step'])] / 60 for r in val]
    axes[0].plot(t, [r['edge_f1'] for r in val], marker='.', label=f'latent noise {arm[5:]}')
    axes[1].plot(t, [r['val_position'] for r in val], marker='.', label=f'latent noise {arm[5:]}')
for ax, key, title in [(axes[0], 'edge_f1', 'validation edge F1 (64 meshes)'),
                       (axes[1], 'val_position', 'validation position MSE')]:
    ax.axhline(shipped[key], color='grey', ls='--', lw=1, label='shipped decoder')
    ax.set_title(title); ax.set_xlabel('wall minutes (both arms at once, 2 cores)'); ax.grid(alpha=.3)
axes[0].legend()
fig.tight_layout(); fig.savefig(PNG, dpi=110)
print('| decoder | val edge F1 | vertex x100 | reconstruction CD x100 | generated CD x100 | HD x100 | holes |')
print('|---|---:|---:|---:|---:|---:|---:|')
for arm in ARMS:
    v = json.load(open(os.path.join(DIR, f'vae_val_{arm}.json')))['all']
    g = json.load(open(os.path.join(DIR, f'generate_val_{arm}.json')))['all']['ours']
    print(f"| latent noise {arm[5:]} | {v['edge_f1']:.3f} | {v['vertex_distance_x100']:.2f} | "
          f"{v['chamfer_x100']:.3f} | {g['chamfer_x100']:.3f} | {g['hausdorff_x100']:.2f} | {g['holes']:.2f} |")
