"""Reading the data build's shards from Python, for the prototypes and tools under bench/.

A shard is a safetensors file of `positions`, `faces` and their per-mesh `vertex_offsets` /
`face_offsets`; `manifest.jsonl` beside the shards names each mesh's split, shard and index
(crate/src/data/ writes them)."""
import json, os, struct
import numpy as np

DTYPES = {'F32': np.float32, 'U32': np.uint32, 'U64': np.uint64}


def read_shard(path):
    """All tensors of one shard (read-only views of its bytes) and its metadata."""
    with open(path, 'rb') as f:
        b = f.read()
    n = struct.unpack('<Q', b[:8])[0]; header = json.loads(b[8:8 + n]); base = 8 + n
    tensors = {k: np.frombuffer(b[base + v['data_offsets'][0]:base + v['data_offsets'][1]],
                                dtype=DTYPES[v['dtype']]).reshape(v['shape'])
               for k, v in header.items() if k != '__metadata__'}
    return tensors, header['__metadata__']


def shard_metadata(path):
    """A shard's `__metadata__`, reading only its header."""
    with open(path, 'rb') as f:
        n = struct.unpack('<Q', f.read(8))[0]
        return json.loads(f.read(n))['__metadata__']


def meshes(shards_dir, splits, max_vertices):
    """(manifest entry, positions, faces) of each mesh of `splits` with at most `max_vertices`
    vertices, in manifest order; each shard is read once."""
    cache = {}
    for line in open(os.path.join(shards_dir, 'manifest.jsonl')):
        e = json.loads(line)
        if e['split'] not in splits or e['vertices'] > max_vertices:
            continue
        if e['shard'] not in cache:
            cache[e['shard']] = read_shard(os.path.join(shards_dir, e['shard']))[0]
        t, i = cache[e['shard']], e['index']
        yield (e, t['positions'][t['vertex_offsets'][i]:t['vertex_offsets'][i + 1]],
               t['faces'][t['face_offsets'][i]:t['face_offsets'][i + 1]])


def surface_points(v, f, rng, count=4096):
    """`count` area-weighted samples of the surface of vertices `v` and faces `f` (float64 and
    int64 arrays), as `meshflow eval generate` conditions on; None for a surface of no area."""
    tri = v[f]; area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    if area.sum() <= 0: return None
    k = rng.choice(len(f), count, p=area / area.sum())
    r1, r2 = rng.random(count), rng.random(count); s = np.sqrt(r1)
    w = np.column_stack([1 - s, s * (1 - r2), s * r2])
    return np.einsum('ij,ijk->ik', w, tri[k])
