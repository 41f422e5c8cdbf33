#!/usr/bin/env python3
"""Sample points uniformly by area from a triangle mesh and write an ASCII PLY.

This makes the example point-cloud fixture in tests/fixtures/points/. It is
deliberately standalone (standard library only, no numpy) so anyone can
regenerate the fixture bit-for-bit:

    python3 scripts/sample_points.py tests/fixtures/meshes/stone_lantern.obj \
        -n 2048 --seed 20240611 -o tests/fixtures/points/stone_lantern_2048.ply

Supported inputs: Wavefront OBJ (polygons are fan-triangulated; only `v` and
`f` records are read) and STL (binary or ASCII). The Rust CLI has its own
sampler; this script only exists to produce a fixed, reproducible fixture.
"""

from __future__ import annotations

import argparse
import bisect
import math
import random
import struct
import sys
from pathlib import Path

Vec = tuple[float, float, float]
Tri = tuple[Vec, Vec, Vec]


def read_obj(data: bytes) -> list[Tri]:
    verts: list[Vec] = []
    tris: list[Tri] = []
    for raw in data.decode("utf-8", errors="replace").splitlines():
        parts = raw.split()
        if not parts:
            continue
        if parts[0] == "v":
            verts.append((float(parts[1]), float(parts[2]), float(parts[3])))
        elif parts[0] == "f":
            idx = []
            for tok in parts[1:]:
                i = int(tok.split("/")[0])
                # OBJ indices are 1-based; negative ones count back from the end.
                idx.append(i - 1 if i > 0 else len(verts) + i)
            for k in range(1, len(idx) - 1):
                tris.append((verts[idx[0]], verts[idx[k]], verts[idx[k + 1]]))
    return tris


def read_stl(data: bytes) -> list[Tri]:
    if len(data) >= 84:
        (count,) = struct.unpack_from("<I", data, 80)
        if 84 + 50 * count == len(data):
            tris = []
            for i in range(count):
                f = struct.unpack_from("<12f", data, 84 + 50 * i)
                tris.append((f[3:6], f[6:9], f[9:12]))
            return tris
    # Not a well-sized binary file: treat it as ASCII.
    tris = []
    corner: list[Vec] = []
    for raw in data.decode("ascii", errors="replace").splitlines():
        parts = raw.split()
        if parts and parts[0] == "vertex":
            corner.append((float(parts[1]), float(parts[2]), float(parts[3])))
            if len(corner) == 3:
                tris.append((corner[0], corner[1], corner[2]))
                corner = []
    return tris


def area(t: Tri) -> float:
    (ax, ay, az), (bx, by, bz), (cx, cy, cz) = t
    ux, uy, uz = bx - ax, by - ay, bz - az
    vx, vy, vz = cx - ax, cy - ay, cz - az
    nx, ny, nz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx
    return 0.5 * math.sqrt(nx * nx + ny * ny + nz * nz)


def sample(tris: list[Tri], n: int, seed: int) -> list[Vec]:
    cumulative = []
    total = 0.0
    for t in tris:
        total += area(t)
        cumulative.append(total)
    if total <= 0.0:
        raise SystemExit("mesh has zero surface area")
    rng = random.Random(seed)
    points = []
    for _ in range(n):
        # Pick a triangle with probability proportional to its area...
        k = bisect.bisect_right(cumulative, rng.random() * total)
        a, b, c = tris[min(k, len(tris) - 1)]
        # ...then a uniform point inside it (square-root barycentric trick).
        r1 = math.sqrt(rng.random())
        r2 = rng.random()
        wa, wb, wc = 1.0 - r1, r1 * (1.0 - r2), r1 * r2
        points.append(tuple(wa * a[i] + wb * b[i] + wc * c[i] for i in range(3)))
    return points


def write_ply(path: Path, points: list[Vec], comment: str) -> None:
    lines = [
        "ply",
        "format ascii 1.0",
        f"comment {comment}",
        f"element vertex {len(points)}",
        "property float x",
        "property float y",
        "property float z",
        "end_header",
    ]
    lines += [f"{x:.6f} {y:.6f} {z:.6f}" for x, y, z in points]
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join(lines) + "\n", encoding="ascii")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("mesh", type=Path, help="input .obj or .stl")
    ap.add_argument("-n", "--count", type=int, default=2048, help="number of points")
    ap.add_argument("--seed", type=int, default=20240611, help="random seed")
    ap.add_argument("-o", "--output", type=Path, required=True, help="output .ply")
    args = ap.parse_args()

    data = args.mesh.read_bytes()
    suffix = args.mesh.suffix.lower()
    if suffix == ".obj":
        tris = read_obj(data)
    elif suffix == ".stl":
        tris = read_stl(data)
    else:
        print(f"unsupported mesh format: {suffix}", file=sys.stderr)
        return 2
    points = sample(tris, args.count, args.seed)
    comment = (
        f"{args.count} points sampled uniformly by area from {args.mesh.name} "
        f"with scripts/sample_points.py --seed {args.seed}"
    )
    write_ply(args.output, points, comment)
    print(f"wrote {len(points)} points from {len(tris)} triangles to {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
