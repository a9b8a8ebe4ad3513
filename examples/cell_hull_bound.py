#!/usr/bin/env python3
"""How well can a surface made of this mesh's cells agree with the silhouettes?

Labels every cell of the run's finest mesh from the silhouettes alone: interior when its four
corners (or, with --centroid, its centroid) project inside every good silhouette, exterior
otherwise (a point outside an image never carves, as in `label`). Cutting with these labels
gives the visual hull at cell resolution, the best silhouette agreement that cell-level
"sure" interior constraints can reach (docs/architecture.md, "How far whole cells can go").

usage: cell_hull_bound.py RUN_DIR OUT_LABELS.h5 [--centroid]
then:  build/bin/cut --mesh RUN_DIR/mesh_<L>.h5 --scores RUN_DIR/scores.h5 \\
           --labels OUT_LABELS.h5 --out hull_cut.h5 --ply hull.ply
       build/bin/silhouette-fix --scene RUN_DIR/scene.h5 --agreement hull.ply RUN_DIR/cut2.ply
"""
import glob
import os
import shutil
import sys

import h5py
import numpy as np

if len(sys.argv) < 3 or sys.argv[1] in ("-h", "--help"):
    sys.exit(__doc__)
run, out = sys.argv[1], sys.argv[2]
by_centroid = "--centroid" in sys.argv[3:]
L = max(int(p.split("_")[-1][:-3]) for p in glob.glob(os.path.join(run, "mesh_*.h5")))
with h5py.File(os.path.join(run, f"mesh_{L}.h5")) as f:
    V, C = f["vertices"][:], f["cells"][:]
with h5py.File(os.path.join(run, "scene.h5")) as f:
    K, R, t = f["cameras/K"][:], f["cameras/R"][:], f["cameras/t"][:]
    sil, valid = f["silhouettes/mask"][:], f["silhouettes/valid"][:]
if not valid.any():
    sys.exit(f"{run}/scene.h5: no view has a silhouette")
pts = V[C].mean(axis=1) if by_centroid else V
inside = np.ones(len(C), bool)
for v in np.flatnonzero(valid):
    x = K[v] @ (R[v] @ pts.T + t[v][:, None])
    u, w = np.rint(x[0] / x[2]).astype(np.int64), np.rint(x[1] / x[2]).astype(np.int64)
    H, W = sil[v].shape
    ok = (x[2] > 0) & (u >= 0) & (u < W) & (w >= 0) & (w < H)
    hit = np.ones(len(pts), bool)          # outside the image: no evidence
    hit[ok] = sil[v][w[ok], u[ok]] > 0
    inside &= hit if by_centroid else hit[C].all(axis=1)
labels = os.path.join(run, "labels.h5")
shutil.copy(labels, out)                    # same layout as label's file, every cell decided
with h5py.File(out, "r+") as f:
    f["cells/label"][:] = np.where(inside, 1, -1).astype(np.int8)
print(f"mesh_{L}: {inside.sum()} of {len(C)} cells inside every silhouette "
      f"({'centroid' if by_centroid else 'all four corners'}) -> {out}")
