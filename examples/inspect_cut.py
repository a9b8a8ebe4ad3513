#!/usr/bin/env python3
"""The cut: labels, energy parts and the face scores omega (histogram of the cut faces'
outward scores against all scored faces).

usage: inspect_cut.py RUN_DIR [OUT.png]
"""
import glob
import os
import sys

import h5py
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

run = sys.argv[1]
out = sys.argv[2] if len(sys.argv) > 2 else os.path.join(run, "cut.png")
L = max(int(p.split("_")[-1][:-3]) for p in glob.glob(os.path.join(run, "mesh_*.h5")))
with h5py.File(os.path.join(run, f"mesh_{L}.h5")) as f:
    face_cells = f["face_cells"][()]
with h5py.File(os.path.join(run, "labels.h5")) as f:
    lab = f["cells/label"][()]
    print(f"labels: {(lab == 1).sum()} interior, {(lab == -1).sum()} exterior, {(lab == 0).sum()} free")
with h5py.File(os.path.join(run, "scores.h5")) as f:
    omega = f["faces/omega"][()]
    scored = f["faces/scored"][()] > 0
fig, ax = plt.subplots(figsize=(6, 4))
ax.hist(omega[scored].max(1), bins=50, density=True, histtype="step", label="scored faces (best side)")
for name in ("cut1", "cut2"):
    p = os.path.join(run, f"{name}.h5")
    if not os.path.exists(p):
        continue
    with h5py.File(p) as f:
        inside = f["cells/inside"][()]
        a = dict(f.attrs)
        print(f"{name}: energy {a['energy']:.4g} = data {a['data_energy']:.4g} + area {a['area_energy']:.4g} "
              f"+ visibility {a.get('visibility_energy', 0):.4g}; {a['cut_faces']} faces")
    c0, c1 = face_cells[:, 0], face_cells[:, 1]
    in0 = inside[c0] > 0
    in1 = np.where(c1 >= 0, inside[np.maximum(c1, 0)] > 0, False)
    cut = in0 != in1
    outward = np.where(in0, omega[:, 0], omega[:, 1])
    ax.hist(outward[cut], bins=50, density=True, histtype="step", label=f"{name} faces (outward side)")
ax.set_xlabel("omega")
ax.legend()
fig.tight_layout()
fig.savefig(out, dpi=90)
print("wrote", out)
