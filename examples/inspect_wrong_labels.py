#!/usr/bin/env python3
"""Where are the hard labels wrong? Draws the cells that the ground truth contradicts.

Reads the "labels" object that `evaluate --labels` writes into eval_cut1.json (labels.h5) or
eval_cut2.json (silfix.h5) on synthetic scenes (schemas/evaluate.md): the wrong cells' ids.
Plots their centroids in three orthogonal projections over the ground truth's points,
coloured by the reason that labelled them (schemas/labels.md), larger when wholly wrong
(centroid and four corners on the wrong side), and prints the count per reason.

usage: inspect_wrong_labels.py RUN_DIR OUT.png [--eval eval_cut2.json]
"""
import glob
import json
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

REASONS = ["none", "boundary", "outside_hull", "voted_out", "hidden", "silfix_exterior", "silfix_interior",
           "hull_core", "outside_q_hull", "seed_core", "seen_free"]


def ply_vertices(path):
    """x, y, z of a binary little-endian PLY's vertices (the synthetic ground truth)."""
    types = {"float": "<f4", "float32": "<f4", "double": "<f8", "uchar": "u1", "int": "<i4", "uint8": "u1"}
    with open(path, "rb") as f:
        props, n, in_vertex = [], 0, False
        while True:
            line = f.readline().decode().split()
            if not line:
                continue
            if line[0] == "format" and line[1] != "binary_little_endian":
                sys.exit(f"{path}: only binary little-endian PLY is read here, not {line[1]}")
            if line[0] == "element":
                in_vertex = line[1] == "vertex"
                n = int(line[2]) if in_vertex else n
            elif line[0] == "property" and in_vertex:
                props.append((line[-1], types[line[1]]))
            elif line[0] == "end_header":
                break
        v = np.frombuffer(f.read(n * np.dtype(props).itemsize), np.dtype(props), n)
    return np.stack([v["x"], v["y"], v["z"]], 1).astype(float)


def main():
    args = sys.argv[1:]
    if len(args) < 2 or args[0] in ("-h", "--help"):
        sys.exit(__doc__)
    run, out = args[0], args[1]
    name = args[args.index("--eval") + 1] if "--eval" in args else "eval_cut1.json"
    ev_path = os.path.join(run, name)
    if not os.path.exists(ev_path):
        sys.exit(f"{ev_path}: not there (make -f pipeline.mk DATA=synth-... evaluate writes it)")
    ev = json.load(open(ev_path))
    fig, axes = plt.subplots(1, 3, figsize=(15, 5.4))
    if "labels" not in ev:  # a real dataset: no ground truth to check labels against
        for ax in axes:
            ax.axis("off")
        axes[1].text(0.5, 0.5, f"{name} has no labels object\n(evaluate --labels: synthetic scenes only)",
                     ha="center", va="center", fontsize=14)
        fig.savefig(out, dpi=80)
        print(f"{name}: no labels object -> {out}")
        return
    lab = ev["labels"]
    meshes = sorted(glob.glob(os.path.join(run, "mesh_*.h5")), key=lambda p: int(p.split("_")[-1][:-3]))
    mesh_file = ev["inputs"].get("tetmesh", meshes[-1] if meshes else "")
    labels_file = ev["inputs"]["labels"]
    with h5py.File(mesh_file) as f:
        V, C = f["vertices"][()], f["cells"][()]
    with h5py.File(labels_file) as f:
        reason = f["cells/reason"][()] if "cells/reason" in f else np.zeros(len(C), np.uint8)
        label = f["cells/label"][()]
    ids = np.asarray(lab["wrong_cells"], dtype=np.int64)
    cen = V[C[ids]].mean(axis=1) if len(ids) else np.zeros((0, 3))
    whole = np.isin(ids, np.asarray(lab.get("wrong_whole_cells", []), dtype=np.int64))
    gt = ply_vertices(ev["inputs"]["gt"])
    gt = gt[np.random.default_rng(0).choice(len(gt), min(len(gt), 40000), replace=False)]
    print(f"{labels_file}: {lab['interior']['wrong']} of {lab['interior']['cells']} interior cells outside the "
          f"object ({lab['interior']['wrong_whole']} wholly), {lab['exterior']['wrong']} of "
          f"{lab['exterior']['cells']} exterior inside ({lab['exterior']['wrong_whole']} wholly); "
          f"cell {lab['cell_size'] * 1000:.3f} mm")
    for r in lab["by_reason"]:
        if r["wrong"]:
            print(f"  {r['name']:16s} {r['wrong']:8d} wrong of {r['cells']:9d} ({r['wrong_whole']} wholly, "
                  f"{r['wrong_deeper_than_2']} deeper than 2 cells, deepest {r['deepest']:.1f})")
    planes = [(0, 1, "x", "y"), (0, 2, "x", "z"), (1, 2, "y", "z")]
    colours = plt.get_cmap("tab10")
    for ax, (a, b, na, nb) in zip(axes, planes):
        ax.scatter(gt[:, a], gt[:, b], s=0.2, c="0.8", linewidths=0)
        for code in np.unique(reason[ids]) if len(ids) else []:
            sel = reason[ids] == code
            side = "interior" if label[ids[sel][0]] > 0 else "exterior"
            ax.scatter(cen[sel, a], cen[sel, b], s=np.where(whole[sel], 14, 5), color=colours(int(code) % 10),
                       label=f"{REASONS[code] if code < len(REASONS) else code} ({side}): {sel.sum()}")
        ax.set_xlabel(na)
        ax.set_ylabel(nb)
        ax.set_aspect("equal")
    if len(ids):
        axes[0].legend(loc="upper left", fontsize=8, markerscale=2)
    fig.suptitle(f"{os.path.basename(labels_file)}: {len(ids)} wrong cells"
                 f"{' (list truncated)' if lab.get('wrong_cells_truncated') else ''} over the ground truth")
    fig.tight_layout()
    fig.savefig(out, dpi=80)
    print(f"-> {out}")


if __name__ == "__main__":
    main()
