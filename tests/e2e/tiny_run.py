"""A small end-to-end run shared by the e2e tests: a synthetic scene rendered by the
project (ring cameras, small images) pushed through pipeline.mk as far as the stages go.
Built once per build directory (a file lock keeps parallel tests from racing)."""
import fcntl
import os
import subprocess

SCENE = "synth-torus"
MAKE_VARS = [
    "SYNTH_CAMERAS=ring",
    "SYNTH_FLAGS=--views 16 --size 320x240",
    "LEVELS=3",
    "QUIET=1",
    "MESH_CELLS=10",
]


def paths(bin_dir):
    build = os.path.dirname(os.path.abspath(bin_dir))
    base = os.path.join(build, "e2e")
    return {
        "build": build,
        "synth_dir": os.path.join(base, "data"),
        "run_dir": os.path.join(base, "runs", SCENE),
        "lock": os.path.join(base, ".lock"),
    }


def make(bin_dir, src_dir, targets, extra=(), run_dir=None, check=True, silent=True):
    p = paths(bin_dir)
    cmd = ["make"] + (["-s"] if silent else []) + ["-f", os.path.join(src_dir, "pipeline.mk"), f"DATA={SCENE}",
           f"BUILD_DIR={p['build']}", f"SYNTH_DIR={p['synth_dir']}",
           f"RUN_DIR={run_dir or p['run_dir']}"] + MAKE_VARS + list(extra) + list(targets)
    r = subprocess.run(cmd, capture_output=True, text=True)
    if check and r.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed:\n{r.stdout}\n{r.stderr}")
    return r


def build(bin_dir, src_dir, target="all"):
    """Runs the pipeline (once) and returns the run directory."""
    p = paths(bin_dir)
    os.makedirs(os.path.dirname(p["lock"]), exist_ok=True)
    with open(p["lock"], "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        make(bin_dir, src_dir, [target])
    return p["run_dir"]


def stages(src_dir):
    return set(os.listdir(os.path.join(src_dir, "stages")))
