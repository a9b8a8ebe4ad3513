#!/usr/bin/env python3
"""Hostile files, failing disks and nonsense scenes (hostile.py makes them), on a scene of
six 64 x 48 views (seconds; `.ci/run` also runs this file under the sanitizers):

- images whose headers declare absurd sizes (PNG, JPEG, BMP, TIFF, PNM), or lie about their
  contents, and masks likewise: ingest refuses with one line naming the file, before
  decoding; HDF5 datasets and PLY elements that declare more than they hold: refused
  naming the file and dataset, before allocating;
- nonsense geometry (a box of +-1e30 m, a box around a camera, a single view, cameras
  facing away, all-black images) refused with a reason; suspicious parts (one camera facing
  away, one black image, a missing mask, the same pose twice) accepted with a warning
  that reaches the run log and the report;
- a full disk (a file size limit) while ingest writes: one line, exit 1, nothing left;
- an output that is an input found while reading (an image of the dataset): refused before
  anything is renamed, the image untouched;
- --threads and OMP_NUM_THREADS out of range, command-line errors: one line;
- pipeline.mk (skipped with --quick): a run whose intermediates are damaged after they were
  made (truncated in place, a side file overwritten, a JSON cut short) is made whole by the
  next make; LEVELS, DATA and RUN_DIR are checked with a sentence; clean refuses a folder
  that is not a run.

usage: test_hostile.py BIN_DIR SOURCE_DIR [--quick]
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
import harness  # noqa: E402
import hostile  # noqa: E402

BIN, SRC = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
QUICK = "--quick" in sys.argv[3:]
CHECKS = harness.Checks()
expect = CHECKS.expect
# a known budget (the machine's may be set otherwise), no run log unless a case sets one
ENV = {k: v for k, v in os.environ.items() if k not in ("TETMVS_LOG", "OMP_NUM_THREADS")}
ENV["TETMVS_MEMORY_GB"] = "16"


def stage(name, *args, env=None, limit=None):
    argv = [os.path.join(BIN, name)] + [str(a) for a in args]
    if limit is not None:
        return hostile.run_with_file_limit(argv, limit, env=env or ENV)
    return subprocess.run(argv, capture_output=True, text=True, env=env or ENV)


def error_lines(r):
    return [l for l in r.stderr.splitlines() if "error" in l]


def no_debris(outputs):
    for o in outputs:
        if os.path.exists(o):
            return f"{o} exists"
        d = os.path.dirname(o) or "."
        left = [p for p in os.listdir(d) if ".tmp." in p] if os.path.isdir(d) else []
        if left:
            return f"temporaries left: {left}"
    return ""


def refused(r, what, words, outputs=()):
    errs = error_lines(r)
    ok = expect(r.returncode in (1, 2), f"{what}: exit status {r.returncode} (1 or 2: refused, no signal)")
    ok &= expect(len(errs) == 1, f"{what}: one error line expected, got {r.stderr.strip()[-600:]!r}")
    for w in words:
        ok &= expect(bool(errs) and w.lower() in errs[0].lower(), f"{what}: {errs[:1]} lacks {w!r}")
    debris = no_debris(outputs)
    ok &= expect(not debris, f"{what}: {debris}")
    if not ok:
        print("   stderr:", r.stderr.strip()[-600:])
    return ok


def succeeded(r, what):
    return expect(r.returncode == 0, f"{what}: failed ({r.returncode}): {r.stderr.strip()[-600:]}")


def dataset(tmp):
    ds = os.path.join(tmp, "ds")
    r = stage("synth", "--object", "torus", "--cameras", "ring", "--views", 6, "--size", "64x48", "--out", ds, "-q")
    succeeded(r, "synth of the small dataset")
    return ds


def image_cases(ds, tmp):
    names = [row[0] for row in hostile.read_par(hostile.par_file(ds))]
    victim = names[1]
    out = os.path.join(tmp, "scene.h5")
    for kind, folder in [("image", ""), ("mask", "silhouettes")]:
        for name, data, words in hostile.hostile_images(64, 48):
            if kind == "mask" and name in ("png_16bit",):  # (a 16-bit mask is fine)
                continue
            d = os.path.join(tmp, f"{kind}_{name}")
            shutil.copytree(ds, d)
            open(os.path.join(d, folder, victim), "wb").write(data)
            w = ["mask" if kind == "mask" and "all images" in words else x for x in words]
            if kind == "mask" and name == "png_other_size":
                w = ["mask is"]
            r = stage("ingest", d, "-o", out, "--contact-sheet", os.path.join(tmp, "sheet.png"), "-q")
            refused(r, f"ingest, {kind} {name}", [victim] + w, [out, os.path.join(tmp, "sheet.png")])
            shutil.rmtree(d)
    # evaluate takes the cameras' size from the first image beside a par file
    d = os.path.join(tmp, "eval_cameras")
    shutil.copytree(ds, d)
    open(os.path.join(d, names[0]), "wb").write(hostile.png(60000, 60000))
    gt, out = os.path.join(ds, "gt.ply"), os.path.join(tmp, "eval.json")
    r = stage("evaluate", "--mesh", gt, "--gt", gt, "--cameras", hostile.par_file(d), "--out", out, "-q")
    refused(r, "evaluate, cameras sized by a header of 60000 x 60000", ["60000 x 60000", "memory budget"], [out])
    shutil.rmtree(d)


def declared_size_cases(ds, tmp):
    """HDF5 datasets and PLY elements that declare far more than the file holds."""
    scene = os.path.join(tmp, "valid_scene.h5")
    succeeded(stage("ingest", ds, "-o", scene, "-q"), "ingest of the small dataset")
    out = os.path.join(tmp, "mesh_0.h5")
    succeeded(stage("bcc-init", "--scene", scene, "--out", out, "-q"), "bcc-init of the small scene")
    mesh0 = out
    big = os.path.join(tmp, "big_images.h5")
    shutil.copy(scene, big)
    with h5py.File(big, "r+") as f:
        n = f["cameras/size"].shape[0]
        f["cameras/size"][...] = np.full((n, 2), 60000, np.int32)
    hostile.h5_declaring(big, big + ".tmp", "/silhouettes/mask", (n, 60000, 60000), np.uint8)
    hostile.h5_declaring(big + ".tmp", big, "/images/rgb", (n, 60000, 60000, 3), np.uint8)
    os.remove(big + ".tmp")
    expect(os.path.getsize(big) < 10 << 20, "the hostile scene is small on disk")
    out = os.path.join(tmp, "mesh_big.h5")
    r = stage("bcc-init", "--scene", big, "--out", out, "-q")
    refused(r, "bcc-init, masks declaring 60000 x 60000", ["big_images.h5", "/silhouettes/mask", "memory budget"], [out])
    out = os.path.join(tmp, "pc_0.h5")
    r = stage("photoconsist", "--scene", big, "--mesh", mesh0, "--level", 0, "--out", out, "-q")
    refused(r, "photoconsist, images declaring 60000 x 60000", ["big_images.h5", "/images/rgb", "memory budget"], [out])
    names = os.path.join(tmp, "names.h5")
    shutil.copy(scene, names)
    with h5py.File(names, "r+") as f:
        del f["cameras/names"]
        f.create_dataset("cameras/names", shape=(10 ** 10,), dtype=h5py.string_dtype(), chunks=True)
    r = stage("bcc-init", "--scene", names, "--out", out, "-q")
    refused(r, "bcc-init, 1e10 camera names", ["names.h5", "/cameras/names", "memory budget"], [out])
    ply = os.path.join(tmp, "declares.ply")
    hostile.ply_declaring(ply, 10 ** 12, 10 ** 12)
    gt = os.path.join(ds, "gt.ply")
    out = os.path.join(tmp, "eval.json")
    r = stage("evaluate", "--mesh", ply, "--gt", gt, "--cameras", scene, "--out", out, "-q")
    refused(r, "evaluate, a PLY declaring 1e12 vertices", ["declares.ply", "1000000000000 vertex", "truncated"], [out])
    return scene, mesh0


def geometry_cases(ds, tmp, scene):
    out = os.path.join(tmp, "scene_g.h5")
    log = os.path.join(tmp, "stages.jsonl")
    warned_scene = None
    for name, d, verdict, words in hostile.nonsense_scenes(ds, tmp):
        env = dict(ENV, TETMVS_LOG=log)
        for f in (log, out):
            if os.path.exists(f):
                os.remove(f)
        r = stage("ingest", d, "-o", out, "-q", env=env)
        if verdict == "refuse":
            refused(r, f"ingest, {name}", words, [out])
            continue
        if not succeeded(r, f"ingest, {name} (accepted with a warning)"):
            continue
        warnings = [l for l in r.stderr.splitlines() if l.startswith("warning:")]
        expect(any(all(w.lower() in l.lower() for w in words) for l in warnings),
               f"ingest, {name}: no warning with {words}: {warnings}")
        logged = [json.loads(l) for l in open(log)] if os.path.exists(log) else []
        expect(logged and any(all(w.lower() in x.lower() for w in words) for x in logged[-1].get("warnings", [])),
               f"ingest, {name}: the run log lacks the warning: {logged[-1:]}")
        if name == "facing_away":
            warned_scene = (out + ".keep", log + ".keep", words)
            shutil.copy(out, warned_scene[0])
            shutil.copy(log, warned_scene[1])
        shutil.rmtree(d)
    # every stage refuses a scene.h5 with nonsense geometry (not only ingest)
    bad = os.path.join(tmp, "box_1e30.h5")
    shutil.copy(scene, bad)
    with h5py.File(bad, "r+") as f:
        f["box/min"][...] = [-1e30] * 3
        f["box/max"][...] = [1e30] * 3
    out0 = os.path.join(tmp, "mesh_bad.h5")
    refused(stage("bcc-init", "--scene", bad, "--out", out0, "-q"), "bcc-init, a scene.h5 with a box of 1e30",
            ["box_1e30.h5", "inside the box"], [out0])
    # the warning reaches the report
    if warned_scene and os.path.exists(os.path.join(BIN, "report")):
        run = os.path.join(tmp, "warned_run")
        os.makedirs(run)
        shutil.copy(warned_scene[0], os.path.join(run, "scene.h5"))
        shutil.copy(warned_scene[1], os.path.join(run, "stages.jsonl"))
        html = os.path.join(run, "report.html")
        if succeeded(stage("report", run, "--out", html, "-q"), "report of a run with a warning"):
            text = open(html).read()
            expect("Warnings" in text and "sees none of the box" in text, "the report does not show the warning")


def disk_and_path_cases(ds, tmp):
    out, sheet = os.path.join(tmp, "full.h5"), os.path.join(tmp, "full.png")
    for limit in (0, 20000):
        r = stage("ingest", ds, "-o", out, "--contact-sheet", sheet, "-q", limit=limit)
        refused(r, f"ingest, disk full after {limit} bytes", ["disk full"], [out, sheet])
    # an input found while reading (an image named by the par file) as the output
    victim = os.path.join(ds, hostile.read_par(hostile.par_file(ds))[2][0])
    before = open(victim, "rb").read()
    r = stage("ingest", ds, "-o", victim, "-q")
    refused(r, "ingest -o onto one of its images", [os.path.basename(victim), "is also an input"])
    expect(open(victim, "rb").read() == before, "ingest -o onto an image changed the image")
    par = hostile.par_file(ds)
    before = open(par, "rb").read()
    refused(stage("ingest", ds, "-o", par, "-q"), "ingest -o onto its par file", ["-o", "is also the input"])
    expect(open(par, "rb").read() == before, "ingest -o onto the par file changed it")


def cli_cases(ds, tmp):
    out = os.path.join(tmp, "cli.h5")
    refused(stage("ingest", ds, "-o", out, "--threads", 100000), "--threads 100000", ["--threads", "100000"], [out])
    refused(stage("ingest", ds, "-o", out, "--threads", -1), "--threads -1", ["--threads"], [out])
    refused(stage("ingest", ds, "-o", out, env=dict(ENV, OMP_NUM_THREADS="100000")), "OMP_NUM_THREADS=100000",
            ["OMP_NUM_THREADS", "100000"], [out])
    succeeded(stage("ingest", ds, "-o", out, "--threads", 2, "-q"), "--threads 2")
    os.remove(out)
    refused(stage("ingest", ds, "-o", out, "--bogus"), "an unknown option", ["--bogus"], [out])
    refused(stage("ingest", "-o", out), "a missing argument", ["dataset"], [out])
    refused(stage("ingest", ds, "-o", ""), "an empty output path", ["-o", "empty"])


# ---- pipeline.mk ----------------------------------------------------------------------------
# 8 ring views and the paper's 60 degree cone: no patch is seen by k = 5 cameras, so the run has
# no photo-consistent point (make_cases checks the warning)
MAKE_VARS = ["DATA=synth-torus", "SYNTH_CAMERAS=ring", "SYNTH_FLAGS=--views 8 --size 128x96", "LEVELS=2",
             "MESH_CELLS=8", "CONE_DEG=60", "QUIET=1"]


def make(tmp, *extra, run="run"):
    cmd = ["make", "-s", "-f", os.path.join(SRC, "pipeline.mk"), f"BUILD_DIR={os.path.dirname(BIN)}",
           f"SYNTH_DIR={os.path.join(tmp, 'data')}", f"RUN_DIR={os.path.join(tmp, run)}"] + MAKE_VARS + list(extra)
    return subprocess.run(cmd, capture_output=True, text=True, env=ENV)


def damage(path, how):
    t = os.path.getmtime(path)
    if how == "truncate":
        with open(path, "r+b") as f:
            f.truncate(os.path.getsize(path) // 3)
    else:
        open(path, "wb").write(b"{\"cut short\": ")
    os.utime(path, (t + 5, t + 5))  # newer than everything: make alone would take it as done


def make_cases(tmp):
    run = os.path.join(tmp, "run")
    r = make(tmp, "cut1", "evaluate")
    if not succeeded(r, "make of the small run"):
        return
    # the run has no photo-consistent point (8 views of 128 x 96, 60 degree cone): it says so
    log = [json.loads(l) for l in open(os.path.join(run, "stages.jsonl"))]
    expect(any("no photo-consistent point" in w for j in log for w in j.get("warnings", [])),
           "the run log has no warning about the missing points")
    for f, how, remade in [("pc_1.h5", "truncate", "pc_1.h5"), ("cut1.h5", "truncate", "cut1.ply"),
                           ("eval_cut1.json", "overwrite", "eval_cut1.json")]:
        damage(os.path.join(run, f), how)
        before = os.path.getmtime(os.path.join(run, remade))  # (the damaged file's: in the future)
        r = make(tmp, "cut1", "evaluate")
        if not succeeded(r, f"make after {f} was damaged ({how})"):
            continue
        expect(f"damaged, made again: {f}" in r.stdout + r.stderr, f"make does not say it remakes {f}")
        expect(os.path.getmtime(os.path.join(run, remade)) != before, f"{remade} was not made again after {f} was damaged")
        r = subprocess.run([os.path.join(BIN, "validate"), os.path.join(run, f), "-q"], capture_output=True, text=True,
                           env=ENV)
        expect(r.returncode == 0 and not r.stdout.strip(), f"{f} still damaged: {r.stdout}")
    again = make(tmp, "-n", "cut1", "evaluate")
    expect("/bin/" not in again.stdout, f"make still has work after the repairs: {again.stdout[-300:]}")
    # the variables
    for extra, words in [(["LEVELS=0"], ["LEVELS", "1 to 12"]), (["LEVELS=abc"], ["LEVELS='abc'", "1 to 12"]),
                         (["LEVELS=13"], ["LEVELS"]), (["LEVELS=2 3"], ["LEVELS"]),
                         (["DATA=no-such-set"], ["DATA=no-such-set", "no dataset folder"])]:
        r = make(tmp, *extra, "cut1", run="fresh")
        text = r.stdout + r.stderr
        expect(r.returncode != 0 and all(w in text for w in words) and "***" in text and len(text.splitlines()) == 1,
               f"make {extra}: one sentence with {words} expected: {text[-300:]!r}")
        expect(not os.path.exists(os.path.join(tmp, "fresh")), f"make {extra} made the run folder")
    r = subprocess.run(["make", "-s", "-f", os.path.join(SRC, "pipeline.mk"), "RUN_DIR=/", "help"], capture_output=True,
                       text=True)
    expect(r.returncode != 0 and "RUN_DIR" in r.stderr, f"RUN_DIR=/ accepted: {r.stderr[-200:]}")
    other = os.path.join(tmp, "not_a_run")
    os.makedirs(other)
    open(os.path.join(other, "keep.txt"), "w").write("mine")
    r = subprocess.run(["make", "-s", "-f", os.path.join(SRC, "pipeline.mk"), f"RUN_DIR={other}", "clean"],
                       capture_output=True, text=True)
    expect(r.returncode != 0 and os.path.exists(os.path.join(other, "keep.txt")),
           f"make clean removed a folder that is not a run: {r.stderr[-200:]}")


def main():
    t0 = time.time()
    tmp = tempfile.mkdtemp(prefix="tetmvs_hostile_")
    try:
        ds = dataset(tmp)
        image_cases(ds, tmp)
        scene, _ = declared_size_cases(ds, tmp)
        geometry_cases(ds, tmp, scene)
        disk_and_path_cases(ds, tmp)
        cli_cases(ds, tmp)
        t1 = time.time()
        if not QUICK:
            make_cases(tmp)
        print(f"stage cases {t1 - t0:.1f} s, make cases {time.time() - t1:.1f} s")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    CHECKS.finish()


if __name__ == "__main__":
    sys.exit(main())
