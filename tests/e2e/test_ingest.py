#!/usr/bin/env python3
"""End-to-end tests of `ingest` on the four Middlebury ring sets and on broken datasets.

usage: test_ingest.py BIN_DIR SOURCE_DIR
"""
import os
import shutil
import subprocess
import sys
import tempfile

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
import harness  # noqa: E402
import check_schema  # noqa: E402

BIN, SRC = sys.argv[1], sys.argv[2]
DATA = os.path.join(SRC, "..", "shared", "data", "middlebury")
SETS = ["dinoRing", "templeRing", "dinoSparseRing", "templeSparseRing"]


CHECKS = harness.Checks()
expect = CHECKS.expect


def run(args):
    return subprocess.run(args, capture_output=True, text=True)


def project(K, R, t, X):
    x = (K @ (R @ X.T + t[:, None]))
    return x[:2] / x[2], x[2]


def check_set(name, tmp):
    out = os.path.join(tmp, name + ".h5")
    sheet = os.path.join(tmp, name + "_contact.png")
    r = run([os.path.join(BIN, "ingest"), os.path.join(DATA, name), "-o", out, "--contact-sheet", sheet, "-q"])
    expect(r.returncode == 0, f"{name}: ingest failed: {r.stderr.strip()}")
    if r.returncode:
        return
    expect(os.path.getsize(sheet) > 10000, f"{name}: contact sheet missing or tiny")
    probs = check_schema.check(os.path.join(SRC, "schemas", "scene.md"), out)
    expect(not probs, f"{name}: schema problems {probs}")
    with h5py.File(out) as f:
        K, R, t = f["cameras/K"][()], f["cameras/R"][()], f["cameras/t"][()]
        masks, valid = f["silhouettes/mask"][()], f["silhouettes/valid"][()]
        lo, hi = f["box/min"][()], f["box/max"][()]
        expect(f.attrs["stage"] == "ingest", f"{name}: stage attribute")
    n = len(K)
    expect(valid.sum() >= n - 5, f"{name}: only {valid.sum()} of {n} views have a silhouette")
    centre = ((lo + hi) / 2)[None, :]
    H, W = masks.shape[1:]
    for v in range(n):
        if not valid[v]:
            continue
        (u, w), d = project(K[v], R[v], t[v], centre)
        u, w = int(round(u[0])), int(round(w[0]))
        inside = 0 <= u < W and 0 <= w < H and masks[v, w, u] > 0
        expect(inside, f"{name}: box centre projects outside the silhouette of view {v}")
        frac = (masks[v] > 0).mean()
        expect(0.01 < frac < 0.6, f"{name}: view {v} silhouette covers {frac:.3f} of the image")
    # visual hull in a grid over the box grown by 30 %: non-empty, and inside the box
    size = hi - lo
    glo, ghi = lo - 0.3 * size, hi + 0.3 * size
    res = 48
    axes = [np.linspace(glo[k], ghi[k], res) for k in range(3)]
    X = np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, 3)
    keep = np.ones(len(X), bool)
    for v in range(n):
        if not valid[v]:
            continue
        (u, w), d = project(K[v], R[v], t[v], X)
        ui, wi = np.round(u).astype(int), np.round(w).astype(int)
        inimg = (ui >= 0) & (ui < W) & (wi >= 0) & (wi < H) & (d > 0)
        m = np.ones(len(X), bool)
        m[inimg] = masks[v, wi[inimg], ui[inimg]] > 0
        keep &= m
    expect(keep.sum() > 100, f"{name}: visual hull is (nearly) empty: {keep.sum()} voxels")
    # Ring cameras cannot bound the hull along the ring's axis (the hull of a ring is a
    # double cone there), so the check is made in the slab of the box along that axis.
    centres = np.array([-R[v].T @ t[v] for v in range(n)])
    c0 = centres.mean(0)
    axis = np.linalg.svd(centres - c0)[2][2]
    corners = np.array([[a, b, c] for a in (lo[0], hi[0]) for b in (lo[1], hi[1]) for c in (lo[2], hi[2])])
    s_lo, s_hi = (corners @ axis).min(), (corners @ axis).max()
    in_slab = (X @ axis >= s_lo) & (X @ axis <= s_hi)
    step = (ghi - glo) / (res - 1)
    inbox = np.all((X >= lo - step) & (X <= hi + step), axis=1)
    outside = keep & in_slab & ~inbox
    inside = keep & inbox
    print(f"{name}: {valid.sum()}/{n} silhouettes, hull {keep.sum()} voxels, {inside.sum()} in the box, "
          f"{outside.sum()} outside it within the box's slab along the ring axis")
    expect(inside.sum() > 100, f"{name}: hull inside the box is (nearly) empty")
    expect(outside.sum() <= 0.02 * (keep & in_slab).sum(),
           f"{name}: {outside.sum()} of {(keep & in_slab).sum()} hull voxels in the slab lie outside the box")


def expect_error(args, what, output, expect_in_msg):
    r = run(args)
    msg = r.stderr.strip()
    expect(r.returncode != 0, f"{what}: exit code 0")
    lines = [l for l in msg.splitlines() if "error" in l]
    expect(len(lines) == 1, f"{what}: expected one error line, got {msg!r}")
    expect(expect_in_msg in msg, f"{what}: message {msg!r} lacks {expect_in_msg!r}")
    expect(not os.path.exists(output), f"{what}: output file exists after the error")
    leftovers = [p for p in os.listdir(os.path.dirname(output)) if ".tmp." in p]
    expect(not leftovers, f"{what}: temporary files left: {leftovers}")


def broken_datasets(tmp):
    base = os.path.join(tmp, "base")
    shutil.copytree(os.path.join(DATA, "dinoSparseRing"), base)
    out = os.path.join(tmp, "out", "scene.h5")
    os.makedirs(os.path.dirname(out))
    ingest = os.path.join(BIN, "ingest")
    # a missing image
    d = os.path.join(tmp, "missing")
    shutil.copytree(base, d)
    os.remove(os.path.join(d, "dinoSR0005.png"))
    expect_error([ingest, d, "-o", out], "missing image", out, "dinoSR0005.png: image file is missing")
    # an image of the wrong size
    d = os.path.join(tmp, "wrongsize")
    shutil.copytree(base, d)
    import matplotlib.image as mpimg
    mpimg.imsave(os.path.join(d, "dinoSR0003.png"), np.zeros((100, 120, 3), np.uint8))
    expect_error([ingest, d, "-o", out], "wrong image size", out, "dinoSR0003.png: image is 120x100")
    # an unreadable image
    d = os.path.join(tmp, "corrupt")
    shutil.copytree(base, d)
    open(os.path.join(d, "dinoSR0002.png"), "wb").write(b"not a png")
    expect_error([ingest, d, "-o", out], "corrupt image", out, "dinoSR0002.png: cannot decode image")
    # broken par files
    for i, (mutate, needle) in enumerate([
        (lambda L: L[:2] + [L[2].rsplit(" ", 1)[0] + "\n"] + L[3:], ":3: expected 22 fields"),
        (lambda L: ["17\n"] + L[1:], ":1: declares 17 views but lists 16"),
        (lambda L: L[:1] + [L[1].replace(" 0.", " x.", 1)] + L[2:], ":2: field"),
        (lambda L: L + [L[1]], "duplicate image name"),
    ]):
        d = os.path.join(tmp, f"par{i}")
        shutil.copytree(base, d)
        p = os.path.join(d, "dinoSR_par.txt")
        lines = open(p).readlines()
        open(p, "w").writelines(mutate(lines))
        expect_error([ingest, d, "-o", out], f"broken par {i}", out, needle)
    # a non-orthonormal rotation
    d = os.path.join(tmp, "rot")
    shutil.copytree(base, d)
    p = os.path.join(d, "dinoSR_par.txt")
    lines = open(p).readlines()
    f = lines[4].split()
    f[10] = str(float(f[10]) * 1.1)
    lines[4] = " ".join(f) + "\n"
    open(p, "w").writelines(lines)
    expect_error([ingest, d, "-o", out], "non-orthonormal R", out, ":5: R is not a rotation")
    # two par files
    d = os.path.join(tmp, "twopar")
    shutil.copytree(base, d)
    shutil.copy(os.path.join(d, "dinoSR_par.txt"), os.path.join(d, "other_par.txt"))
    expect_error([ingest, d, "-o", out], "two par files", out, "2 *_par.txt files")
    # a bad bbox.txt
    d = os.path.join(tmp, "bbox")
    shutil.copytree(base, d)
    open(os.path.join(d, "bbox.txt"), "w").write("0 0 0\n1 1\n")
    expect_error([ingest, d, "-o", out], "bad bbox.txt", out, "bbox.txt: expected two lines")
    # unknown parameter
    expect_error([ingest, base, "-o", out, "--set", "ingest.nope=1"], "unknown param", out, "unknown parameter")
    # no box stated and no README: the box comes from the visual hull and contains the stated one
    d = os.path.join(tmp, "nobox")
    shutil.copytree(base, d)
    os.remove(os.path.join(d, "README.txt"))
    r = run([ingest, d, "-o", out, "-q"])
    expect(r.returncode == 0, f"visual-hull box: {r.stderr}")
    if r.returncode == 0:
        with h5py.File(out) as f:
            lo, hi = f["box/min"][()], f["box/max"][()]
            src = f["box"].attrs["source"]
        tlo = np.array([-0.061897, -0.018874, -0.057845])
        thi = np.array([0.010897, 0.068227, 0.015495])
        print("visual hull box", lo, hi, "stated", tlo, thi)
        expect(src == "visual hull", "box source")
        size = thi - tlo
        expect(np.all(lo <= tlo + 0.1 * size) and np.all(hi >= thi - 0.1 * size), "hull box covers the stated box")
        expect(np.all(hi - lo <= 4 * size), "hull box is not absurdly larger")
        os.remove(out)


def main():
    tmp = tempfile.mkdtemp(prefix="tetmvs_ingest_")
    try:
        if os.path.isdir(DATA):
            for s in SETS:
                check_set(s, tmp)
            broken_datasets(tmp)
        else:
            print("SKIP: no Middlebury data at", DATA)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    CHECKS.finish()


if __name__ == "__main__":
    sys.exit(main())
