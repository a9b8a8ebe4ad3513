#!/usr/bin/env python3
"""Determinism: the same inputs give byte-identical outputs whatever the thread count.

Each stage of the small shared run (tiny_run.py) is rerun on that run's own inputs, with
the exact arguments the pipeline used (from stages.jsonl), but with a different --threads
than the shared run had (1 when it had more), writing into a scratch folder; then every
output file must be byte-identical (for HDF5 files a difference is reported dataset by
dataset: numpy array_equal and the same dtype, every attribute equal). Stage by stage on identical inputs
means the whole pipeline is deterministic.
When the shared run is older than a stage's program (a developer's stale run), that stage
is run twice here instead, with 1 and 2 threads. deform runs with fewer iterations, with 1
and 2 threads (its full run alone would take a minute).

usage: test_determinism.py BIN_DIR SOURCE_DIR
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
import tiny_run  # noqa: E402

BIN, SRC = sys.argv[1], sys.argv[2]
CHECKS = harness.Checks()
expect = CHECKS.expect

# (stage, the file whose record in stages.jsonl gives the arguments, every file it writes)
STEPS = [
    ("bcc-init", "mesh_0.h5", ["mesh_0.h5", "mesh_0_slice.png"]),
    ("photoconsist", "pc_0.h5", ["pc_0.h5"]),
    ("refine", "mesh_2.h5", ["mesh_2.h5", "mesh_2_slice.png"]),
    ("label", "labels.h5", ["labels.h5", "labels_slice.png"]),
    ("cut", "cut1.h5", ["cut1.h5", "cut1.ply"]),
    ("silhouette-fix", "silfix.h5", ["silfix.h5", "silfix"]),
    ("evaluate", "eval_cut1.json", ["eval_cut1.json", "eval_cut1.png"]),
    ("deform", "final.ply", ["final.ply", "deform.h5", "final_views.png"]),
]
TWICE = {"deform": ["--set", "deform.iterations=2"]}  # run at 1 and 2 threads, cheaper
# Datasets that differ by design, with the reason; anything else that differs fails.
# (deform.h5 no longer stores wall-clock seconds per iteration: timings live in
# stages.jsonl and the log, never in a result file.)
KNOWN = {}


def records(run):
    """--out file name -> the last stages.jsonl record that wrote it."""
    out = {}
    with open(os.path.join(run, "stages.jsonl")) as f:
        for line in f:
            r = json.loads(line)
            a = r.get("args", "").split()
            for i in range(len(a) - 1):
                if a[i] in ("--out", "-o") and a[i + 1].startswith(run + "/"):
                    out[os.path.relpath(a[i + 1], run)] = r
    return out


def h5_diff(a, b):
    diff = []
    with h5py.File(a, "r") as fa, h5py.File(b, "r") as fb:
        objs = {"/": (fa, fb)}
        names = []
        fa.visititems(lambda n, o: names.append(n))
        for n in names:
            if n not in fb:
                diff.append(f"{n} missing")
                continue
            x, y = fa[n], fb[n]
            objs[n] = (x, y)
            if isinstance(x, h5py.Dataset):
                u, v = x[()], y[()]
                if u.dtype != v.dtype or u.shape != v.shape or not np.array_equal(u, v):
                    where = ""
                    if u.shape == v.shape and u.dtype == v.dtype and u.dtype.kind in "iuf":
                        bad = np.flatnonzero(u.reshape(-1) != v.reshape(-1))
                        where = f" ({bad.size} of {u.size} values differ, first at {bad[:3].tolist()})"
                    diff.append(f"dataset {n}{where}")
        for n, (x, y) in objs.items():
            for k in set(x.attrs) | set(y.attrs):
                if k not in x.attrs or k not in y.attrs:
                    diff.append(f"attribute {n}:{k} missing")
                elif not np.array_equal(np.asarray(x.attrs[k]), np.asarray(y.attrs[k])):
                    diff.append(f"attribute {n}:{k}")
    return diff


def compare(a, b, name):
    """List of differences between output `name` at a and b (files or folders)."""
    if os.path.isdir(a):
        fa, fb = sorted(os.listdir(a)), sorted(os.listdir(b)) if os.path.isdir(b) else []
        if fa != fb:
            return [f"{name}: files {fa} vs {fb}"]
        return [d for f in fa for d in compare(os.path.join(a, f), os.path.join(b, f), f"{name}/{f}")]
    if not os.path.exists(b):
        return [f"{name} not written"]
    same_bytes = open(a, "rb").read() == open(b, "rb").read()
    if name.endswith(".h5") and not same_bytes:
        # the datasets and attributes that differ, or else the file's own bytes (HDF5 objects
        # are written without creation times, so equal contents give equal files)
        return [f"{name}: {d}" for d in h5_diff(a, b)] or [f"{name}: bytes differ, contents equal"]
    return [] if same_bytes else [f"{name}: bytes differ"]


def run_stage(stage, args, threads, extra=()):
    t = time.time()
    r = subprocess.run([os.path.join(BIN, stage)] + args + ["--threads", str(threads)] + list(extra),
                       capture_output=True, text=True)
    expect(r.returncode == 0, f"{stage} --threads {threads} fails: {r.stderr.strip()[-300:]}")
    return time.time() - t


def main():
    have = {s for s in tiny_run.stages(SRC) if os.path.exists(os.path.join(BIN, s))}
    t0 = time.time()
    ref = tiny_run.build(BIN, SRC, "all")
    t1 = time.time()
    rec = records(ref)
    scratch = tempfile.mkdtemp(prefix="determinism_", dir=os.path.dirname(ref))
    compared = 0
    try:
        for stage, key, outputs in STEPS:
            if stage not in have or key not in rec:
                print(f"  {stage}: not in the shared run, skipped")
                continue
            r = rec[key]
            binary = os.path.join(BIN, stage)
            stale = os.path.getmtime(os.path.join(ref, key)) < os.path.getmtime(binary)
            dirs = []
            for k in range(2 if (stale or stage in TWICE) else 1):
                d = os.path.join(scratch, f"{stage}_{k}")
                os.makedirs(d)
                dirs.append(d)
            # the recorded arguments with this stage's outputs moved into the scratch folders
            def args_for(d):
                out = []
                for a in r["args"].split():
                    rel = os.path.relpath(a, ref) if a.startswith(ref + "/") else None
                    out.append(os.path.join(d, rel) if rel in outputs else a)
                return out
            ref_threads = int(r.get("threads", 0))
            if len(dirs) == 1:
                other = 1 if ref_threads != 1 else 2
                secs = run_stage(stage, args_for(dirs[0]), other)
                pairs = [(os.path.join(ref, o), os.path.join(dirs[0], o), o) for o in outputs]
                what = f"threads {ref_threads} (shared run) vs {other}"
            else:
                extra = TWICE.get(stage, [])
                secs = run_stage(stage, args_for(dirs[0]), 1, extra) + run_stage(stage, args_for(dirs[1]), 2, extra)
                pairs = [(os.path.join(dirs[0], o), os.path.join(dirs[1], o), o) for o in outputs]
                what = "threads 1 vs 2" + (" " + " ".join(extra) if extra else "")
            diffs = []
            for a, b, o in pairs:
                if not os.path.exists(a):
                    continue  # an optional output the pipeline did not ask for
                diffs += compare(a, b, o)
                compared += 1
            known = [k for k in diffs if k.split(" (")[0] in KNOWN]
            diffs = [k for k in diffs if k not in known]
            for k in known:
                print(f"  {stage}: {k} differs, known: {KNOWN[k.split(' (')[0]]}")
            expect(not diffs, f"{stage} ({what}) is not deterministic: {diffs}")
            print(f"  {stage}: {what}, {len(outputs)} outputs, {secs:.1f} s{'' if not diffs else ': DIFFERENT'}")
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    expect(compared >= 4, f"only {compared} outputs compared")
    print(f"shared run {t1 - t0:.1f} s, determinism checks {time.time() - t1:.1f} s")
    CHECKS.finish()


if __name__ == "__main__":
    sys.exit(main())
