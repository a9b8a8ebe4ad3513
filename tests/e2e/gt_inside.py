"""Ground-truth helpers for the e2e tests: a binary PLY reader and an inside test by ray
parity (for checking labels against the exact synthetic surface)."""
import sys

import h5py
import numpy as np

def read_ply(path):
    f=open(path,'rb'); hdr=[]; 
    while True:
        l=f.readline().decode().strip(); hdr.append(l)
        if l=='end_header': break
    nv=nf=0; vprops=[]; cur=None; fprops=[]
    for l in hdr:
        p=l.split()
        if p[0]=='element': cur=p[1]; n=int(p[2]); 
        if p[0]=='element' and p[1]=='vertex': nv=n
        if p[0]=='element' and p[1]=='face': nf=n
        if p[0]=='property' and cur=='vertex': vprops.append((p[-1],p[1]))
        if p[0]=='property' and cur=='face' and p[1]!='list': fprops.append((p[-1],p[1]))
    tmap={'float':'<f4','double':'<f8','uchar':'u1','int':'<i4','float32':'<f4'}
    vdt=np.dtype([(n,tmap[t]) for n,t in vprops]); V=np.frombuffer(f.read(nv*vdt.itemsize),vdt,nv)
    fdt=np.dtype([('n','u1'),('i','<i4',(3,))]+[(n,tmap[t]) for n,t in fprops]); F=np.frombuffer(f.read(nf*fdt.itemsize),fdt,nf)
    return np.stack([V['x'],V['y'],V['z']],1).astype(float), F['i']
def inside(P, V, F, d=np.array([0.5773,0.5774,0.5775])):
    A,B,C=V[F[:,0]],V[F[:,1]],V[F[:,2]]; e1=B-A; e2=C-A
    pv=np.cross(d,e2); det=(e1*pv).sum(1)
    res=np.zeros(len(P),bool)
    for i,p in enumerate(P):
        t=p-A; u=(t*pv).sum(1)/det; q=np.cross(t,e1); v=(q@d)/det; tt=(q*e2).sum(1)/det
        hit=(u>=0)&(v>=0)&(u+v<=1)&(tt>0)
        res[i]=hit.sum()%2==1
    return res


def label_errors(gt_ply, mesh_h5, labels_h5, sample=1500, seed=0):
    """Samples interior and exterior cells; returns (interior_outside, exterior_inside, n_int, n_ext)."""
    V, F = read_ply(gt_ply)
    with h5py.File(mesh_h5) as m, h5py.File(labels_h5) as f:
        X, C = m["vertices"][()], m["cells"][()]
        lab = f["cells/label"][()]
    cen = X[C].mean(1)
    rng = np.random.default_rng(seed)
    out = []
    for val in (1, -1):
        idx = np.where(lab == val)[0]
        if len(idx) > sample:
            idx = rng.choice(idx, sample, replace=False)
        ins = inside(cen[idx], V, F) if len(idx) else np.zeros(0, bool)
        out.append((ins if val == -1 else ~ins).sum())
        out.append(len(idx))
    return out[0], out[2], out[1], out[3]
