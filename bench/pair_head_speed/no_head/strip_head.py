#!/usr/bin/env python3
"""A copy of a weights folder whose VAE has no pair head, for timing only (issue 15 item 8).

    python3 bench/pair_head_speed/no_head/strip_head.py WEIGHTS OUT

The VAE's `decoder.pair_head.*` tensors are left out, `pair_head` is set to 0 in vae.json and
in the manifest's model, and the manifest's sha256 is the new file's; the DiT is copied as is.
The decoder then does everything the shipped one does except the pair head, so
`meshflow bench generate --weights OUT` times decoding without it. Its meshes are not the
shipped pair's (the stage-3 decoder was trained with the head), so it is not for quality."""
import hashlib, json, os, shutil, struct, sys

src, out = sys.argv[1], sys.argv[2]
os.makedirs(out, exist_ok=True)
for name in ('dit.json', 'dit.manifest.json', 'dit.safetensors'):
    shutil.copy(os.path.join(src, name), out)
with open(os.path.join(src, 'vae.safetensors'), 'rb') as f:
    raw = f.read()
n = struct.unpack('<Q', raw[:8])[0]
header, data = json.loads(raw[8:8 + n]), raw[8 + n:]
meta = header.pop('__metadata__', None)
kept, blob = {}, bytearray()
for key, v in sorted(header.items(), key=lambda kv: kv[1]['data_offsets'][0]):
    if 'pair_head' in key:
        continue
    a, b = v['data_offsets']
    kept[key] = dict(v, data_offsets=[len(blob), len(blob) + b - a])
    blob += data[a:b]
if meta is not None:
    kept['__metadata__'] = meta
h = json.dumps(kept).encode()
h += b' ' * (-len(h) % 8)
body = struct.pack('<Q', len(h)) + h + bytes(blob)
with open(os.path.join(out, 'vae.safetensors'), 'wb') as f:
    f.write(body)
config = json.load(open(os.path.join(src, 'vae.json')))
config['pair_head'] = 0
json.dump(config, open(os.path.join(out, 'vae.json'), 'w'), indent=2)
manifest = json.load(open(os.path.join(src, 'vae.manifest.json')))
manifest['model']['pair_head'] = 0
manifest['sha256'] = hashlib.sha256(body).hexdigest()
json.dump(manifest, open(os.path.join(out, 'vae.manifest.json'), 'w'), indent=1)
