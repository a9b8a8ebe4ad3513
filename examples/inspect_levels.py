#!/usr/bin/env python3
"""The adaptive refinement level by level: cells per level, active share, crossing faces,
and a histogram of the faces' best lattice-point scores.

usage: inspect_levels.py RUN_DIR [OUT.png]
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
out = sys.argv[2] if len(sys.argv) > 2 else os.path.join(run, "levels.png")
meshes = sorted(glob.glob(os.path.join(run, "mesh_*.h5")), key=lambda p: int(p.split("_")[-1][:-3]))
fig, ax = plt.subplots(1, 2, figsize=(11, 4))
for m in meshes:
    i = int(m.split("_")[-1][:-3])
    with h5py.File(m) as f:
        cells = f["cells"].shape[0]
        levels = np.bincount(f["cell_level"][()].astype(int))
    line = f"mesh_{i}: {cells} cells, per level {levels.tolist()}"
    pc = os.path.join(run, f"pc_{i}.h5")
    if os.path.exists(pc):
        with h5py.File(pc) as f:
            active = f["cells/active"][()]
            crossing = f["faces/crossing"][()]
            tested = f["faces/tested"][()]
            best = f["faces/best_score"][()][tested > 0]
        line += f"; active {active.mean() * 100:.1f} %, crossing faces {(crossing > 0).sum()} of {(tested > 0).sum()} tested"
        ax[1].hist(best[best >= 0], bins=50, histtype="step", label=f"level {i}")
    ax[0].bar(i, cells)
    print(line)
ax[0].set_xlabel("level")
ax[0].set_ylabel("cells")
ax[0].set_yscale("log")
ax[1].set_xlabel("best lattice-point score of a tested face")
ax[1].legend()
fig.tight_layout()
fig.savefig(out, dpi=90)
print("wrote", out)
