#!/usr/bin/env python3
"""Does the faceting of a point cloud predict the artist's vertex count (issue 15 item 5)?
A prototype, not product code.

    python3 bench/budget_facets.py [SHARDS] [-o docs/experiments/data/2026-11-26-budget-features/budget_facets.json]

Points sampled from a low-poly mesh lie on its flat faces, and an artist who spent few vertices
left large flat faces. Each cloud (4,096 area-weighted surface samples of a training,
validation or test mesh of at most 512 vertices, put in the model frame, as
bench/budget_learned.py does) gets, besides the shipped rule's two features (ln occupied cells
of the 32^3 grid, 16-neighbour surface variation):
- per point, a normal and a flatness (smallest eigenvalue share) from its 12 nearest
  neighbours;
- facets: neighbouring flat points (share < 0.01) joined when their normals agree within
  3 (or 8) degrees and each lies within a quarter of the median point spacing of the other's
  plane; the connected pieces of at least 6 points are the facets;
- `flat_share`: the share of all points that lie in a facet; `ln_facets`: ln(1 + facets);
  `ln_eff_facets`: the entropy of the facet sizes (ln of an effective facet count).
It fits ln V by least squares on the training meshes and reports R^2 and the median factor
missed on the validation and test meshes for several feature sets; then the same validation
clouds with Gaussian noise (sigma 0.003 and 0.01 of the half extent) added, to see what the
faceting features read on a scan. Needs numpy and scipy."""
import json, os, sys, time
import numpy as np
from scipy.spatial import cKDTree
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from shards import meshes, surface_points

SHARDS = os.path.expanduser(sys.argv[1] if len(sys.argv) > 1 and not sys.argv[1].startswith('-') else '~/.cache/meshflow/data/shards')
OUT = sys.argv[sys.argv.index('-o') + 1] if '-o' in sys.argv else None
POINTS, MAX_V, K = 4096, 512, 12


def model_frame(p):
    lo, hi = p.min(0), p.max(0)
    return (p - (lo + hi) / 2) / ((hi - lo).max() / 2)


def features(q):
    tree = cKDTree(q); dist, nb = tree.query(q, K)
    c = q[nb] - q[nb].mean(1, keepdims=True)
    ev, evec = np.linalg.eigh(np.einsum('nki,nkj->nij', c, c) / K)
    normal, share = evec[:, :, 0], ev[:, 0] / np.maximum(ev.sum(1), 1e-18)
    cells = np.unique(np.clip(np.floor((q + 1) / 2 * 32), 0, 31).astype(int), axis=0)
    out = {'ln_occ32': float(np.log(len(cells))), 'variation16': float(share.mean())}
    spacing = float(np.median(dist[:, 1]))
    i = np.repeat(np.arange(len(q)), K - 1); j = nb[:, 1:].ravel()
    for deg in (3, 8):
        agree = np.abs(np.einsum('ij,ij->i', normal[i], normal[j])) > np.cos(np.radians(deg))
        near = np.abs(np.einsum('ij,ij->i', q[j] - q[i], normal[i])) < 0.25 * spacing
        ok = agree & near & (share[i] < 0.01) & (share[j] < 0.01)
        graph = coo_matrix((np.ones(ok.sum()), (i[ok], j[ok])), shape=(len(q), len(q)))
        sizes = np.bincount(connected_components(graph, directed=False)[1])
        facets = sizes[sizes >= 6]
        s = facets / max(facets.sum(), 1)
        out[f'ln_facets{deg}'] = float(np.log(1 + len(facets)))
        out[f'flat_share{deg}'] = float(facets.sum() / len(q))
        out[f'ln_eff_facets{deg}'] = float(-(s * np.log(np.maximum(s, 1e-30))).sum())
    return out


def load(split, noise=()):
    rng = np.random.default_rng(0); rows = []
    for _, v, f in meshes(SHARDS, (split,), MAX_V):
        if len(f) == 0: continue
        p = surface_points(v.astype(np.float64), f.astype(np.int64), rng)
        if p is None: continue
        q = model_frame(p)
        row = features(q); row['lnV'] = float(np.log(len(v)))
        for sigma in noise:
            row[f'noisy{sigma}'] = features(q + rng.normal(0, sigma, q.shape))
        rows.append(row)
    return rows


def fit(data, keys):
    X = lambda rows: np.c_[np.array([[r[k] for k in keys] for r in rows]), np.ones(len(rows))]
    y = lambda rows: np.array([r['lnV'] for r in rows])
    w = np.linalg.lstsq(X(data['train']), y(data['train']), rcond=None)[0]
    scores = {}
    for split in ('train', 'val', 'test'):
        p, t = X(data[split]) @ w, y(data[split])
        scores[split] = {'r2': float(1 - ((t - p) ** 2).sum() / ((t - t.mean()) ** 2).sum()),
                         'median_factor': float(np.exp(np.median(np.abs(t - p))))}
    return w, scores


if __name__ == '__main__':
    start = time.time()
    data = {'train': load('train'), 'val': load('val', noise=(0.003, 0.01)), 'test': load('test')}
    print(f"{len(data['train'])} / {len(data['val'])} / {len(data['test'])} train / val / test meshes (<= {MAX_V} vertices), {time.time() - start:.0f} s")
    SETS = [['ln_occ32', 'variation16'], ['flat_share3'], ['ln_facets3'],
            ['ln_occ32', 'variation16', 'flat_share3'],
            ['ln_occ32', 'variation16', 'flat_share3', 'ln_facets3'],
            ['ln_occ32', 'variation16', 'flat_share3', 'flat_share8', 'ln_facets3', 'ln_facets8'],
            ['ln_occ32', 'variation16', 'ln_facets3', 'flat_share3', 'ln_eff_facets3', 'ln_facets8', 'flat_share8', 'ln_eff_facets8']]
    results = []
    print(f"{'features':90s} {'train R^2':>9s} {'val R^2':>8s} {'test R^2':>8s} {'val miss':>8s} {'test miss':>9s}")
    for keys in SETS:
        w, s = fit(data, keys)
        results.append({'features': keys, 'coefficients': w.tolist(), **s})
        print(f"{' + '.join(keys):90s} {s['train']['r2']:9.3f} {s['val']['r2']:8.3f} {s['test']['r2']:8.3f} "
              f"x{s['val']['median_factor']:7.2f} x{s['test']['median_factor']:8.2f}")
    noise = {}
    for key in ('flat_share3', 'ln_facets3', 'variation16'):
        noise[key] = {'clean': float(np.mean([r[key] for r in data['val']]))}
        for sigma in (0.003, 0.01):
            noise[key][f'sigma {sigma}'] = float(np.mean([r[f'noisy{sigma}'][key] for r in data['val']]))
        print(f'{key}: validation mean', ', '.join(f'{k} {v:.4f}' for k, v in noise[key].items()))
    if OUT:
        with open(OUT, 'w') as f:
            json.dump({'fits': results, 'noise_on_validation': noise, 'points': POINTS, 'neighbours': K}, f, indent=1)
