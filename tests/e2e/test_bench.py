#!/usr/bin/env python3
"""scripts/bench_pipeline.py --ab: two configurations run alternately on a tiny synthetic
scene (8 views of 160 x 120, one level); the comparison's JSON holds each run, the means and
B's change per stage, and the options it cannot combine with are refused. --levels auto
records the number of levels the pipeline chose.

usage: test_bench.py BIN_DIR SOURCE_DIR
"""
import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(__file__))
import harness  # noqa: E402

BIN, SRC = sys.argv[1], sys.argv[2]
CHECKS = harness.Checks()
expect = CHECKS.expect
BENCH = [sys.executable, os.path.join(SRC, "scripts", "bench_pipeline.py")]


def main():
    build = os.path.dirname(os.path.abspath(BIN))
    with tempfile.TemporaryDirectory(prefix="tetmvs_bench_") as tmp:
        out = os.path.join(tmp, "compare.json")
        scene = [f"BUILD_DIR={build}", f"SYNTH_DIR={tmp}/data", "SYNTH_CAMERAS=ring",
                 "SYNTH_FLAGS=--views 8 --size 160x120"]
        r = subprocess.run(BENCH + ["--data", "synth-torus", "--levels", "1", "--run-dir", f"{tmp}/run", "--out", out,
                                    "--ab", "", "DEFORM_ITERATIONS=2", "--repeat", "2"] + scene,
                           capture_output=True, text=True)
        expect(r.returncode == 0, f"bench_pipeline --ab exits 0 ({r.stderr.strip()[-500:]})")
        if r.returncode == 0:
            c = json.load(open(out))
            expect(c["schema"] == "tetmvs.bench_compare", "the comparison's schema")
            expect(c["A"] == "" and c["B"] == "DEFORM_ITERATIONS=2", "A and B as given")
            expect(len(c["runs"]["A"]) == 2 and len(c["runs"]["B"]) == 2, "two runs of each")
            expect(os.path.isfile(f"{tmp}/run-A/final.ply") and os.path.isfile(f"{tmp}/run-B/final.ply"),
                   "each configuration has its own run directory")
            rows = c["stages"]
            expect({"pipeline", "photoconsist", "cut", "deform"} <= set(rows), f"stage rows: {sorted(rows)}")
            d = rows["deform"]
            expect(len(d["A_cpu_s"]) == 2 and abs(d["A_cpu_s_mean"] - sum(d["A_cpu_s"]) / 2) < 1e-3,
                   "a stage's mean is the mean of its runs")
            expect(d["change_cpu_s"] is not None and
                   abs(d["change_cpu_s"] - (d["B_cpu_s_mean"] / d["A_cpu_s_mean"] - 1)) < 1e-3,
                   "B's change is B's mean over A's, minus one")
            expect("deform" in r.stdout and "change" in r.stdout, "the table is printed")
        # --levels auto: the pipeline chooses the levels (refine.target_pixels) and the JSON
        # holds the number it chose, its finest mesh's cells and the option as given
        auto = os.path.join(tmp, "auto.json")
        r = subprocess.run(BENCH + ["--data", "synth-torus", "--levels", "auto", "--run-dir", f"{tmp}/auto",
                                    "--out", auto] + scene, capture_output=True, text=True)
        expect(r.returncode == 0, f"bench_pipeline --levels auto exits 0 ({r.stderr.strip()[-500:]})")
        if r.returncode == 0:
            a = json.load(open(auto))
            chosen = open(f"{tmp}/auto/levels.mk").read().split(":=")[1].strip()
            expect(a["levels_option"] == "auto" and a["levels"] == int(chosen),
                   f"the levels pipeline.mk chose ({chosen}) are recorded: {a['levels']}, {a['levels_option']}")
            expect(os.path.isfile(f"{tmp}/auto/mesh_{a['levels']}.h5") and a["mesh"]["cells_final"] > 0,
                   "the finest mesh's cells are those of the chosen level")
        for bad in (["--levels", "0"], ["--levels", "13"], ["--levels", "many"]):
            r = subprocess.run(BENCH + bad, capture_output=True, text=True)
            expect(r.returncode == 2 and "--levels" in r.stderr, f"{' '.join(bad)} is refused ({r.stderr.strip()[-200:]})")
        for bad in (["--collect"], ["--keep"], ["--repeat", "0"]):
            r = subprocess.run(BENCH + ["--ab", "", "T=0.7"] + bad, capture_output=True, text=True)
            expect(r.returncode == 2 and ("--ab" in r.stderr or "--repeat" in r.stderr),
                   f"--ab with {' '.join(bad)} is refused naming the option ({r.stderr.strip()[-200:]})")
    CHECKS.finish()


if __name__ == "__main__":
    main()
