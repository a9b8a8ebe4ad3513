#!/usr/bin/env python3
"""Interruption: a stage killed by SIGKILL or SIGTERM at several moments (while reading,
at the moment its output's temporary file appears, half-way through writing it, between
its HDF5 file and its PLY) never leaves an output that `make -f pipeline.mk` takes as
finished: after each kill the make target does not exist, or make reruns the stage. The
rerun then completes, leaves no temporary file behind (killed stages' debris is removed)
and gives the same data as an uninterrupted run.

Runs in a copy of the small shared run (tiny_run.py): refine (mesh_1 -> mesh_2) and
cut (cut1.h5 + cut1.ply), with make's -o so that nothing upstream is rebuilt.

usage: test_interrupt.py BIN_DIR SOURCE_DIR
"""
import glob
import os
import shutil
import signal
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


def stage_pid(stage, work, timeout=120.0):
    """pid of the running `stage` whose command line names the work folder."""
    t0 = time.time()
    while time.time() - t0 < timeout:
        for p in os.listdir("/proc"):
            if not p.isdigit():
                continue
            try:
                with open(f"/proc/{p}/cmdline", "rb") as f:
                    argv = f.read().split(b"\0")
            except OSError:
                continue
            if argv and os.path.basename(argv[0]).decode(errors="replace") == stage and \
                    any(work.encode() in a for a in argv[1:]):
                return int(p)
        time.sleep(0.002)
    return None


def wait_for(path, pid, timeout=120.0):
    """True once `path` exists (polled every ms); False when the process ended first."""
    t0 = time.time()
    while time.time() - t0 < timeout:
        if os.path.exists(path):
            return True
        if not os.path.exists(f"/proc/{pid}") or open(f"/proc/{pid}/stat").read().split()[2] == "Z":
            return os.path.exists(path)
        time.sleep(0.001)
    return False


class Run:
    def __init__(self, work, assume_old):
        self.work = work
        self.old = [a for f in assume_old for a in ("-o", os.path.join(work, f))]

    def make(self, target, dry=False):
        return tiny_run.make(BIN, SRC, (["-n"] if dry else []) + self.old + [os.path.join(self.work, target)],
                             run_dir=self.work, check=False)

    def start(self, target):
        p = tiny_run.paths(BIN)
        cmd = ["make", "-s", "-f", os.path.join(SRC, "pipeline.mk"), f"DATA={tiny_run.SCENE}",
               f"BUILD_DIR={p['build']}", f"SYNTH_DIR={p['synth_dir']}", f"RUN_DIR={self.work}"] + \
            tiny_run.MAKE_VARS + self.old + [os.path.join(self.work, target)]
        return subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def kill_trial(run, stage, target, sig, moment, watch=None, delay=0.0, outputs=(), must_hit=True):
    """Starts make for `target`, kills `stage` at `moment` ('after': delay seconds after it
    started; 'file': when the temporary of `watch` appears, plus delay; 'done': when `watch`
    itself appears), then checks. Returns True when the kill landed before the stage ended."""
    what = f"{stage} killed by {signal.Signals(sig).name} {moment}" + (f" {watch}" if watch else "") + \
        (f" +{delay:.2f}s" if delay else "")
    mk = run.start(target)
    pid = stage_pid(stage, run.work)
    if not expect(pid is not None, f"{what}: the stage did not start"):
        mk.wait()
        return
    if moment in ("file", "done"):
        hit = wait_for(os.path.join(run.work, f"{watch}.tmp.{pid}" if moment == "file" else watch), pid)
        expect(hit or not must_hit, f"{what}: {watch} never appeared before the stage ended (test timing)")
    if delay:
        time.sleep(delay)
    try:
        os.kill(pid, sig)
    except ProcessLookupError:
        pass
    mk.communicate(timeout=300)
    dry = run.make(target, dry=True)
    reruns = f"/bin/{stage} " in dry.stdout
    if mk.returncode == 0:
        # the stage ended before the kill: then everything it writes must be complete
        expect(not must_hit, f"{what}: make reported success")
        expect(not reruns, f"{what}: the stage finished, yet make -n reruns it")
        for o in outputs:
            expect(os.path.exists(os.path.join(run.work, o)), f"{what}: the stage finished without {o}")
        print(f"  {what}: the stage had finished; its outputs are complete")
        return False
    # the check: the make target does not exist, or make would rerun the stage
    expect(not os.path.exists(os.path.join(run.work, target)) or reruns,
           f"{what}: {target} exists and make takes it as finished")
    expect(reruns, f"{what}: make -n does not rerun {stage}: {dry.stdout[-300:]}")
    for o in outputs:
        expect(not os.path.exists(os.path.join(run.work, o)), f"{what}: {o} exists after the kill")
    print(f"  {what}: ok ({len(glob.glob(os.path.join(run.work, '*.tmp.*')))} temporary files left by the kill)")
    return True


def same_datasets(a, b):
    """Names of the datasets that differ (values or dtype) between two HDF5 files."""
    diff = []
    with h5py.File(a, "r") as fa, h5py.File(b, "r") as fb:
        names = []
        fa.visititems(lambda n, o: names.append(n) if isinstance(o, h5py.Dataset) else None)
        for n in names:
            if n not in fb:
                diff.append(n)
                continue
            x, y = fa[n][()], fb[n][()]
            if x.dtype != y.dtype or not np.array_equal(x, y):
                diff.append(n)
    return diff


def fresh(ref, stage):
    """The shared run's file was made by the current binary (else comparing says nothing)."""
    return os.path.exists(ref) and os.path.getmtime(ref) > os.path.getmtime(os.path.join(BIN, stage))


def main():
    have = {s for s in tiny_run.stages(SRC) if os.path.exists(os.path.join(BIN, s))}
    if not {"refine", "photoconsist", "label", "cut"} <= have:
        print("skipped: needs refine, photoconsist, label and cut")
        return 0
    t0 = time.time()
    ref = tiny_run.build(BIN, SRC, "cut1")
    t1 = time.time()
    work = tempfile.mkdtemp(prefix="interrupt_", dir=os.path.dirname(ref))
    try:
        # copies keep their time stamps; make's -o keeps the inputs from being remade
        for f in ["scene.h5", "mesh_1.h5", "pc_1.h5", "mesh_3.h5", "scores.h5", "labels.h5"]:
            shutil.copy2(os.path.join(ref, f), os.path.join(work, f))
        shutil.copytree(os.path.join(ref, ".params"), os.path.join(work, ".params"))

        # --- refine: mesh_1 -> mesh_2 (an HDF5 file and a slice PNG) ---
        r = Run(work, ["mesh_1.h5", "pc_1.h5"])
        kill_trial(r, "refine", "mesh_2.h5", signal.SIGKILL, "after", delay=0.05, outputs=["mesh_2.h5"])
        kill_trial(r, "refine", "mesh_2.h5", signal.SIGTERM, "file", watch="mesh_2.h5", outputs=["mesh_2.h5"])
        kill_trial(r, "refine", "mesh_2.h5", signal.SIGKILL, "file", watch="mesh_2.h5", delay=0.02,
                   outputs=["mesh_2.h5"])
        # (each refine removes the debris of the killed ones before it: one file is left)
        left = glob.glob(os.path.join(work, "mesh_2.h5.tmp.*"))
        expect(len(left) == 1, f"the killed stages left one temporary file (the case the rerun must clean): {left}")
        done = r.make("mesh_2.h5")
        expect(done.returncode == 0, f"refine rerun fails: {done.stderr[-400:]}")
        left = glob.glob(os.path.join(work, "*.tmp.*"))
        expect(not left, f"temporary files of killed stages remain after the rerun: {left}")
        again = r.make("mesh_2.h5", dry=True)
        expect("/bin/refine " not in again.stdout, "make still reruns refine after the rerun")
        if fresh(os.path.join(ref, "mesh_2.h5"), "refine"):
            d = same_datasets(os.path.join(ref, "mesh_2.h5"), os.path.join(work, "mesh_2.h5"))
            expect(not d, f"mesh_2.h5 after interruptions differs from the uninterrupted run: {d}")

        # --- cut: cut1.h5 then cut1.ply (the make target, written last) ---
        c = Run(work, ["mesh_3.h5", "scores.h5", "labels.h5"])
        # (cut1.h5 is small: its write may end between two polls, then the outputs are complete)
        kill_trial(c, "cut", "cut1.ply", signal.SIGKILL, "file", watch="cut1.h5", outputs=["cut1.ply", "cut1.h5"],
                   must_hit=False)
        # between cut1.h5 and cut1.ply: a window of milliseconds, hit or not, the rule holds
        kill_trial(c, "cut", "cut1.ply", signal.SIGTERM, "done", watch="cut1.h5", outputs=["cut1.ply"],
                   must_hit=False)
        expect(not os.path.exists(os.path.join(work, "cut1.ply")) or os.path.exists(os.path.join(work, "cut1.h5")),
               "cut1.ply exists without cut1.h5")
        done = c.make("cut1.ply")
        expect(done.returncode == 0, f"cut rerun fails: {done.stderr[-400:]}")
        expect(os.path.exists(os.path.join(work, "cut1.h5")), "cut1.h5 missing after the rerun")
        # make's target is written last: cut1.h5 was complete before cut1.ply was written
        expect(os.stat(os.path.join(work, "cut1.h5")).st_mtime_ns <= os.stat(os.path.join(work, "cut1.ply")).st_mtime_ns,
               "cut wrote cut1.ply (make's target) before cut1.h5 was complete")
        left = glob.glob(os.path.join(work, "*.tmp.*"))
        expect(not left, f"temporary files of killed stages remain after the rerun: {left}")
        again = c.make("cut1.ply", dry=True)
        expect("/bin/cut " not in again.stdout, "make still reruns cut after the rerun")
        if fresh(os.path.join(ref, "cut1.h5"), "cut"):
            d = same_datasets(os.path.join(ref, "cut1.h5"), os.path.join(work, "cut1.h5"))
            expect(not d, f"cut1.h5 after interruptions differs from the uninterrupted run: {d}")
            expect(open(os.path.join(ref, "cut1.ply"), "rb").read() == open(os.path.join(work, "cut1.ply"), "rb").read(),
                   "cut1.ply after interruptions differs from the uninterrupted run")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print(f"shared run {t1 - t0:.1f} s, interruption trials {time.time() - t1:.1f} s")
    CHECKS.finish()


if __name__ == "__main__":
    sys.exit(main())
