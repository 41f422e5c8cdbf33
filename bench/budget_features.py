#!/usr/bin/env python3
"""Can shape features of the input point cloud predict the artist's vertex count better than the
default budget rule's two (issue 15 item 5)? A prototype, not product code.

    meshflow eval generate --split train --limit 1000 --steps 1 --samples 1 --no-fit --meshes T -o T.json
    meshflow eval generate --split val --steps 1 --samples 1 --no-fit --meshes V -o V.json
    python3 bench/budget_features.py T V

(the generations are only there to write each mesh's conditioning points and the ground truth's
vertex count). Fits ln V by least squares on T, reports R^2 on T and on V for the shipped
features (occupancy of the 32^3 grid, 16-neighbour surface variation), each further feature
added to them, and a greedy forward selection. Needs numpy, scipy, trimesh."""
import json, sys, numpy as np, trimesh
from scipy.spatial import cKDTree
from scipy import ndimage
def feats(p, rng):
    # model frame: bbox to [-1,1] (max extent), as to_model_frame does (approx)
    lo, hi = p.min(0), p.max(0); c=(lo+hi)/2; s=(hi-lo).max()/2; q=(p-c)/s
    out={}
    for g in (16,32,64):
        idx=np.clip(np.floor((q+1)/2*g),0,g-1).astype(int)
        occ=np.zeros((g,g,g),bool); occ[idx[:,0],idx[:,1],idx[:,2]]=True
        out[f'ln_occ{g}']=np.log(occ.sum())
        if g==32:
            lab,n=ndimage.label(occ, structure=np.ones((3,3,3))); out['ln_pieces']=np.log(n)
    tree=cKDTree(q)
    sel=rng.choice(len(q), min(512,len(q)), replace=False)
    for k in (8,16,32,64):
        d,ii=tree.query(q[sel],k)
        shares=[]
        for row in ii:
            nb=q[row]; cov=np.cov(nb.T,bias=True); ev=np.linalg.eigvalsh(cov); shares.append(ev[0]/max(ev.sum(),1e-18))
        shares=np.array(shares)
        out[f'var{k}']=shares.mean()
        if k==16:
            out['frac_corner16']=(shares>0.05).mean(); out['var16_p90']=np.quantile(shares,0.9)
    ext=np.sort(hi-lo)/ (hi-lo).max(); out['ext_min']=ext[0]; out['ext_mid']=ext[1]
    d,_=tree.query(q,2); out['ln_spacing']=np.log(d[:,1].mean())
    return out
def load(run):
    d=json.load(open(f'{run}.json')); rows=[]; rng=np.random.default_rng(0)
    for i,m in enumerate(d['per_mesh']):
        try: p=np.asarray(trimesh.load(f'{run}/{i}.points.ply').vertices)
        except Exception: continue
        f=feats(p,rng); f['y']=np.log(m['gt_vertices']); rows.append(f)
    return rows
tr=load(sys.argv[1]); va=load(sys.argv[2])
keys=[k for k in tr[0] if k!='y']
X=lambda rows,ks: np.column_stack([np.ones(len(rows))]+[[r[k] for r in rows] for k in ks])
Y=lambda rows: np.array([r['y'] for r in rows])
def r2(ks):
    A=X(tr,ks); w=np.linalg.lstsq(A,Y(tr),rcond=None)[0]
    def sc(rows):
        pr=X(rows,ks)@w; y=Y(rows); return 1-((y-pr)**2).sum()/((y-y.mean())**2).sum(), np.median(np.abs(y-pr))
    return sc(tr), sc(va), w
print(len(tr), len(va))
print('shipped features', r2(['ln_occ32','var16'])[:2])
for k in keys: print(k, 'alone+shipped', [round(x,3) for x in sum([list(t) for t in r2(['ln_occ32','var16',k])[:2]],[])])
# greedy forward selection
chosen=[]; rest=list(keys)
for step in range(6):
    best=max(rest,key=lambda k: r2(chosen+[k])[1][0]); chosen.append(best); rest.remove(best)
    (a,b),(c,e),w=r2(chosen); print('forward', chosen, 'train R2 %.3f val R2 %.3f val med|err| %.3f'%(a,c,e))
