"""A copy of a shard build with only its train and val meshes of at most MAX_VERTICES vertices
(512 by default; all that training a model of that capacity reads), small enough to carry to a
GPU machine: `python3 compact_data.py SHARDS OUT [MAX_VERTICES]` (SHARDS:
~/.cache/meshflow/data/shards)."""
import json, shutil, struct, sys, os, numpy as np
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..'))
from shards import meshes, shard_metadata
src, dst = sys.argv[1], sys.argv[2]
max_vertices = int(sys.argv[3]) if len(sys.argv) > 3 else 512
os.makedirs(dst, exist_ok=True)
def write(path, t, meta):
    names = {np.dtype(np.float32): 'F32', np.dtype(np.uint32): 'U32', np.dtype(np.uint64): 'U64'}
    h = {'__metadata__': meta}; off = 0; blobs = []
    for k in sorted(t):
        a = np.ascontiguousarray(t[k]); h[k] = {'dtype': names[a.dtype], 'shape': list(a.shape), 'data_offsets': [off, off + a.nbytes]}; off += a.nbytes; blobs.append(a.tobytes())
    hb = json.dumps(h).encode(); hb += b' ' * ((8 - len(hb) % 8) % 8)
    with open(path, 'wb') as f:
        f.write(struct.pack('<Q', len(hb))); f.write(hb); [f.write(x) for x in blobs]
out = {'train': {'pos': [], 'faces': [], 'vo': [0], 'fo': [0]}, 'val': {'pos': [], 'faces': [], 'vo': [0], 'fo': [0]}}
new_entries = []
for e, p, f in meshes(src, ('train', 'val'), max_vertices):
    o = out[e['split']]; e = dict(e); e['shard'] = f"{e['split']}-00000.safetensors"; e['index'] = len(o['vo']) - 1
    o['pos'].append(p); o['faces'].append(f); o['vo'].append(o['vo'][-1] + len(p)); o['fo'].append(o['fo'][-1] + len(f)); new_entries.append(e)
meta = shard_metadata(os.path.join(src, json.loads(open(f'{src}/manifest.jsonl').readline())['shard']))
for s, o in out.items():
    write(f'{dst}/{s}-00000.safetensors', {'positions': np.concatenate(o['pos']), 'faces': np.concatenate(o['faces']), 'vertex_offsets': np.array(o['vo'], np.uint64), 'face_offsets': np.array(o['fo'], np.uint64)}, meta)
with open(f'{dst}/manifest.jsonl', 'w') as f:
    for e in new_entries: f.write(json.dumps(e) + '\n')
shutil.copy(f'{src}/build.json', dst)
print(len(new_entries), {s: len(o['vo']) - 1 for s, o in out.items()})
