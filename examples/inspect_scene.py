#!/usr/bin/env python3
"""The scene: cameras (centres seen from above) and the bounding box, and one image with
its silhouette.

usage: inspect_scene.py RUN_DIR [OUT.png]
"""
import os
import sys

import h5py
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

run = sys.argv[1]
out = sys.argv[2] if len(sys.argv) > 2 else os.path.join(run, "scene.png")
with h5py.File(os.path.join(run, "scene.h5")) as f:
    R, t = f["cameras/R"][()], f["cameras/t"][()]
    names = [n.decode() if isinstance(n, bytes) else n for n in f["cameras/names"][()]]
    lo, hi = f["box/min"][()], f["box/max"][()]
    img, sil, valid = f["images/rgb"][0], f["silhouettes/mask"][0], f["silhouettes/valid"][()]
centres = np.einsum("nji,nj->ni", R, -t)
print(f"{len(names)} cameras, {valid.sum()} silhouettes, box {lo} - {hi}")
fig, ax = plt.subplots(1, 2, figsize=(11, 4))
ax[0].plot(centres[:, 0], centres[:, 2], "o")
ax[0].add_patch(plt.Rectangle((lo[0], lo[2]), hi[0] - lo[0], hi[2] - lo[2], fill=False, color="r"))
ax[0].set_aspect("equal")
ax[0].set_title("camera centres (x, z) and the box")
ax[1].imshow(img)
ax[1].contour(sil > 0, levels=[0.5], colors="lime")
ax[1].set_title(names[0])
fig.tight_layout()
fig.savefig(out, dpi=90)
print("wrote", out)
