"""The two-stage candidate (`bash bench/vae_two_stage/run.sh RUN`) against the three-stage
recipe. Left: stage 1, one pass per batch (the reproduction of commit f9b9fd3, bench/vae_repro) against two
half-batches at once (this run), by step. Middle and right: the decoder after stage 1, by
decoder minutes on the 2-core AMD EPYC VM of the run, modelled as steps x the measured step time of each
stage with `--data-parallel 2` (`meshflow bench train-vae`, 30 steps: 346 ms for the
vertex-block stage, 369 ms for a stage with the pair head):
- shipped: 16,000 steps of stage 2 (bench/vae_latent64/position80/ld64_vertex), then 7,000 of
  stage 3 (bench/vae_pair_lr/e_lr3e4);
- f9b9fd3: 7,000 + 6,000 (bench/vae_repro/vertex, pair);
- this run: one 13,500-step stage with the pair head from the start.
Validation (64 meshes): edge F1 at the best tau of the grid, position MSE.
`python3 bench/vae_two_stage/plot.py RUN_METRICS_DIR [PNG]` (default PNG: two_stage.png beside this script), where RUN_METRICS_DIR holds
base.metrics.jsonl and decoder.metrics.jsonl."""
import json, os, sys
import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
BENCH = os.path.join(HERE, '..')
RUN = sys.argv[1] if len(sys.argv) > 1 else HERE
PNG = sys.argv[2] if len(sys.argv) > 2 else os.path.join(HERE, 'two_stage.png')
MS_VERTEX, MS_PAIR = 346.2, 369.1


def val(path):
    return [r for r in map(json.loads, open(path)) if 'val_loss' in r]


def chain(parts):
    """(minutes, F1, position) along stages run one after another: parts = [(path, ms)]."""
    out, t0 = [], 0.0
    for path, ms in parts:
        rows = val(path)
        for r in rows:
            out.append((t0 + r['step'] * ms / 60000.0, r['edge_f1_best_tau'], r['val_position'], r['val_normal']))
        t0 += rows[-1]['step'] * ms / 60000.0
    return out


decoders = [
    ('shipped: 16,000 + 7,000', [(os.path.join(BENCH, 'vae_latent64/position80/ld64_vertex.metrics.jsonl'), MS_VERTEX),
                                 (os.path.join(BENCH, 'vae_pair_lr/e_lr3e4.metrics.jsonl'), MS_PAIR)]),
    ('f9b9fd3: 7,000 + 6,000', [(os.path.join(BENCH, 'vae_repro/vertex.metrics.jsonl'), MS_VERTEX),
                                (os.path.join(BENCH, 'vae_repro/pair.metrics.jsonl'), MS_PAIR)]),
    ('one stage, 13,500 (this run)', [(os.path.join(RUN, 'decoder.metrics.jsonl'), MS_PAIR)]),
]
fig, axes = plt.subplots(1, 3, figsize=(15, 4.6))
for label, path in [('one pass (f9b9fd3)', os.path.join(BENCH, 'vae_repro/base.metrics.jsonl')),
                    ('two half-batches (this run)', os.path.join(RUN, 'base.metrics.jsonl'))]:
    if not os.path.exists(path):
        continue
    rows = val(path)
    axes[0].plot([r['step'] for r in rows], [r['edge_f1_best_tau'] for r in rows], marker='.', label=label)
    print(f"stage 1, {label}: step {rows[-1]['step']}, best-tau F1 {rows[-1]['edge_f1_best_tau']:.4f}, "
          f"position {rows[-1]['val_position']:.5f}")
axes[0].set_title('stage 1 (whole VAE)')
axes[0].set_xlabel('step')
axes[0].set_ylabel('validation edge F1 (best tau)')
for label, parts in decoders:
    if not all(os.path.exists(p) for p, _ in parts):
        continue
    pts = chain(parts)
    axes[1].plot([p[0] for p in pts], [p[1] for p in pts], marker='.', ms=3, label=label)
    axes[2].plot([p[0] for p in pts], [p[2] for p in pts], marker='.', ms=3, label=label)
    m, f1, pos, nrm = pts[-1]
    print(f"decoder, {label}: {m:.0f} min, best-tau F1 {f1:.4f}, position {pos:.5f}, normal {nrm:.5f}")
axes[1].set_title('decoder stages after stage 1')
axes[1].set_ylabel('validation edge F1 (best tau)')
axes[2].set_ylabel('validation position MSE')
axes[2].set_yscale('log')
for ax in axes[1:]:
    ax.set_xlabel('decoder minutes on the 2-core AMD EPYC VM (steps x step time, 2 half-batches)')
for ax in axes:
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(PNG, dpi=110)
print('wrote', PNG)
