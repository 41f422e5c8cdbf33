#!/usr/bin/env python3
"""Build the bundled example point clouds in web/examples/ from their original meshes.

Five ASCII PLY point clouds are made from meshes shipped in three published
packages (none of them a training source, see docs/data.md):

    Debian assimp-testmodels 5.2.5~ds0-1   CesiumMilkTruck (glTF 1.0), 2CylinderEngine (GLB)
    PyPI panda3d 1.10.16                   panda.egg.pz, panda-model.egg.pz
    PyPI compas 2.15.1                     tubemesh.obj

The originals are kept in a cache folder (default ~/.cache/meshflow/examples-src,
or --cache). Missing ones are fetched again with the ordinary package clients
(`apt-get download`, `pip download`, `npm pack`; run `apt-get update` first on a
fresh machine) and every original is checked against its sha256 before use.

Only the standard library is used for the geometry: the file readers, the
area-uniform sampler and the noise all run on Python floats with
`random.Random(seed)`, so the same originals give byte-identical PLYs. (The
noisy example draws Gaussian noise with `random.gauss`, which uses the C
library's log/cos; on an exotic libm the last printed digit could differ.)

    python3 scripts/make_examples.py            # writes web/examples/*
    python3 scripts/make_examples.py --check    # rebuilds in memory, compares with the files

web/examples/SOURCES.md documents the sources, licenses and processing.
"""

from __future__ import annotations

import argparse
import bisect
import hashlib
import io
import json
import math
import os
import random
import re
import struct
import subprocess
import sys
import tarfile
import zipfile
import zlib
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
OUT = REPO / "web" / "examples"
DEFAULT_CACHE = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "meshflow" / "examples-src"

# --------------------------------------------------------------------------
# Packages and the original files taken from them
# --------------------------------------------------------------------------

PACKAGES = {
    "assimp-testmodels": {
        "kind": "deb",
        "spec": "assimp-testmodels=5.2.5~ds0-1",
        "archive": "assimp-testmodels_5.2.5~ds0-1_all.deb",
        "sha256": "526f326186000cd6f631ea806128548a7d3d391abd8149fddc5c4c8513e80b8a",
    },
    "panda3d": {
        "kind": "pypi",
        # The models are data files, the same in every platform's wheel; this one is pinned.
        "spec": ["--only-binary=:all:", "--platform", "manylinux2014_x86_64",
                 "--python-version", "3.11", "--implementation", "cp", "panda3d==1.10.16"],
        "archive": "panda3d-1.10.16-cp311-cp311-manylinux2014_x86_64.whl",
        "sha256": "8aa53ad6d83eaa750d84e8c1d84919c0f1167212208c836c15b998409cdb6a83",
    },
    "compas": {
        "kind": "pypi",
        "spec": ["compas==2.15.1"],
        "archive": "compas-2.15.1-py3-none-any.whl",
        "sha256": "509ab436da7fc185b66436d5a1044ab94c932e9d9ca569cb5fe225f32f4493b2",
    },
    "spdx-license-list": {
        "kind": "npm",
        "spec": "spdx-license-list@6.12.0",
        "archive": "spdx-license-list-6.12.0.tgz",
        "sha256": "54cc8d13086187333ca1457c8edaa06d9a412144f076aa7f7c1b59c4f3b0a1ef",
    },
}

# name -> (package, path inside the package, sha256)
ORIGINALS = {
    "truck.gltf": ("assimp-testmodels", "usr/share/assimp/models/glTF/CesiumMilkTruck/CesiumMilkTruck.gltf",
                   "4ad2fe70e7074fa699538606c5d004cbe6750938aa0194f69fd20cadbf7b8fb4"),
    "truck.bin": ("assimp-testmodels", "usr/share/assimp/models/glTF/CesiumMilkTruck/CesiumMilkTruck.bin",
                  "c3d1a90ee230ce8feceb3444cf980c0675ed03344188b701c133a001d5159fda"),
    "engine.glb": ("assimp-testmodels", "usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb",
                   "bb5fbccc73a3f68c52f26687fbb25b4a1248ab5f8a115ec55e7ac6a4451c47ee"),
    "panda.egg.pz": ("panda3d", "panda3d/models/panda.egg.pz",
                     "343e596560e423acb25486983cb810f2a784eefc702590984cf80fbab1c1100b"),
    "panda-model.egg.pz": ("panda3d", "panda3d/models/panda-model.egg.pz",
                           "b37710dee12bf106f41b99444486c5b7e16c03ddfeff95db3bc6cf2076a3ef5a"),
    "tubemesh.obj": ("compas", "compas/data/samples/tubemesh.obj",
                     "9fa4f171dd3161e8789625764baf47149319a3b8c1ea887f99a97d0f4517e834"),
}

# License files copied verbatim into web/examples/licenses/: output name -> (package, path, how)
LICENSE_FILES = {
    "assimp-testmodels.copyright": ("assimp-testmodels", "usr/share/doc/assimp-testmodels/copyright", None),
    "panda3d.LICENSE.txt": ("panda3d", "panda3d-1.10.16.dist-info/LICENSE.txt", None),
    "compas.LICENSE": ("compas", "compas-2.15.1.dist-info/licenses/LICENSE", None),
    # The CC BY 4.0 legal code, from the SPDX license list's JSON (field licenseText).
    "CC-BY-4.0.txt": ("spdx-license-list", "package/licenses/CC-BY-4.0.json", "spdx-json"),
}


def sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def download(pkg: str, cache: Path) -> Path:
    info = PACKAGES[pkg]
    dl = cache / "downloads"
    dl.mkdir(parents=True, exist_ok=True)
    path = dl / info["archive"]
    if not path.exists():
        print(f"fetching {pkg} ...", file=sys.stderr)
        if info["kind"] == "deb":
            subprocess.run(["apt-get", "download", info["spec"]], cwd=dl, check=True)
        elif info["kind"] == "pypi":
            subprocess.run([sys.executable, "-m", "pip", "download", "--no-deps", "-d", str(dl), *info["spec"]],
                           check=True)
        elif info["kind"] == "npm":
            subprocess.run(["npm", "pack", info["spec"]], cwd=dl, check=True, stdout=subprocess.DEVNULL)
    got = sha256(path.read_bytes())
    if got != info["sha256"]:
        print(f"warning: {path.name} has sha256 {got}, expected {info['sha256']} "
              "(the files inside are still checked one by one)", file=sys.stderr)
    return path


def deb_data_tar(deb: bytes) -> tarfile.TarFile:
    assert deb[:8] == b"!<arch>\n", "not a .deb"
    pos = 8
    while pos + 60 <= len(deb):
        name = deb[pos:pos + 16].decode().strip().rstrip("/")
        size = int(deb[pos + 48:pos + 58].decode().strip())
        body = deb[pos + 60:pos + 60 + size]
        if name.startswith("data.tar"):
            return tarfile.open(fileobj=io.BytesIO(body), mode="r:*")
        pos += 60 + size + (size & 1)
    raise ValueError("no data.tar in the .deb")


def read_member(pkg: str, member: str, cache: Path) -> bytes:
    archive = download(pkg, cache)
    kind = PACKAGES[pkg]["kind"]
    if kind == "deb":
        tar = deb_data_tar(archive.read_bytes())
        for m in tar.getmembers():
            if m.name.lstrip("./") == member:
                return tar.extractfile(m).read()
        raise KeyError(member)
    if kind == "npm":
        with tarfile.open(archive, "r:gz") as tar:
            return tar.extractfile(member).read()
    with zipfile.ZipFile(archive) as z:
        return z.read(member)


def original(name: str, cache: Path) -> bytes:
    pkg, member, digest = ORIGINALS[name]
    path = cache / pkg / member
    if path.exists() and sha256(path.read_bytes()) == digest:
        return path.read_bytes()
    data = read_member(pkg, member, cache)
    if sha256(data) != digest:
        sys.exit(f"{pkg}:{member} has sha256 {sha256(data)}, expected {digest}")
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(data)
    return data


# --------------------------------------------------------------------------
# Readers (triangles as tuples of three (x, y, z) tuples)
# --------------------------------------------------------------------------

IDENT = ((1.0, 0.0, 0.0, 0.0), (0.0, 1.0, 0.0, 0.0), (0.0, 0.0, 1.0, 0.0), (0.0, 0.0, 0.0, 1.0))
COMPONENT = {5120: "b", 5121: "B", 5122: "h", 5123: "H", 5125: "I", 5126: "f"}
WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}


def mat_mul(a, b):
    return tuple(tuple(sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)) for i in range(4))


def apply(m, p):
    x, y, z = p
    return (m[0][0] * x + m[0][1] * y + m[0][2] * z + m[0][3],
            m[1][0] * x + m[1][1] * y + m[1][2] * z + m[1][3],
            m[2][0] * x + m[2][1] * y + m[2][2] * z + m[2][3])


def node_matrix(node):
    if "matrix" in node:
        m = node["matrix"]  # column-major
        return tuple(tuple(float(m[c * 4 + r]) for c in range(4)) for r in range(4))
    tx, ty, tz = node.get("translation", [0, 0, 0])
    qx, qy, qz, qw = node.get("rotation", [0, 0, 0, 1])
    sx, sy, sz = node.get("scale", [1, 1, 1])
    r = ((1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)),
         (2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)),
         (2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)))
    return ((r[0][0] * sx, r[0][1] * sy, r[0][2] * sz, float(tx)),
            (r[1][0] * sx, r[1][1] * sy, r[1][2] * sz, float(ty)),
            (r[2][0] * sx, r[2][1] * sy, r[2][2] * sz, float(tz)),
            (0.0, 0.0, 0.0, 1.0))


def gltf_triangles(doc: dict, buffers: dict, version: int):
    """Triangles of the default scene, node transforms applied (glTF 1.0 or 2.0)."""

    def accessor(key):
        a = doc["accessors"][key]
        view = doc["bufferViews"][a["bufferView"]]
        buf = buffers[view.get("buffer", 0)]
        fmt, n = COMPONENT[a["componentType"]], WIDTH[a["type"]]
        size = struct.calcsize("<" + fmt) * n
        stride = (a.get("byteStride") if version == 1 else view.get("byteStride")) or size
        base = view.get("byteOffset", 0) + a.get("byteOffset", 0)
        return [struct.unpack_from("<%d%s" % (n, fmt), buf, base + k * stride) for k in range(a["count"])]

    tris = []

    def visit(key, parent):
        node = doc["nodes"][key]
        world = mat_mul(parent, node_matrix(node))
        meshes = node.get("meshes", []) if version == 1 else ([node["mesh"]] if "mesh" in node else [])
        for mk in meshes:
            for prim in doc["meshes"][mk]["primitives"]:
                if prim.get("mode", 4) != 4:
                    raise ValueError("only triangle lists are read")
                pos = [apply(world, p) for p in accessor(prim["attributes"]["POSITION"])]
                idx = [i[0] for i in accessor(prim["indices"])] if "indices" in prim else list(range(len(pos)))
                for k in range(0, len(idx) - 2, 3):
                    tris.append((pos[idx[k]], pos[idx[k + 1]], pos[idx[k + 2]]))
        for child in node.get("children", []):
            visit(child, world)

    for root in doc["scenes"][doc.get("scene", 0)]["nodes"]:
        visit(root, IDENT)
    return tris


def read_glb(data: bytes):
    if data[:4] != b"glTF" or struct.unpack_from("<I", data, 4)[0] != 2:
        raise ValueError("not a glTF 2.0 GLB")
    json_len = struct.unpack_from("<I", data, 12)[0]
    doc = json.loads(data[20:20 + json_len])
    off = 20 + json_len
    bin_len = struct.unpack_from("<I", data, off)[0]
    return gltf_triangles(doc, {0: data[off + 8:off + 8 + bin_len]}, 2)


def read_gltf1(gltf: bytes, buffers: dict):
    doc = json.loads(gltf)
    return gltf_triangles(doc, buffers, 1)


def read_obj(data: bytes):
    verts, tris = [], []
    for raw in data.decode("utf-8", "replace").splitlines():
        p = raw.split()
        if not p:
            continue
        if p[0] == "v":
            verts.append((float(p[1]), float(p[2]), float(p[3])))
        elif p[0] == "f":
            idx = []
            for tok in p[1:]:
                i = int(tok.split("/")[0])
                idx.append(i - 1 if i > 0 else len(verts) + i)
            for k in range(1, len(idx) - 1):  # fan-triangulate
                tris.append((verts[idx[0]], verts[idx[k]], verts[idx[k + 1]]))
    return tris


EGG_TOKEN = re.compile(r'//[^\n]*|/\*.*?\*/|"(?:[^"\\]|\\.)*"|[{}]|<[^>]*>|[^\s{}<"]+', re.S)


def read_egg(data: bytes):
    """Panda3D egg (optionally .pz, zlib-compressed): polygons from vertex pools.

    Egg files keep vertex positions in the model's global space (group and joint
    <Transform>s are not applied to them), so positions are used as they are.
    Returns (triangles, coordinate system string)."""
    if not data.lstrip().startswith(b"<"):
        data = zlib.decompress(data)
    toks = [t for t in EGG_TOKEN.findall(data.decode("latin-1")) if not t.startswith(("//", "/*"))]
    pos = 0

    def body():
        nonlocal pos
        items = []
        while pos < len(toks):
            t = toks[pos]
            pos += 1
            if t == "}":
                return items
            if t.startswith("<"):
                name = None
                if toks[pos] != "{":
                    name = toks[pos].strip('"')
                    pos += 1
                assert toks[pos] == "{", (t, toks[pos])
                pos += 1
                items.append((t[1:-1], name, body()))
            else:
                items.append(t)
        return items

    tree = body()
    pools, polys, coord = {}, [], None

    def walk(items):
        nonlocal coord
        for it in items:
            if not isinstance(it, tuple):
                continue
            tag, name, sub = it
            if tag == "CoordinateSystem":
                coord = sub[0]
            elif tag == "VertexPool":
                pool = {}
                for v in sub:
                    if isinstance(v, tuple) and v[0] == "Vertex":
                        nums = [float(x) for x in v[2] if not isinstance(x, tuple)]
                        pool[int(v[1])] = (nums[0], nums[1], nums[2])
                pools[name] = pool
            elif tag == "Polygon":
                for s in sub:
                    if isinstance(s, tuple) and s[0] == "VertexRef":
                        idx = [int(x) for x in s[2] if not isinstance(x, tuple)]
                        ref = [x for x in s[2] if isinstance(x, tuple) and x[0] == "Ref"][0][2][0]
                        polys.append((ref.strip('"'), idx))
            else:
                walk(sub)

    walk(tree)
    tris = []
    for ref, idx in polys:
        pool = pools[ref]
        for k in range(1, len(idx) - 1):
            tris.append((pool[idx[0]], pool[idx[k]], pool[idx[k + 1]]))
    return tris, coord


def z_up_to_y_up(tris):
    """Rigid rotation of -90 degrees about X: (x, y, z) -> (x, z, -y)."""
    return [tuple((p[0], p[2], -p[1]) for p in t) for t in tris]


# --------------------------------------------------------------------------
# Sampling
# --------------------------------------------------------------------------

def cross(u, v):
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


class Sampler:
    """Area-uniform points on a triangle soup, with the face's unit normal."""

    def __init__(self, tris):
        self.tris = tris
        self.cum = []
        self.normals = []
        total = 0.0
        for a, b, c in tris:
            n = cross(sub(b, a), sub(c, a))
            length = math.sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2])
            total += 0.5 * length
            self.cum.append(total)
            self.normals.append((n[0] / length, n[1] / length, n[2] / length) if length > 0 else (0.0, 0.0, 0.0))
        self.total = total

    def draw(self, rng: random.Random):
        i = bisect.bisect_right(self.cum, rng.random() * self.total)
        i = min(i, len(self.tris) - 1)
        a, b, c = self.tris[i]
        r1 = math.sqrt(rng.random())
        r2 = rng.random()
        wa, wb, wc = 1.0 - r1, r1 * (1.0 - r2), r1 * r2
        p = tuple(wa * a[k] + wb * b[k] + wc * c[k] for k in range(3))
        return p, self.normals[i]


def bbox(tris):
    pts = [p for t in tris for p in t]
    lo = tuple(min(p[k] for p in pts) for k in range(3))
    hi = tuple(max(p[k] for p in pts) for k in range(3))
    return lo, hi


def sample_uniform(tris, n, seed, normals=False):
    s, rng = Sampler(tris), random.Random(seed)
    out = []
    for _ in range(n):
        p, nrm = s.draw(rng)
        out.append(p + nrm if normals else p)
    return out


def sample_noisy_scan(tris, n, seed, view, density_floor, hole_dir, hole_radius, sigma_frac):
    """Scan-like points: density falls off on faces turned away from `view`, a patch
    around the surface point furthest along `hole_dir` is missing, and isotropic
    Gaussian noise of sigma_frac * bbox diagonal is added to every coordinate."""
    lo, hi = bbox(tris)
    diag = math.dist(lo, hi)
    sigma = sigma_frac * diag
    vl = math.sqrt(sum(x * x for x in view))
    view = tuple(x / vl for x in view)
    centre = max((p for t in tris for p in t), key=lambda p: sum(p[k] * hole_dir[k] for k in range(3)))
    r_hole = hole_radius * diag
    s, rng = Sampler(tris), random.Random(seed)
    out = []
    while len(out) < n:
        p, nrm = s.draw(rng)
        facing = max(0.0, sum(nrm[k] * view[k] for k in range(3)))
        keep = rng.random() < density_floor + (1.0 - density_floor) * facing
        if not keep or math.dist(p, centre) < r_hole:
            continue
        out.append(tuple(p[k] + rng.gauss(0.0, sigma) for k in range(3)))
    return out, {"sigma": sigma, "diag": diag, "centre": centre, "r_hole": r_hole}


# --------------------------------------------------------------------------
# The examples
# --------------------------------------------------------------------------

def decimals_for(points):
    m = max(abs(c) for p in points for c in p[:3])
    return max(0, 6 - max(1, math.ceil(math.log10(m + 1e-30))))


def ply(points, comments, normals=False):
    d = decimals_for(points)
    lines = ["ply", "format ascii 1.0"] + ["comment " + c for c in comments]
    lines += [f"element vertex {len(points)}", "property float x", "property float y", "property float z"]
    if normals:
        lines += ["property float nx", "property float ny", "property float nz"]
    lines.append("end_header")
    for p in points:
        xyz = " ".join(f"{c:.{d}f}" for c in p[:3])
        lines.append(xyz + (" " + " ".join(f"{c:.4f}" for c in p[3:6]) if normals else ""))
    return ("\n".join(lines) + "\n").encode("ascii")


def build(cache: Path):
    """Returns {file name: bytes} for the PLYs and examples.json."""
    files, entries = {}, []
    see = "see web/examples/SOURCES.md; made by scripts/make_examples.py"

    # 1. Hard surface: Cesium Milk Truck (glTF 1.0, Y-up, metres).
    truck = read_gltf1(original("truck.gltf", cache), {"CesiumMilkTruck": original("truck.bin", cache)})
    pts = sample_uniform(truck, 4096, seed=101)
    files["milk_truck_4096.ply"] = ply(pts, [
        "Cesium Milk Truck (CesiumMilkTruck.gltf, glTF 1.0 sample model), (c) Cesium, CC-BY-4.0",
        "from Debian assimp-testmodels 5.2.5~ds0-1; changed: 4096 points sampled uniformly by area, seed 101",
        see])
    entries.append({"file": "milk_truck_4096.ply", "label": "Milk truck (4096 points)", "kind": "hard-surface",
                    "license": "CC-BY-4.0",
                    "source": "Cesium Milk Truck (glTF sample model) by Cesium, via Debian assimp-testmodels 5.2.5~ds0-1"})

    # 2. Organic: the Panda3D panda (egg, declared Y-up).
    panda, coord = read_egg(original("panda.egg.pz", cache))
    assert coord == "Y-Up", coord
    pts = sample_uniform(panda, 4096, seed=202)
    files["panda_4096.ply"] = ply(pts, [
        "Panda3D panda (models/panda.egg.pz), BSD-3-Clause, Copyright (c) 2008 Carnegie Mellon University",
        "from PyPI panda3d 1.10.16; changed: 4096 points sampled uniformly by area, seed 202",
        see])
    entries.append({"file": "panda_4096.ply", "label": "Panda (4096 points)", "kind": "organic",
                    "license": "BSD-3-Clause",
                    "source": "Panda3D's panda model (models/panda.egg.pz), PyPI panda3d 1.10.16"})

    # 3. Thin / open: the COMPAS tube mesh, a single-layer shell (Z-up -> Y-up).
    tube = z_up_to_y_up(read_obj(original("tubemesh.obj", cache)))
    pts = sample_uniform(tube, 3072, seed=303)
    files["tube_shell_3072.ply"] = ply(pts, [
        "COMPAS sample tubemesh.obj (an open, single-layer shell), MIT, Copyright (c) 2017-2023 COMPAS Association",
        "from PyPI compas 2.15.1; changed: rotated Z-up to Y-up (x, z, -y), 3072 points sampled uniformly by area, seed 303",
        see])
    entries.append({"file": "tube_shell_3072.ply", "label": "Tube shell (3072 points)", "kind": "thin/open",
                    "license": "MIT",
                    "source": "COMPAS sample tubemesh.obj, PyPI compas 2.15.1 (rotated to Y-up)"})

    # 4. Noisy scan: the Panda3D walking panda (egg, declared Z-up -> Y-up), with synthetic
    #    scanner-like density, a missing patch and 1% Gaussian noise added by us.
    walk, coord = read_egg(original("panda-model.egg.pz", cache))
    assert coord == "Z-Up", coord
    walk = z_up_to_y_up(walk)
    pts, info = sample_noisy_scan(walk, 4096, seed=404, view=(0.4, 0.5, 1.0), density_floor=0.15,
                                  hole_dir=(1.0, 0.3, 0.0), hole_radius=0.10, sigma_frac=0.01)
    files["panda_walk_noisy_4096.ply"] = ply(pts, [
        "Panda3D walking panda (models/panda-model.egg.pz), BSD-3-Clause, Copyright (c) 2008 Carnegie Mellon University",
        "from PyPI panda3d 1.10.16; changed: rotated Z-up to Y-up (x, z, -y), then 4096 points, seed 404, with",
        "SYNTHETIC scan artefacts added by MeshFlow: density 0.15 + 0.85 * max(0, n . v) toward view v = (0.4, 0.5, 1),",
        "a missing patch of radius 10% of the bbox diagonal on the +x flank, and isotropic Gaussian noise",
        f"sigma = 1% of the bbox diagonal ({info['sigma']:.3f} model units); not a real scan",
        see])
    entries.append({"file": "panda_walk_noisy_4096.ply", "label": "Walking panda, noisy (4096 points)",
                    "kind": "noisy scan", "license": "BSD-3-Clause",
                    "source": "Panda3D's walking panda (models/panda-model.egg.pz), PyPI panda3d 1.10.16, "
                              "with synthetic noise, uneven density and a hole added by us"})

    # 5. With normals: Cesium 2 Cylinder Engine (GLB, Y-up, CAD units), face normals.
    engine = read_glb(original("engine.glb", cache))
    pts = sample_uniform(engine, 3072, seed=505, normals=True)
    files["engine_normals_3072.ply"] = ply(pts, [
        "2 Cylinder Engine (2CylinderEngine.glb, glTF 2.0 sample model), (c) Cesium, CC-BY-4.0",
        "from Debian assimp-testmodels 5.2.5~ds0-1; changed: 3072 points sampled uniformly by area, seed 505;",
        "nx ny nz are the unit normals of the source triangle each point lies on (winding order)",
        see], normals=True)
    entries.append({"file": "engine_normals_3072.ply", "label": "Two-cylinder engine, with normals (3072 points)",
                    "kind": "with normals", "license": "CC-BY-4.0",
                    "source": "2 Cylinder Engine (glTF sample model) by Cesium, via Debian assimp-testmodels 5.2.5~ds0-1"})

    files["examples.json"] = (json.dumps(entries, indent=2, ensure_ascii=False) + "\n").encode("utf-8")

    for name, (pkg, member, how) in LICENSE_FILES.items():
        data = read_member(pkg, member, cache)
        if how == "spdx-json":
            data = json.loads(data)["licenseText"].encode("utf-8")
            if not data.endswith(b"\n"):
                data += b"\n"
        files["licenses/" + name] = data
    return files


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cache", type=Path, default=DEFAULT_CACHE, help="folder for the original files")
    ap.add_argument("--out", type=Path, default=OUT)
    ap.add_argument("--check", action="store_true", help="compare with the files in --out instead of writing")
    args = ap.parse_args()
    files = build(args.cache)
    bad = 0
    for name, data in files.items():
        path = args.out / name
        if args.check:
            same = path.exists() and path.read_bytes() == data
            print(f"{'ok  ' if same else 'DIFF'} {name}")
            bad += not same
        else:
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_bytes(data)
            print(f"{name}: {len(data)} bytes, sha256 {sha256(data)}")
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
