#!/usr/bin/env python3
"""Which share of planar neighbourhoods predicts the artist's vertex count best (issue 15
item 5)? The prototype that chose the shipped rule's third feature; not product code.

    python3 bench/budget_planar.py [SHARDS] [-o docs/experiments/data/2026-11-29-budget-planar-share/planar.json]

bench/budget_facets.py found that the share of points lying in flat facets predicts ln V far
better than the shipped two features, but it needs every point's normal and a connected-
components pass. Here the cheaper cousin is read from the same neighbourhoods as the shipped
surface variation: for 512 sampled points of each cloud (4,096 area-weighted samples in the
model frame, as `meshflow eval budget` draws), the smallest eigenvalue share of the
covariance of the k nearest neighbours, and the share of those below a threshold
(`p{k}_{threshold}`: neighbourhoods lying on one plane). Least squares of ln V on the 3,806
training meshes of at most 512 vertices; R^2 and the median factor missed on validation and
test; and the mean shift of the predicted ln V when Gaussian noise of sigma 0.01 / 0.02 (model
frame: 0.5% / 1% of the longest side) is added to the validation and test clouds. About two
minutes on 2 cores. Needs numpy and scipy."""
import json, os, sys, time
import numpy as np
from scipy.spatial import cKDTree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from shards import meshes, surface_points
from budget_facets import model_frame

SHARDS = os.path.expanduser(sys.argv[1] if len(sys.argv) > 1 and not sys.argv[1].startswith('-') else '~/.cache/meshflow/data/shards')
OUT = sys.argv[sys.argv.index('-o') + 1] if '-o' in sys.argv else None
THRESHOLDS, NEIGHBOURS, QUERIES = (1e-5, 3e-5, 1e-4, 3e-4), (12, 16, 24), 512


def features(q, rng):
    tree = cKDTree(q)
    cells = np.unique(np.clip(np.floor((q + 1) / 2 * 32), 0, 31).astype(int), axis=0)
    out = {'ln_occ32': float(np.log(len(cells)))}
    at = rng.choice(len(q), QUERIES, replace=False)
    for k in NEIGHBOURS:
        _, nb = tree.query(q[at], k)
        c = q[nb] - q[nb].mean(1, keepdims=True)
        ev = np.linalg.eigvalsh(np.einsum('nki,nkj->nij', c, c) / k)
        share = ev[:, 0] / np.maximum(ev.sum(1), 1e-18)
        out[f'var{k}'] = float(share.mean())
        for t in THRESHOLDS:
            out[f'p{k}_{t:g}'] = float((share < t).mean())
    return out


def load(split, noisy):
    rng = np.random.default_rng(0); rows = []
    for _, v, f in meshes(SHARDS, (split,), 512):
        if len(f) == 0: continue
        p = surface_points(v.astype(np.float64), f.astype(np.int64), rng)
        if p is None: continue
        q = model_frame(p)
        row = {'lnV': float(np.log(len(v))), 'clean': features(q, rng)}
        if noisy:
            for sigma in (0.01, 0.02):
                row[sigma] = features(model_frame(q + rng.normal(0, sigma, q.shape)), rng)
        rows.append(row)
    return rows


def score(data, keys):
    X = lambda rows, cloud: np.c_[np.ones(len(rows)), np.array([[r[cloud][k] for k in keys] for r in rows])]
    y = lambda rows: np.array([r['lnV'] for r in rows])
    w = np.linalg.lstsq(X(data['train'], 'clean'), y(data['train']), rcond=None)[0]
    out = {'features': keys, 'coefficients': w.tolist()}
    for split in ('train', 'val', 'test'):
        p, t = X(data[split], 'clean') @ w, y(data[split])
        out[split] = {'r2': float(1 - ((t - p) ** 2).sum() / ((t - t.mean()) ** 2).sum()),
                      'median_factor': float(np.exp(np.median(np.abs(t - p))))}
        if split != 'train':
            for sigma in (0.01, 0.02):
                out[split][f'noise_shift_{sigma}'] = float((X(data[split], sigma) @ w - p).mean())
    return out


if __name__ == '__main__':
    start = time.time()
    data = {'train': load('train', False), 'val': load('val', True), 'test': load('test', True)}
    print(f"{len(data['train'])} / {len(data['val'])} / {len(data['test'])} meshes, {time.time() - start:.0f} s")
    sets = [['ln_occ32', 'var16']]
    sets += [['ln_occ32', 'var16', f'p{k}_{t:g}'] for k in NEIGHBOURS for t in THRESHOLDS]
    sets += [['ln_occ32', 'var16', 'var12', 'var24', 'p12_0.0001', 'p16_0.0001', 'p24_0.0001', 'p12_1e-05', 'p24_1e-05']]
    results = [score(data, keys) for keys in sets]
    print(f"{'features':70s} {'train':>6s} {'val':>6s} {'test':>6s} {'miss val':>8s} {'test':>6s}  noise shift val 0.01 / 0.02, test 0.01 / 0.02")
    for r in results:
        print(f"{' + '.join(r['features']):70s} {r['train']['r2']:6.3f} {r['val']['r2']:6.3f} {r['test']['r2']:6.3f} "
              f"x{r['val']['median_factor']:7.2f} x{r['test']['median_factor']:5.2f}  "
              + ' / '.join(f"{r[s][f'noise_shift_{n}']:+.2f}" for s in ('val', 'test') for n in (0.01, 0.02)))
    if OUT:
        with open(OUT, 'w') as f:
            json.dump({'fits': results, 'queries': QUERIES}, f, indent=1)
