#!/usr/bin/env python3
"""The non-learned baseline of `meshflow eval generate`: screened Poisson reconstruction of
the conditioning point cloud, then quadric-error decimation to the face count our generated
mesh has (what a user without MeshFlow would reach for).

Input: a folder written by `meshflow eval generate --meshes DIR` (K.points.ply per mesh and
targets.json mapping K to our face count). Output: K.poisson.ply beside them, and
poisson_qem.json with the settings and per-mesh wall times. Then
`meshflow eval generate ... --baseline DIR` scores them with the same metrics.

Normals are estimated from the points (a scan has none): PyMeshLab's point-cloud normals
(10 neighbours) oriented consistently, Poisson depth 8, default decimation settings.

Usage: pip install pymeshlab && python3 bench/poisson_qem.py DIR
"""

import argparse
import json
import os
import pathlib
import sys
import time

# MeshLab's OpenMP threads spin while they wait; beside another busy process (a training run)
# that slowed this script about 30-fold here. Passive waiting gives the same meshes.
os.environ.setdefault("OMP_WAIT_POLICY", "passive")
import pymeshlab  # noqa: E402


def baseline(points: pathlib.Path, faces: int, out: pathlib.Path, depth: int) -> dict:
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(points))
    started = time.perf_counter()
    ms.compute_normal_for_point_clouds(k=10)
    ms.generate_surface_reconstruction_screened_poisson(depth=depth)
    poisson_faces = ms.current_mesh().face_number()
    poisson_s = time.perf_counter() - started
    started = time.perf_counter()
    if faces > 0 and poisson_faces > faces:
        ms.meshing_decimation_quadric_edge_collapse(targetfacenum=faces)
    qem_s = time.perf_counter() - started
    ms.save_current_mesh(str(out), save_vertex_normal=False, save_vertex_color=False)
    return {
        "target_faces": faces,
        "poisson_faces": poisson_faces,
        "faces": ms.current_mesh().face_number(),
        "poisson_s": poisson_s,
        "qem_s": qem_s,
    }


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("dir", type=pathlib.Path)
    parser.add_argument("--depth", type=int, default=8, help="Poisson octree depth")
    args = parser.parse_args()
    targets = json.loads((args.dir / "targets.json").read_text())
    results, failed = {}, []
    for i, (key, faces) in enumerate(sorted(targets.items(), key=lambda kv: int(kv[0]))):
        points = args.dir / f"{key}.points.ply"
        try:
            results[key] = baseline(points, faces, args.dir / f"{key}.poisson.ply", args.depth)
        except Exception as e:  # PyMeshLab raises its own types; record and go on.
            failed.append(f"{key}: {e}")
        print(f"\r{i + 1}/{len(targets)}", end="", file=sys.stderr, flush=True)
    print(file=sys.stderr)
    report = {
        "pymeshlab": pymeshlab.__version__ if hasattr(pymeshlab, "__version__") else "unknown",
        "depth": args.depth,
        "normals": "compute_normal_for_point_clouds(k=10)",
        "meshes": len(results),
        "failed": failed,
        "mean_poisson_s": sum(r["poisson_s"] for r in results.values()) / max(len(results), 1),
        "mean_qem_s": sum(r["qem_s"] for r in results.values()) / max(len(results), 1),
        "per_mesh": results,
    }
    (args.dir / "poisson_qem.json").write_text(json.dumps(report, indent=2))
    print(f"{len(results)} baseline meshes, {len(failed)} failed -> {args.dir}/*.poisson.ply")
    return 0


if __name__ == "__main__":
    sys.exit(main())
