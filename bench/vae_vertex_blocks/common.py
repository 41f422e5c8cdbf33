"""Surface figures of `meshflow eval vae` files over the meshes every file reconstructed with
faces (a mesh extracted with no faces is left out of a file's own means, so files with
different such meshes are compared here on the same meshes).
`python3 bench/vae_vertex_blocks/common.py NAME=FILE ...` prints one table row per file."""
import json, sys

files = dict(a.split('=', 1) for a in sys.argv[1:])
per = {n: dict(json.load(open(f))['per_mesh']) for n, f in files.items()}
common = set.intersection(*({k for k, m in p.items() if m.get('comparison')} for p in per.values()))
left_out = sorted(set.union(*(set(p) for p in per.values())) - common)
print(f'{len(common)} meshes in common; left out: {", ".join(left_out) or "none"}')
print('| VAE | CD x100 | HD x100 | faces | gt faces | holes | edge F1 |')
print('|---|---:|---:|---:|---:|---:|---:|')
for n, p in per.items():
    mean = lambda f: sum(f(p[k]) for k in common) / len(common)
    c = lambda m: m['comparison']
    print(f"| {n} | {mean(lambda m: c(m)['chamfer_x100']):.3f} | {mean(lambda m: c(m)['hausdorff_x100']):.2f} "
          f"| {mean(lambda m: c(m)['pred_topology']['faces']):.1f} | {mean(lambda m: c(m)['gt_topology']['faces']):.1f} "
          f"| {mean(lambda m: c(m)['pred_topology']['holes']):.2f} | {mean(lambda m: m['edge_f1']):.3f} |")
