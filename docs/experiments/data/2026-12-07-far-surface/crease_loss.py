"""Where the edge F-score is lost: per mesh of a `meshflow eval generate --meshes DIR` folder,
our sharp-edge samples by their distance to the ground truth's sharp edges (precision's side)
and the ground truth's by their distance to ours (recall's side), with whether the other
surface is there; the ground truth's sharp length by dihedral angle and its recall; how our
sharp edges' ends and midpoints sit on the ground truth's creases; the share of our surface
far from the input points; how often a ground-truth crease found (within 0.01) and one missed
(0.01-0.04) has another crease within three spacings (0.0089 of the box, the validation
inputs' median). Issue 52's definitions: sharp = two faces whose normals differ by
more than 30 degrees, both meshes in the ground truth's [-0.5, 0.5] frame, 0.01 of the box.
    python3 crease_loss.py DIR [MESH] > crease_loss.csv   (needs numpy, scipy, trimesh)
MESH is the generated mesh's file name after K. (default ours.glb; poisson.ply for Poisson +
QEM's mesh that bench/poisson_qem.py wrote beside it)."""
import csv
import glob
import os
import sys

import numpy as np
import trimesh
from scipy.spatial import cKDTree

BANDS = [0.01, 0.02, 0.04]  # of the box; 0.01 is EF1's threshold, about one point spacing
ANGLES = [30, 45, 60, 90, 120, 181]


def load(path):
    m = trimesh.load(path, force="mesh", process=False)
    return np.asarray(m.vertices, float), np.asarray(m.faces, int)


def sharp_edges(v, f):
    """Ends of each sharp edge and its dihedral angle in degrees."""
    m = trimesh.Trimesh(v, f, process=False)
    n, adj, ends = m.face_normals, m.face_adjacency, m.face_adjacency_edges
    cos = np.einsum("ij,ij->i", n[adj[:, 0]], n[adj[:, 1]])
    s = cos < np.cos(np.radians(30))
    return v[ends[s, 0]], v[ends[s, 1]], np.degrees(np.arccos(np.clip(cos[s], -1, 1)))


def along(a, b, n, rng):
    """`n` samples by length along segments a-b, and the segment of each."""
    length = np.linalg.norm(b - a, axis=1)
    i = rng.choice(len(a), n, p=length / length.sum())
    return a[i] + rng.random(n)[:, None] * (b[i] - a[i]), i


def surface(v, f, n, rng):
    return trimesh.sample.sample_surface(trimesh.Trimesh(v, f, process=False), n,
                                         seed=int(rng.integers(1 << 30)))[0]


def bands(d):
    edges = [0.0] + BANDS + [np.inf]
    return [float(((d >= lo) & (d < hi)).mean()) for lo, hi in zip(edges, edges[1:])]


def main(folder, mesh="ours.glb"):
    rng = np.random.default_rng(0)
    out = csv.writer(sys.stdout)
    header = (["mesh", "gt_length", "our_length"]
              + [f"p_{b}" for b in ("01", "02", "04", "far")] + ["p_far_on_gt"]
              + [f"r_{b}" for b in ("01", "02", "04", "far")] + ["r_far_on_ours", "r_miss_to_ours_median"]
              + [f"gt_len_{lo}" for lo in ANGLES[:-1]] + [f"gt_hit_{lo}" for lo in ANGLES[:-1]]
              + [f"our_len_{lo}" for lo in ANGLES[:-1]]
              + ["len_both_ends_mid_on", "len_both_ends_mid_off", "len_one_end", "len_no_end",
                 "area_far3", "area_far5", "hit_near_other", "miss_near_other"])
    out.writerow(header)
    keys = sorted(glob.glob(os.path.join(folder, "*.gt.glb")), key=lambda p: int(os.path.basename(p).split(".")[0]))
    for g in keys:
        k = os.path.basename(g).split(".")[0]
        gv, gf = load(g)
        path = os.path.join(folder, f"{k}.{mesh}")
        if not os.path.exists(path):
            continue
        ov, of = load(path)
        points = np.asarray(trimesh.load(os.path.join(folder, f"{k}.points.ply")).vertices, float)
        lo, hi = gv.min(0), gv.max(0)
        centre, size = (lo + hi) / 2, (hi - lo).max()
        gv, ov, points = (gv - centre) / size, (ov - centre) / size, (points - centre) / size
        ga, gb, gang = sharp_edges(gv, gf)
        oa, ob, oang = sharp_edges(ov, of)
        # Our surface far from the input points (in their median nearest-neighbour spacings).
        tree = cKDTree(points)
        spacing = np.median(tree.query(points, 2)[0][:, 1])
        far = tree.query(surface(ov, of, 20000, rng))[0]
        area_far = [float((far > 3 * spacing).mean()), float((far > 5 * spacing).mean())]
        if len(ga) == 0 or len(oa) == 0:
            continue  # EF1 is 1 (neither) or 0 (one side): nothing to split
        gs, gi = along(ga, gb, 2000, rng)
        os_, _ = along(oa, ob, 2000, rng)
        dp = cKDTree(gs).query(os_)[0]
        dr = cKDTree(os_).query(gs)[0]
        on_gt = cKDTree(surface(gv, gf, 40000, rng)).query(os_)[0] < 0.01
        to_ours = cKDTree(surface(ov, of, 40000, rng)).query(gs)[0]
        miss = (dr >= 0.01) & (dr < 0.04)
        glen = np.linalg.norm(gb - ga, axis=1)
        olen = np.linalg.norm(ob - oa, axis=1)
        gt_len = np.histogram(gang, ANGLES, weights=glen)[0]
        # Recall per angle band, as the share of that band's samples found within 0.01.
        sample_angle = gang[gi]
        hit = [float((dr[(sample_angle >= a) & (sample_angle < b)] < 0.01).sum()) for a, b in zip(ANGLES, ANGLES[1:])]
        counts = np.histogram(sample_angle, ANGLES)[0]
        our_len = np.histogram(oang, ANGLES, weights=olen)[0]
        near = cKDTree(gs)
        end_a, end_b = near.query(oa)[0] < 0.01, near.query(ob)[0] < 0.01
        mid = near.query((oa + ob) / 2)[0] < 0.01
        both = end_a & end_b
        # Whether another crease of the ground truth (off this sample's own line) lies within
        # three spacings: a crease between faces a few spacings wide.
        direction = (gb - ga)[gi] / glen[gi][:, None]
        gtree = cKDTree(gs)
        near_other = np.zeros(len(gs), bool)
        for j, found in enumerate(gtree.query_ball_point(gs, 3 * 0.0089)):
            w = gs[found] - gs[j]
            near_other[j] = bool((np.linalg.norm(np.cross(w, direction[j]), axis=1) > 0.004).any())
        hit_mask = dr < 0.01
        near = [float(near_other[hit_mask].mean()) if hit_mask.any() else "",
                float(near_other[miss].mean()) if miss.any() else ""]
        out.writerow([k, glen.sum(), olen.sum()] + bands(dp) + [float(((dp >= 0.04) & on_gt).mean())]
                     + bands(dr) + [float(((dr >= 0.04) & (to_ours < 0.01)).mean()),
                                    float(np.median(to_ours[miss])) if miss.any() else ""]
                     + list(gt_len) + [h / c if c else "" for h, c in zip(hit, counts)] + list(our_len)
                     + [olen[both & mid].sum(), olen[both & ~mid].sum(), olen[end_a ^ end_b].sum(),
                        olen[~end_a & ~end_b].sum()] + area_far + near)


if __name__ == "__main__":
    main(*sys.argv[1:3])
