#!/usr/bin/env python3
"""Would a learned predictor of the artist's vertex count beat the default budget rule's R^2 0.10
(issue 15 item 5)? A prototype, not product code.

    python3 bench/budget_learned.py [SHARDS] [-o docs/experiments/data/2026-11-26-budget-features/budget_learned.json]

Reads the training and validation shards directly (SHARDS, default
~/.cache/meshflow/data/shards; bench/shards.py), keeps meshes of at most 512 vertices (the ones the VAE takes),
samples 4,096 area-weighted surface points from each, as `meshflow eval generate` conditions on,
puts them in the model frame (longest side spans [-1, 1]) and describes each cloud by:
- the shipped rule's two features (ln occupied cells of the 32^3 grid, 16-neighbour surface
  variation);
- a coarse shape descriptor: occupancy of an 8^3 grid (512 values), the D2 shape distribution
  (a 32-bin histogram of distances between random point pairs) and the sorted bounding-box
  extents.
It fits ln V on the training meshes and reports R^2 and the median |log error| on the held-out
validation meshes for: the shipped rule refitted; ridge regression on all features; and
k-nearest-neighbour regression on the standardised descriptor (how far "shapes like this one"
predict the count). Needs numpy and scipy."""
import json, os, sys, numpy as np
from scipy.spatial import cKDTree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from shards import meshes, surface_points

SHARDS = os.path.expanduser(sys.argv[1] if len(sys.argv) > 1 and not sys.argv[1].startswith('-') else '~/.cache/meshflow/data/shards')
OUT = sys.argv[sys.argv.index('-o') + 1] if '-o' in sys.argv else None
POINTS, MAX_V = 4096, 512

def descriptor(p, rng):
    lo, hi = p.min(0), p.max(0); q = (p - (lo + hi) / 2) / ((hi - lo).max() / 2)
    def occ(g):
        idx = np.clip(np.floor((q + 1) / 2 * g), 0, g - 1).astype(int); o = np.zeros((g, g, g)); o[idx[:, 0], idx[:, 1], idx[:, 2]] = 1; return o
    tree = cKDTree(q); sel = rng.choice(len(q), 512, replace=False); _, nb = tree.query(q[sel], 16)
    shares = []
    for row in nb:
        ev = np.linalg.eigvalsh(np.cov(q[row].T, bias=True)); shares.append(ev[0] / max(ev.sum(), 1e-18))
    a, b = rng.integers(0, len(q), (2, 4096)); d2 = np.histogram(np.linalg.norm(q[a] - q[b], axis=1), 32, (0, 2 * np.sqrt(3)))[0] / 4096
    ext = np.sort(hi - lo) / (hi - lo).max()
    return np.log(occ(32).sum()), float(np.mean(shares)), np.concatenate([occ(8).ravel(), d2, ext[:2]])

def load(split):
    rng = np.random.default_rng(0); rows = []
    for _, v, f in meshes(SHARDS, (split,), MAX_V):
        if len(f) == 0: continue
        p = surface_points(v.astype(np.float64), f.astype(np.int64), rng)
        if p is None: continue
        rows.append((np.log(len(v)),) + descriptor(p, rng))
    y = np.array([r[0] for r in rows]); shipped = np.array([[r[1], r[2]] for r in rows]); desc = np.array([r[3] for r in rows])
    return y, shipped, desc

def score(y, pred):
    return 1 - ((y - pred) ** 2).sum() / ((y - y.mean()) ** 2).sum(), float(np.median(np.abs(y - pred)))

def ridge(Xt, yt, Xv, lam):
    mu, sd = Xt.mean(0), Xt.std(0) + 1e-9; A = (Xt - mu) / sd; B = (Xv - mu) / sd
    w = np.linalg.solve(A.T @ A + lam * np.eye(A.shape[1]), A.T @ (yt - yt.mean()))
    return B @ w + yt.mean()

yt, st, dt_ = load('train'); yv, sv, dv = load('val')
print(f'{len(yt)} training meshes, {len(yv)} validation meshes (<= {MAX_V} vertices)')
results = {}
results['shipped features, least squares'] = score(yv, ridge(st, yt, sv, 1e-6))
for lam in (1, 10, 100, 1000):
    results[f'ridge on all features, lambda {lam}'] = score(yv, ridge(np.hstack([st, dt_]), yt, np.hstack([sv, dv]), lam))
mu, sd = dt_.mean(0), dt_.std(0) + 1e-9; tree = cKDTree((dt_ - mu) / sd)
for k in (1, 5, 10, 20, 40):
    _, nb = tree.query((dv - mu) / sd, k); nb = nb.reshape(len(yv), -1)
    results[f'{k}-nearest neighbours on the descriptor'] = score(yv, yt[nb].mean(1))
results['the training mean (R^2 0 by definition)'] = score(yv, np.full_like(yv, yt.mean()))
for k, (r2, med) in results.items():
    print(f'{k:45s} val R^2 {r2:6.3f}  median |ln error| {med:.3f} (factor {np.exp(med):.2f})')
if OUT:
    with open(OUT, 'w') as f:
        json.dump({'train': len(yt), 'val': len(yv), 'results': {k: {'val_r2': r, 'median_abs_ln_error': m} for k, (r, m) in results.items()}}, f, indent=1)
