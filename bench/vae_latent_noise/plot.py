"""Latent noise in decoder training (run.sh): validation edge F1 and position MSE against wall
time for both arms, the shipped decoder's last validation as a line; writes latent_noise.png
and prints the table of reconstruction and generation on the validation split."""
import json, os
import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
ARMS = ['noise0.3', 'noise0.75']
shipped = [json.loads(l) for l in open(os.path.join(HERE, '..', 'training', 'vae_decoder.metrics.jsonl'))
           if 'val_loss' in l][-1]
fig, axes = plt.subplots(1, 2, figsize=(11, 4))
for arm in ARMS:
    rows = [json.loads(l) for l in open(os.path.join(HERE, f'{arm}.metrics.jsonl'))]
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
fig.tight_layout(); fig.savefig(os.path.join(HERE, 'latent_noise.png'), dpi=110)
print('| decoder | val edge F1 | vertex x100 | reconstruction CD x100 | generated CD x100 | HD x100 | holes |')
print('|---|---:|---:|---:|---:|---:|---:|')
for arm in ARMS:
    v = json.load(open(os.path.join(HERE, f'vae_val_{arm}.json')))['all']
    g = json.load(open(os.path.join(HERE, f'generate_val_{arm}.json')))['all']['ours']
    print(f"| latent noise {arm[5:]} | {v['edge_f1']:.3f} | {v['vertex_distance_x100']:.2f} | "
          f"{v['chamfer_x100']:.3f} | {g['chamfer_x100']:.3f} | {g['hausdorff_x100']:.2f} | {g['holes']:.2f} |")
