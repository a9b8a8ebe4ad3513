#!/usr/bin/env python3
"""End-to-end: the pipeline on a small synthetic scene, every output checked against its
schema, quality against the exact ground truth, and make's change tracking.

usage: test_pipeline.py BIN_DIR SOURCE_DIR
"""
import glob
import json
import os
import re
import sys

sys.path.insert(0, os.path.dirname(__file__))
import check_schema  # noqa: E402
import tiny_run  # noqa: E402

BIN, SRC = sys.argv[1], sys.argv[2]
failures, passed = [], 0


def expect(cond, msg):
    global passed
    if cond:
        passed += 1
    else:
        failures.append(msg)
        print("FAIL:", msg)


SCHEMA_OF = {
    "scene.h5": "scene.md",
    "mesh_*.h5": "mesh.md",
    "pc_*.h5": "photoconsist.md",
    "scores.h5": "scores.md",
    "labels.h5": "labels.md",
    "cut*.h5": "cut.md",
    "silfix.h5": "silfix.md",
    "deform.h5": "deform.md",
}

# stage commands as make prints them
STAGE_RE = re.compile(r"/bin/(ingest|bcc-init|photoconsist|refine|label|cut|silhouette-fix|deform|evaluate|synth) ")


def stages_run(output):
    return [m.group(1) for m in STAGE_RE.finditer(output)]


def main():
    have = {s for s in tiny_run.stages(SRC) if os.path.exists(os.path.join(BIN, s))}
    target = "all" if have >= tiny_run.stages(SRC) else ("mesh" if "photoconsist" not in have else "all")
    run = tiny_run.build(BIN, SRC, target)
    # 1. every HDF5 output matches its schema
    for pattern, doc in SCHEMA_OF.items():
        for f in sorted(glob.glob(os.path.join(run, pattern))):
            docp = os.path.join(SRC, "schemas", doc)
            expect(os.path.exists(docp), f"schema document {doc} exists for {os.path.basename(f)}")
            if os.path.exists(docp):
                probs = check_schema.check(docp, f)
                expect(not probs, f"{os.path.basename(f)}: {probs}")
    expect(os.path.exists(os.path.join(run, "scene.h5")), "scene.h5 written")
    if "refine" in have and "photoconsist" in have:
        expect(os.path.exists(os.path.join(run, "mesh_3.h5")), "mesh_3.h5 written (LEVELS=3)")
    # 2. quality against the ground truth
    for surf in ("cut1", "cut2", "final"):
        ev = os.path.join(run, f"eval_{surf}.json")
        if not os.path.exists(ev):
            continue
        e = json.load(open(ev))
        print(surf, json.dumps({k: e[k] for k in e if k in ("accuracy", "completeness", "mesh")})[:600])
    # 3. change tracking: nothing changed -> nothing reruns
    r = tiny_run.make(BIN, SRC, ["-n", target])
    expect(stages_run(r.stdout) == [], f"a second make reruns {stages_run(r.stdout)}")
    if "cut" in have and "photoconsist" in have:
        r = tiny_run.make(BIN, SRC, ["-n", "all"], extra=["LAMBDA=0.123"])
        ran = set(stages_run(r.stdout))
        expect("cut" in ran, "LAMBDA reruns cut")
        expect(not ran & {"ingest", "bcc-init", "photoconsist", "refine", "label", "synth"},
               f"LAMBDA reruns only cut and later stages, ran {sorted(ran)}")
    if "photoconsist" in have:
        r = tiny_run.make(BIN, SRC, ["-n", "all"], extra=["T=0.55"])
        out = r.stdout
        ran = stages_run(out)
        expect("photoconsist" in ran and "--level 0" in out, "T reruns photoconsist from level 0")
        expect(not set(ran) & {"ingest", "bcc-init", "synth"}, f"T does not rerun ingest/bcc-init, ran {ran}")
    r = tiny_run.make(BIN, SRC, ["-n", target], extra=["SIL_THRESHOLD=0.2"])
    expect("ingest" in stages_run(r.stdout), "an ingest parameter reruns ingest")
    print(f"{passed} passed, {len(failures)} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
