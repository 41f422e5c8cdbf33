"""The boundary loops of a folder of OBJ meshes (`meshflow convert K.ours.glb K.obj`), each
classified by how a fan around its centroid would fold: onto the rim faces across the loop
("onto"), onto itself ("within"), both, or neither (normals more than about 143 degrees
apart, as crate/src/geometry/topology.rs folds()). Run in the folder: python3 hole_loops.py
"""
import numpy as np, sys, glob, collections
FOLD=-0.8
def load(p):
    V=[];F=[]
    for l in open(p):
        t=l.split()
        if not t: continue
        if t[0]=='v': V.append([float(x) for x in t[1:4]])
        if t[0]=='f': F.append([int(x.split('/')[0])-1 for x in t[1:4]])
    return np.array(V),np.array(F)
def nrm(a,b,c):
    n=np.cross(b-a,c-a); l=np.linalg.norm(n); return n/l if l>0 else n
stats=collections.Counter(); sizes=[]; rows=[]
for p in sorted(glob.glob('*.obj')):
    V,F=load(p)
    if len(F)==0: continue
    ext=(V.max(0)-V.min(0)).max()
    walk={}
    for i,(a,b,c) in enumerate(F):
        for u,v in ((a,b),(b,c),(c,a)): walk[(u,v)]=i
    out=collections.defaultdict(list)
    for (u,v),i in walk.items():
        if (v,u) not in walk: out[v].append(u)
    while any(out.values()):
        s=next(a for a,l in out.items() if l)
        loop=[s]; x=out[s].pop()
        while x!=s:
            loop.append(x)
            if not out[x]: break
            x=out[x].pop()
        k=len(loop); c=V[loop].mean(0)
        onto=0; within=0
        ns=[nrm(V[loop[i]],V[loop[(i+1)%k]],c) for i in range(k)]
        for i in range(k):
            g=walk.get((loop[(i+1)%k],loop[i]))
            if g is None: continue
            m=nrm(*V[F[g]])
            if np.dot(ns[i],m)<FOLD: onto+=1
            if np.dot(ns[i],ns[(i+1)%k])<FOLD: within+=1
        perim=sum(np.linalg.norm(V[loop[i]]-V[loop[(i+1)%k]]) for i in range(k))/ext
        cls='onto' if onto and not within else 'within' if within and not onto else 'both' if onto else 'none'
        stats[cls]+=1; sizes.append(k)
        rows.append((p,k,onto,within,round(perim,3),cls))
print(stats, 'loops',len(sizes))
print('size hist', collections.Counter(min(s,30)//3*3 for s in sizes))
import itertools
for cls in ['onto','within','both','none']:
    r=[x for x in rows if x[5]==cls]
    print(cls, len(r), 'median k', np.median([x[1] for x in r]) if r else 0, 'median onto', np.median([x[2] for x in r]) if r else 0, 'median perim/ext', np.median([x[4] for x in r]) if r else 0)
print([x for x in rows if x[5]=='onto'][:15])
print('onto count hist (all loops):', sorted(collections.Counter(min(x[2],40)//4*4 for x in rows).items()))
print('frac onto/k hist:', sorted(collections.Counter(round(x[2]/x[1],1) for x in rows).items()))
