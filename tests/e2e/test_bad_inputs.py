#!/usr/bin/env python3
"""The bad-input matrix: every stage, fed a missing, empty, truncated, foreign, or
corrupted input (wrong schema, dtype, shape, NaN) or a parameter out of range, must fail
with ONE error line that names the file (or parameter) and the problem, exit non-zero,
and leave no output file behind (not even a temporary one).

For every output of every stage in the matrix, also: a path under a file, a path that is
a folder (a file, for an output folder), a path that is one of the inputs (directly or
through a symbolic link; the input must stay untouched); and for each stage a disk that
fills up (a file size limit just below its largest output): the stage refuses or fails
with one line, exits 1 (no signal, no crash) and leaves none of its outputs, also those
it had written before the failing one.

usage: test_bad_inputs.py BIN_DIR SOURCE_DIR
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
import hostile  # noqa: E402
import tiny_run  # noqa: E402

BIN, SRC = sys.argv[1], sys.argv[2]
cases = 0


CHECKS = harness.Checks()
expect = CHECKS.expect


# ---- mutations of an input file; each returns (path, words expected in the message) ----
def m_missing(src, tmp):
    return os.path.join(tmp, "absent.h5"), ["absent.h5", ("does not exist", "missing")]


def m_empty(src, tmp):
    p = os.path.join(tmp, "empty" + os.path.splitext(src)[1])
    open(p, "wb").close()
    return p, ["empty"]


def m_truncated(src, tmp):
    p = os.path.join(tmp, "trunc" + os.path.splitext(src)[1])
    data = open(src, "rb").read()
    open(p, "wb").write(data[: len(data) // 3])
    return p, ["trunc"]


def m_text(src, tmp):
    p = os.path.join(tmp, "text" + os.path.splitext(src)[1])
    open(p, "w").write("this is not the file you are looking for\n")
    return p, ["text"]


def m_schema(other):
    def f(src, tmp):
        p = os.path.join(tmp, "foreign.h5")
        shutil.copy(other, p)
        return p, ["foreign.h5", "expected"]
    return f


def m_version(src, tmp):
    p = os.path.join(tmp, "version.h5")
    shutil.copy(src, p)
    with h5py.File(p, "r+") as f:
        f.attrs["schema_version"] = np.int64(99)
    return p, ["version.h5", "version 99"]


def m_dataset(name, how):
    def f(src, tmp):
        p = os.path.join(tmp, f"bad_{how}.h5")
        shutil.copy(src, p)
        with h5py.File(p, "r+") as h:
            d = h[name][()]
            del h[name]
            if how == "nan":
                d = d.astype(d.dtype)
                d.flat[len(d.flat) // 2] = np.nan
                h[name] = d
            elif how == "dtype":
                h[name] = d.astype(np.float32 if d.dtype.kind in "iu" else np.int32)
            elif how == "shape":
                h[name] = d.reshape(-1)[:-1] if d.ndim == 1 else d[:, :-1]
            elif how == "missing":
                pass
        return p, [f"bad_{how}.h5", name]
    return f


H5_BASIC = [m_missing, m_empty, m_truncated, m_text, m_version]


def run_case(stage, argv, outputs, words, what, file_limit=None):
    global cases
    cases += 1
    for o in outputs:
        if os.path.isdir(o):
            shutil.rmtree(o)
        elif os.path.exists(o):
            os.remove(o)
    if file_limit is None:
        r = subprocess.run([os.path.join(BIN, stage)] + argv, capture_output=True, text=True)
    else:
        r = hostile.run_with_file_limit([os.path.join(BIN, stage)] + argv, file_limit)
    expect(r.returncode in (1, 2), f"{stage} {what}: exit status {r.returncode} (1 or 2 expected: no signal, no crash)")
    msg = r.stderr.strip()
    errs = [l for l in msg.splitlines() if "error" in l]
    def has(w):
        alts = w if isinstance(w, tuple) else (w,)
        return bool(errs) and any(a.lower() in errs[0].lower() for a in alts)
    ok = r.returncode != 0 and len(errs) == 1 and all(has(w) for w in words)
    expect(r.returncode != 0, f"{stage} {what}: exit 0")
    expect(len(errs) == 1, f"{stage} {what}: expected one error line, got {msg!r}")
    for w in words:
        expect(has(w), f"{stage} {what}: {errs[:1]} lacks {w!r}")
    for o in outputs:
        expect(not os.path.exists(o), f"{stage} {what}: output {o} exists")
        d = os.path.dirname(o)
        left = [p for p in os.listdir(d) if ".tmp." in p] if os.path.isdir(d) else []
        expect(not left, f"{stage} {what}: temporary files left {left}")
    if not ok:
        print("   stderr:", msg[:300])


def output_cases(stage, argv, outputs, sizes, inputs, tmp, folders=()):
    """The outputs' paths and the disk, for one valid call (see the top of the file)."""
    d = tempfile.mkdtemp(dir=tmp)
    a_file = os.path.join(d, "a_file")
    open(a_file, "w").write("x")
    src = next((p for p in inputs if os.path.isfile(p)), None)
    for o in outputs:
        i = argv.index(o)
        opt = argv[i - 1]
        def with_out(path):
            return argv[:i] + [path] + argv[i + 1:]
        ext = os.path.splitext(o)[1]
        run_case(stage, with_out(os.path.join(a_file, "x" + ext)), outputs, [opt, "a_file", "not a folder"],
                 f"{opt} under a file")
        if o in folders:
            run_case(stage, with_out(a_file), outputs, [opt, "a_file", "not a folder"], f"{opt} is a file")
            continue
        run_case(stage, with_out(d), outputs, [opt, "is a folder"], f"{opt} is a folder")
        if src:
            # the input through a copy (and a link to the copy): the stage must refuse before any work
            copy = os.path.join(d, "in_copy" + os.path.splitext(src)[1])
            shutil.copy(src, copy)
            link = os.path.join(d, "link" + ext)
            os.symlink(copy, link)
            before = open(copy, "rb").read()
            j = argv.index(src)
            for target, how in [(copy, "the input"), (link, "a link to the input")]:
                bad = with_out(target)
                bad[j] = copy
                run_case(stage, bad, [p for p in outputs if p != o], [opt, "is also the input"], f"{opt} is {how}")
                expect(open(copy, "rb").read() == before, f"{stage} {opt} is {how}: the input changed")
            os.remove(link)
            os.remove(copy)
    # the disk fills up while the largest output is written: every output goes, also those
    # written before it
    if sizes:
        big = max(sizes, key=sizes.get)
        if sizes[big] > 1:
            run_case(stage, argv, outputs, [tuple(os.path.basename(p) for p in outputs), "disk full"],
                     f"disk full writing {os.path.basename(big)}", file_limit=sizes[big] - 1)


def matrix(stage, argv_of, slots, outputs, tmp, extra_cases=(), folders=()):
    """argv_of(inputs) -> argv; slots: {slot: (valid_path, [mutations])}; folders: the
    outputs that are folders (their files count as outputs too)."""
    valid = {k: v[0] for k, v in slots.items()}
    # the valid call must succeed (otherwise the matrix proves nothing)
    r = subprocess.run([os.path.join(BIN, stage)] + argv_of(valid) + ["-q"], capture_output=True, text=True)
    expect(r.returncode == 0, f"{stage}: the valid baseline fails: {r.stderr.strip()}")
    sizes = {o: os.path.getsize(o) for o in outputs if os.path.isfile(o)}
    for f in folders:
        for p in os.listdir(f) if os.path.isdir(f) else []:
            sizes[os.path.join(f, p)] = os.path.getsize(os.path.join(f, p))
    for o in outputs:
        if os.path.isdir(o):
            shutil.rmtree(o)
        elif os.path.exists(o):
            os.remove(o)
    output_cases(stage, argv_of(valid), outputs, sizes, list(valid.values()), tmp, folders)
    for slot, (path, muts) in slots.items():
        for mut in muts:
            d = tempfile.mkdtemp(dir=tmp)
            bad, words = mut(path, d)
            inputs = dict(valid)
            inputs[slot] = bad
            run_case(stage, argv_of(inputs), outputs, words, f"{slot}={os.path.basename(bad)} ({mut.__name__ if hasattr(mut, '__name__') else ''})")
    for argv_extra, words, what in extra_cases:
        run_case(stage, argv_of(valid) + argv_extra, outputs, words, what)


# ---- memory budget (common/budget.h): a budget too small for the problem must stop the
# stage before its big allocations, naming the estimate, the budget and what to change ----
def budget_cases(run, tmp, out_dir, have):
    scene, mesh0 = os.path.join(run, "scene.h5"), os.path.join(run, "mesh_0.h5")
    tiny = ["--set", "resource.memory_gb=0.001"]  # 1 MiB
    words = ["memory budget", "1.02 MiB", "resource.memory_gb"]
    # stages that read the scene first: a budget its images and masks fit in (a dataset
    # larger than the whole budget is refused as it is read, naming the dataset)
    small = ["--set", "resource.memory_gb=0.005"]  # 5 MiB
    small_words = ["memory budget", "5.12 MiB", "resource.memory_gb"]
    out = os.path.join(out_dir, "mesh_0.h5")
    run_case("bcc-init", ["--scene", scene, "--out", out] + small, [out], small_words + ["bcc-init", "mesh.cells"],
             "budget: 5 MiB")
    run_case("bcc-init", ["--scene", scene, "--out", out] + tiny, [out], words + ["scene.h5", "/silhouettes/mask"],
             "budget: 1 MiB, smaller than the scene's masks")
    act = os.path.join(tmp, "budget_active.h5")
    with h5py.File(mesh0) as f:
        nc = f["cells"].shape[0]
    with h5py.File(act, "w") as f:
        a = np.zeros(nc, np.uint8)
        a[: nc // 2] = 1
        f["cells/active"] = a
    out = os.path.join(out_dir, "mesh_1.h5")
    refine = ["--mesh", mesh0, "--active", act, "--out", out]
    run_case("refine", refine + tiny, [out], words + ["mesh_0.h5"], "budget: 1 MiB (reading)")
    # a budget the input fits in but not the refined mesh: the second estimate refuses
    run_case("refine", refine + ["--set", "resource.memory_gb=0.01"], [out],
             ["memory budget", "active cells", "LEVELS"], "budget: 10 MiB (refined mesh)")
    old = os.environ.get("TETMVS_MEMORY_GB")
    try:
        os.environ["TETMVS_MEMORY_GB"] = "0.001"
        run_case("refine", refine, [out], ["memory budget", "TETMVS_MEMORY_GB"], "budget from the environment")
        os.environ["TETMVS_MEMORY_GB"] = "plenty"
        run_case("refine", refine, [out], ["TETMVS_MEMORY_GB", "plenty"], "budget: environment not a number")
    finally:
        if old is None:
            os.environ.pop("TETMVS_MEMORY_GB", None)
        else:
            os.environ["TETMVS_MEMORY_GB"] = old
    run_case("refine", refine + ["--set", "resource.memory_gb=0"], [out], ["resource.memory_gb", "minimum"],
             "budget: parameter out of range")
    data = os.path.join(tiny_run.paths(BIN)["synth_dir"], tiny_run.SCENE)
    gt = os.path.join(data, "gt.ply")
    out = os.path.join(out_dir, "eval.json")
    run_case("evaluate", ["--mesh", gt, "--gt", gt, "--cameras", scene, "--out", out, "--set",
                          "eval.sample_spacing_px=0.01"], [out], ["memory budget", "eval.sample_spacing_px"],
             "budget: sample spacing far too fine")
    if {"photoconsist", "label", "cut"} <= have:
        full = tiny_run.build(BIN, SRC, "cut1")
        L = max(int(p[5:-3]) for p in os.listdir(full) if p.startswith("mesh_") and p.endswith(".h5"))
        meshL = os.path.join(full, f"mesh_{L}.h5")
        scores, labels = os.path.join(full, "scores.h5"), os.path.join(full, "labels.h5")
        out, ply = os.path.join(out_dir, "cut.h5"), os.path.join(out_dir, "cut.ply")
        run_case("cut", ["--mesh", meshL, "--scores", scores, "--labels", labels, "--out", out, "--ply", ply] + tiny,
                 [out, ply], words + ["cut", "edges"], "budget: 1 MiB")
        out = os.path.join(out_dir, "labels.h5")
        run_case("label", ["--scene", scene, "--mesh", meshL, "--scores", scores, "--out", out] + small,
                 [out], small_words + ["label", "cells"], "budget: 5 MiB")
        # evaluate --labels: needs its mesh, and a closed ground truth
        out = os.path.join(out_dir, "eval_labels.json")
        run_case("evaluate", ["--mesh", gt, "--gt", gt, "--cameras", scene, "--out", out, "--labels", labels],
                 [out], ["--labels", "--tetmesh"], "labels without their mesh")
        open_gt = os.path.join(out_dir, "open.ply")
        with open(open_gt, "w") as f:
            f.write("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                    "0 0 0\n0.01 0 0\n0 0.01 0\n3 0 1 2\n")
        run_case("evaluate", ["--mesh", gt, "--gt", open_gt, "--cameras", scene, "--out", out, "--labels", labels,
                              "--tetmesh", meshL], [out], ["open.ply", "closed"], "labels against an open ground truth")
        out = os.path.join(out_dir, "scores.h5")
        run_case("photoconsist", ["--scene", scene, "--mesh", meshL, "--scores", "--out", out] + small,
                 [out], small_words + ["photoconsist", "faces", "LEVELS"], "budget: 5 MiB")
        if "deform" in have and os.path.exists(os.path.join(full, "cut1.ply")):
            out, st = os.path.join(out_dir, "final.ply"), os.path.join(out_dir, "deform.h5")
            run_case("deform", ["--scene", scene, "--mesh", os.path.join(full, "cut1.ply"), "--out", out,
                                "--stats", st] + small, [out, st], small_words + ["deform", "faces"], "budget: 5 MiB")


# ---- COLMAP workspaces (tests/e2e/test_colmap.py has the working ones) ----
def colmap_mutation(name, edit, words):
    """Copies the workspace, applies edit(ws) and expects `words` in the one error line."""
    def f(src, tmp):
        ws = os.path.join(tmp, "ws_" + name)
        shutil.copytree(src, ws)
        edit(ws)
        return ws, words
    f.__name__ = "colmap_" + name
    return f


def _rewrite(path, fn):
    lines = open(path).read().split("\n")
    open(path, "w").write("\n".join(fn(lines)))


def _first_data(lines):
    return next(i for i, l in enumerate(lines) if l and not l.startswith("#"))


def _unknown_model(ws):
    _rewrite(os.path.join(ws, "sparse", "cameras.txt"),
             lambda ls: [l.replace(" PINHOLE ", " KANNALA_X ") for l in ls])


def _foreign_image(ws):
    _rewrite(os.path.join(ws, "sparse", "points3D.txt"), lambda ls: ls[:-1] + ["999999 0 0 0 1 2 3 0.5 77 0", ""])


def _malformed(ws):
    def fn(ls):
        i = _first_data(ls)
        f = ls[i].split()
        f[1] = "0.7x"
        ls[i] = " ".join(f)
        return ls
    _rewrite(os.path.join(ws, "sparse", "images.txt"), fn)


def _missing_image(ws):
    os.remove(os.path.join(ws, "images", "torus0003.png"))


def _truncated_bin(ws):
    sp = os.path.join(ws, "sparse")
    subprocess.run([os.path.join(BIN, "synth"), "--object", "torus", "--cameras", "ring", "--views", "4",
                    "--size", "64x48", "--out", os.path.join(ws, "mb"), "--colmap", os.path.join(ws, "b"),
                    "--colmap-binary", "-q"], check=True, capture_output=True)
    for f in ["cameras.bin", "images.bin", "points3D.bin"]:
        shutil.copy(os.path.join(ws, "b", "sparse", f), sp)
    data = open(os.path.join(sp, "points3D.bin"), "rb").read()
    open(os.path.join(sp, "points3D.bin"), "wb").write(data[: len(data) - 5])


def colmap_cases(out_dir, tmp):
    src = os.path.join(tmp, "colmap_src")
    r = subprocess.run([os.path.join(BIN, "synth"), "--object", "torus", "--cameras", "ring", "--views", "6",
                        "--size", "96x72", "--out", os.path.join(src, "mb"), "--colmap", os.path.join(src, "ws"), "-q"],
                       capture_output=True, text=True)
    expect(r.returncode == 0, f"synth --colmap failed: {r.stderr.strip()}")
    if r.returncode:
        return
    ws = os.path.join(src, "ws")
    out = os.path.join(out_dir, "scene_colmap.h5")
    # image lines start at line 5 of images.txt (four comment lines); torus0003 is the third image
    matrix("ingest", lambda i: [i["ws"], "-o", out],
           {"ws": (ws, [colmap_mutation("missing_image", _missing_image, ["torus0003.png", "images.txt:9", "missing"]),
                        colmap_mutation("unknown_model", _unknown_model, ["cameras.txt:4", "KANNALA_X", "unknown camera model"]),
                        colmap_mutation("foreign_image", _foreign_image, ["points3D.txt", "image 77"]),
                        colmap_mutation("malformed", _malformed, ["images.txt:5", "0.7x"]),
                        colmap_mutation("truncated_bin", _truncated_bin, ["points3D.bin", "truncated"])])},
           [out], tmp,
           [(["--set", "ingest.roi=1,2,3"], ["ingest.roi", "six numbers"], "roi malformed"),
            (["--set", "ingest.points_percentile=30"], ["ingest.points_percentile", "maximum"], "percentile above range")])


def main():
    have = {s for s in tiny_run.stages(SRC) if os.path.exists(os.path.join(BIN, s))}
    run = tiny_run.build(BIN, SRC, "mesh")
    tmp = tempfile.mkdtemp(prefix="tetmvs_bad_")
    out_dir = os.path.join(tmp, "out")
    os.makedirs(out_dir)
    scene, mesh0 = os.path.join(run, "scene.h5"), os.path.join(run, "mesh_0.h5")
    try:
        # bcc-init: scene.h5
        out, pic = os.path.join(out_dir, "mesh_0.h5"), os.path.join(out_dir, "mesh_0_slice.png")
        matrix("bcc-init", lambda i: ["--scene", i["scene"], "--out", out, "--slice-png", pic],
               {"scene": (scene, H5_BASIC + [m_schema(mesh0), m_dataset("/cameras/t", "nan"),
                                             m_dataset("/cameras/K", "shape"), m_dataset("/box/min", "missing"),
                                             m_dataset("/cameras/size", "dtype")])},
               [out, pic], tmp,
               [(["--set", "mesh.cells=0"], ["mesh.cells", "minimum"], "param below range"),
                (["--set", "mesh.nope=1"], ["unknown parameter"], "unknown param"),
                (["--set", "mesh.cells=abc"], ["mesh.cells"], "param not a number"),
                (["--threads", "100000"], ["--threads", "100000"], "threads out of range"),
                (["--no-such-option"], ["--no-such-option"], "unknown option")])
        # refine: mesh + active flags
        act = os.path.join(tmp, "active.h5")
        with h5py.File(mesh0) as f:
            nc = f["cells"].shape[0]
        with h5py.File(act, "w") as f:
            a = np.zeros(nc, np.uint8)
            a[: nc // 10] = 1
            f["cells/active"] = a
        out, pic = os.path.join(out_dir, "mesh_1.h5"), os.path.join(out_dir, "mesh_1_slice.png")
        matrix("refine", lambda i: ["--mesh", i["mesh"], "--active", i["active"], "--out", out, "--slice-png", pic],
               {"mesh": (mesh0, H5_BASIC + [m_schema(scene), m_dataset("/cells", "shape"),
                                            m_dataset("/vertices", "nan"), m_dataset("/cells", "dtype")]),
                "active": (act, [m_missing, m_truncated, m_dataset("/cells/active", "shape"),
                                 m_dataset("/cells/active", "dtype")])},
               [out, pic], tmp)
        # photoconsist, level 0
        out, pts = os.path.join(out_dir, "pc_0.h5"), os.path.join(out_dir, "points.ply")
        matrix("photoconsist", lambda i: ["--scene", i["scene"], "--mesh", i["mesh"], "--level", "0", "--out", out,
                                          "--points-ply", pts],
               {"scene": (scene, [m_missing, m_truncated, m_schema(mesh0)]),
                "mesh": (mesh0, [m_missing, m_text, m_schema(scene)])},
               [out, pts], tmp,
               [(["--set", "photo.T=2"], ["photo.T", "maximum"], "T above range")])
        # ingest: parameters out of range (the dataset matrix is in test_ingest.py)
        data = os.path.join(tiny_run.paths(BIN)["synth_dir"], tiny_run.SCENE)
        out, sheet = os.path.join(out_dir, "scene.h5"), os.path.join(out_dir, "contact.png")
        matrix("ingest", lambda i: [i["dir"], "-o", out, "--contact-sheet", sheet], {"dir": (data, [])}, [out, sheet], tmp,
               [(["--set", "ingest.sil_threshold=1.5"], ["ingest.sil_threshold", "maximum"], "threshold above range"),
                (["--set", "ingest.sil_dilate=-1"], ["ingest.sil_dilate", "minimum"], "dilate below range"),
                (["--params", os.path.join(tmp, "nope.json")], ["nope.json"], "missing params file")])
        # ingest: broken COLMAP models (a workspace exported by synth --colmap, then mutated)
        colmap_cases(out_dir, tmp)
        # evaluate: PLY inputs
        gt = os.path.join(data, "gt.ply")
        out, pic = os.path.join(out_dir, "eval.json"), os.path.join(out_dir, "eval.png")
        matrix("evaluate", lambda i: ["--mesh", i["mesh"], "--gt", i["gt"], "--cameras", scene, "--out", out,
                                      "--png", pic],
               {"mesh": (gt, [m_missing, m_empty, m_truncated, m_text]), "gt": (gt, [m_missing, m_text])},
               [out, pic], tmp)
        # synth: its dataset folder
        out = os.path.join(out_dir, "synth_ds")
        matrix("synth", lambda i: ["--object", "sphere", "--cameras", "ring", "--views", "3", "--size", "32x24",
                                   "--out", out],
               {}, [out], tmp, [(["--box", "1 2"], ["--box", "six numbers"], "box malformed")], folders=[out])
        # later stages join the matrix as they exist (cut, label: scores.h5 / labels.h5)
        if {"photoconsist", "label", "cut"} <= have:
            full = tiny_run.build(BIN, SRC, "cut1")
            L = max(int(p[5:-3]) for p in os.listdir(full) if p.startswith("mesh_") and p.endswith(".h5"))
            meshL = os.path.join(full, f"mesh_{L}.h5")
            scores, labels = os.path.join(full, "scores.h5"), os.path.join(full, "labels.h5")
            out, ply, pic = os.path.join(out_dir, "cut.h5"), os.path.join(out_dir, "cut.ply"), os.path.join(out_dir, "cut.png")
            matrix("cut", lambda i: ["--mesh", i["mesh"], "--scores", i["scores"], "--labels", i["labels"],
                                     "--out", out, "--ply", ply, "--scene", scene, "--png", pic],
                   {"mesh": (meshL, [m_missing, m_truncated, m_schema(scene)]),
                    "scores": (scores, H5_BASIC + [m_schema(labels), m_dataset("/faces/omega", "nan"),
                                                   m_dataset("/faces/omega", "shape")]),
                    "labels": (labels, H5_BASIC + [m_schema(scores), m_dataset("/cells/label", "dtype"),
                                                   m_dataset("/cells/label", "shape")])},
                   [out, ply, pic], tmp,
                   [(["--set", "cut.sigma=0"], ["cut.sigma", "minimum"], "sigma out of range"),
                    (["--set", "cut.lambda=-1"], ["cut.lambda", "minimum"], "lambda out of range")])
            # an option that needs another: refused before any work
            run_case("cut", ["--mesh", meshL, "--scores", scores, "--labels", labels, "--out", out, "--ply", ply,
                             "--png", pic], [out, ply, pic], ["--png", "--scene"], "--png without --scene")
            out, pic = os.path.join(out_dir, "labels.h5"), os.path.join(out_dir, "labels.png")
            matrix("label", lambda i: ["--scene", i["scene"], "--mesh", i["mesh"], "--scores", i["scores"], "--out", out,
                                       "--slice-png", pic],
                   {"scene": (scene, [m_missing, m_truncated, m_schema(scores)]),
                    "mesh": (meshL, [m_missing, m_schema(scene)]),
                    "scores": (scores, H5_BASIC + [m_dataset("/points/position", "nan"),
                                                   m_dataset("/points/cams", "dtype")])},
                   [out, pic], tmp,
                   [(["--set", "label.low_percentile=101"], ["label.low_percentile", "maximum"], "percentile out of range"),
                    (["--set", "label.low_percentile=80"], ["label.low_percentile", "label.high_percentile"],
                     "percentiles crossed")])
            if "silhouette-fix" in have:
                out, pics = os.path.join(out_dir, "silfix.h5"), os.path.join(out_dir, "silfix_pics")
                cut1 = os.path.join(full, "cut1.h5")
                matrix("silhouette-fix", lambda i: ["--scene", scene, "--mesh", meshL, "--scores", scores, "--labels",
                                                    labels, "--cut", i["cut"], "--out", out, "--png-dir", pics],
                       {"cut": (cut1, [m_missing, m_truncated, m_schema(labels)])},
                       [out, pics], tmp, [(["--surface", os.path.join(full, "cut1.ply")], ["--cut", "--surface"],
                                           "both --cut and --surface")], folders=[pics])
            if "deform" in have:
                out, st, pic = (os.path.join(out_dir, p) for p in ("final.ply", "deform.h5", "final.png"))
                matrix("deform", lambda i: ["--scene", scene, "--mesh", i["mesh"], "--out", out, "--stats", st,
                                            "--png", pic],
                       {"mesh": (os.path.join(full, "cut1.ply"), [m_missing, m_empty, m_text])},
                       [out, st, pic], tmp)
            if "report" in have:
                out = os.path.join(out_dir, "report.html")
                matrix("report", lambda i: [i["run"], "--out", out], {"run": (full, [])}, [out], tmp)
        budget_cases(run, tmp, out_dir, have)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    print(f"bad-input cases: {cases}")
    CHECKS.finish()


if __name__ == "__main__":
    sys.exit(main())
