"""A weights folder's pair with its capacity raised: `python3 raise.py SRC DST [VERTICES]`
copies SRC's vae.* and dit.* to DST with the VAE's num_vertices set to VERTICES (default 2,048)
and num_latents with it (same merge ratio), the DiT's num_latents to match and its
count_divisor kept at the latents it was trained with. No weight changes (the configuration is
not a shape: docs/design.md, MeshVAE), so the pair loads and, for any budget it could make
before, gives the same mesh (crate/tests/capacity.rs)."""
import json, os, shutil, sys

src, dst = sys.argv[1], sys.argv[2]
vertices = int(sys.argv[3]) if len(sys.argv) > 3 else 2048
os.makedirs(dst, exist_ok=True)
for name in os.listdir(src):
    if name.startswith(('vae.', 'dit.')) and not name.endswith('train.json'):
        shutil.copy(os.path.join(src, name), dst)
vae = json.load(open(os.path.join(src, 'vae.json')))
latents = vertices // (vae['num_vertices'] // vae['num_latents'])
for name, key in [('vae.json', None), ('vae.manifest.json', 'model'), ('dit.json', None),
                  ('dit.manifest.json', 'model')]:
    doc = json.load(open(os.path.join(dst, name)))
    cfg = doc[key] if key else doc
    if name.startswith('vae'):
        cfg['num_vertices'], cfg['num_latents'] = vertices, latents
    else:
        cfg['count_divisor'] = cfg.get('count_divisor') or cfg['num_latents']
        cfg['num_latents'] = latents
    json.dump(doc, open(os.path.join(dst, name), 'w'), indent=2)
print(f'{dst}: capacity {vertices} vertices, {latents} latents')
