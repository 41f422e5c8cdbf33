#!/usr/bin/env python3
"""Can the faceting features survive a noisy scan if the cloud is denoised first (issue 15
item 5)? A prototype, not product code.

    python3 bench/budget_robust.py [SHARDS] [-o docs/experiments/data/2026-11-29-budget-planar-share/budget_robust.json] [--limit N]

bench/budget_facets.py found that the share of the points lying in flat facets predicts the
artist's vertex count better than the shipped rule's two features (validation R^2 0.27 against
0.10), but that Gaussian noise erases the facets, so a rule using it would ask a scan for the
most vertices it gives. Here every cloud (training ones too) is first denoised by projecting
each point onto the least-squares plane of its `k` nearest neighbours, `rounds` times: a
flat facet is a fixed point of that projection, so a clean low-poly cloud barely moves, while
noise shrinks by about the square root of `k` per round. The features of bench/budget_facets.py
are then read on the denoised cloud. It reports R^2 on validation and test (clean), and how
far the noisy clouds' predicted counts move from the clean ones' (mean and spread of
ln(V noisy / V clean) on validation, Gaussian noise of sigma 0.01 and 0.02 in the model frame,
i.e. 0.5% and 1% of the longest side: `meshflow eval generate --noise 0.01` is the latter),
and whether a clean cloud's local plane residual tells it from a noisy one (the percentiles
of `residual` on validation). `--limit 150` (the figures in
docs/experiments/2026-11-29-budget-planar-share.md) takes about ten minutes on 2 cores.
Needs numpy and scipy."""
import json, os, sys, time
import numpy as np
from scipy.spatial import cKDTree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from shards import meshes, surface_points
from budget_facets import features, model_frame

SHARDS = os.path.expanduser(sys.argv[1] if len(sys.argv) > 1 and not sys.argv[1].startswith('-') else '~/.cache/meshflow/data/shards')
OUT = sys.argv[sys.argv.index('-o') + 1] if '-o' in sys.argv else None
LIMIT = int(sys.argv[sys.argv.index('--limit') + 1]) if '--limit' in sys.argv else None
MAX_V, SIGMAS = 512, (0.01, 0.02)
# (neighbours, rounds) of the denoising; (0, 0) is none.
DENOISE = [(0, 0), (16, 2), (32, 2), (32, 4)]


def denoise(q, k, rounds):
    """Each point projected onto the plane of its k nearest neighbours, `rounds` times."""
    for _ in range(rounds):
        _, nb = cKDTree(q).query(q, k)
        centre = q[nb].mean(1)
        c = q[nb] - centre[:, None]
        _, evec = np.linalg.eigh(np.einsum('nki,nkj->nij', c, c))
        normal = evec[:, :, 0]
        q = q - np.einsum('ni,ni->n', q - centre, normal)[:, None] * normal
    return q


def residual(q, k=12):
    """The median over points of the RMS distance of a point's k nearest neighbours from
    their plane, in median point spacings: what a noise detector would read."""
    d, nb = cKDTree(q).query(q, k)
    c = q[nb] - q[nb].mean(1, keepdims=True)
    smallest = np.linalg.eigvalsh(np.einsum('nki,nkj->nij', c, c) / k)[:, 0]
    return float(np.median(np.sqrt(np.maximum(smallest, 0))) / np.median(d[:, 1]))


def rows(split, noisy):
    rng = np.random.default_rng(0); out = []
    for count, (_, v, f) in enumerate(meshes(SHARDS, (split,), MAX_V)):
        if LIMIT and count >= LIMIT: break
        if len(f) == 0: continue
        p = surface_points(v.astype(np.float64), f.astype(np.int64), rng)
        if p is None: continue
        q = model_frame(p)
        clouds = {'clean': q}
        if noisy:
            for s in SIGMAS:
                clouds[s] = model_frame(q + rng.normal(0, s, q.shape))
        row = {'lnV': float(np.log(len(v))), 'residual': {n: residual(c) for n, c in clouds.items()}}
        for k, r in DENOISE:
            for name, c in clouds.items():
                row[(k, r, name)] = features(denoise(c, k, r) if r else c)
        out.append(row)
    return out


KEYS = {'shipped two': ['ln_occ32', 'variation16'],
        'shipped two + flat share': ['ln_occ32', 'variation16', 'flat_share3'],
        'all eight': ['ln_occ32', 'variation16', 'ln_facets3', 'flat_share3', 'ln_eff_facets3',
                      'ln_facets8', 'flat_share8', 'ln_eff_facets8']}

if __name__ == '__main__':
    start = time.time()
    data = {'train': rows('train', False), 'val': rows('val', True), 'test': rows('test', True)}
    print(f"{len(data['train'])} / {len(data['val'])} / {len(data['test'])} meshes, {time.time() - start:.0f} s")
    results = []
    print(f"{'denoise':>8s} {'features':26s} {'val R2':>7s} {'test R2':>7s} "
          + ' '.join(f'{"val d" + str(s):>12s}' for s in SIGMAS) + ' ' + ' '.join(f'{"test d" + str(s):>12s}' for s in SIGMAS))
    for k, r in DENOISE:
        for name, keys in KEYS.items():
            X = lambda rs, cloud: np.c_[np.array([[x[(k, r, cloud)][key] for key in keys] for x in rs]), np.ones(len(rs))]
            y = lambda rs: np.array([x['lnV'] for x in rs])
            w = np.linalg.lstsq(X(data['train'], 'clean'), y(data['train']), rcond=None)[0]
            res = {'denoise': [k, r], 'features': name, 'coefficients': w.tolist()}
            for split in ('val', 'test'):
                p, t = X(data[split], 'clean') @ w, y(data[split])
                res[split] = {'r2': float(1 - ((t - p) ** 2).sum() / ((t - t.mean()) ** 2).sum()),
                              'median_factor': float(np.exp(np.median(np.abs(t - p))))}
                for s in SIGMAS:
                    d = X(data[split], s) @ w - p
                    res[split][f'noise {s}'] = {'mean_ln_ratio': float(d.mean()), 'std_ln_ratio': float(d.std())}
            results.append(res)
            print(f"{k:>3d} x{r:<3d} {name:26s} {res['val']['r2']:7.3f} {res['test']['r2']:7.3f} "
                  + ' '.join(f"{res['val'][f'noise {s}']['mean_ln_ratio']:+6.2f}+-{res['val'][f'noise {s}']['std_ln_ratio']:4.2f}" for s in SIGMAS) + ' '
                  + ' '.join(f"{res['test'][f'noise {s}']['mean_ln_ratio']:+6.2f}+-{res['test'][f'noise {s}']['std_ln_ratio']:4.2f}" for s in SIGMAS))
    residuals = {str(n): np.percentile([x['residual'][n] for x in data['val']], [10, 50, 90]).tolist()
                 for n in ('clean',) + SIGMAS}
    for n, p in residuals.items():
        print(f'validation plane residual / spacing, {n}: 10th / 50th / 90th percentile ' + ' / '.join(f'{x:.3f}' for x in p))
    if OUT:
        with open(OUT, 'w') as f:
            json.dump({'fits': results, 'sigmas': SIGMAS, 'limit': LIMIT, 'residual_percentiles': residuals}, f, indent=1)
