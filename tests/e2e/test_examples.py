#!/usr/bin/env python3
"""Every examples/*.py inspection script runs on the small end-to-end run and writes its PNG.

usage: test_examples.py BIN_DIR SOURCE_DIR
"""
import glob
import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(__file__))
import tiny_run  # noqa: E402

BIN, SRC = sys.argv[1], sys.argv[2]
run = tiny_run.build(BIN, SRC, "all")
failed = passed = 0
with tempfile.TemporaryDirectory() as tmp:
    # cell_hull_bound.py writes a labels file, not a picture: cut with it and measure the
    # silhouette agreement of the cell-resolution visual hull (the bound of #7's second surface)
    bound = os.path.join(SRC, "examples", "cell_hull_bound.py")
    out = os.path.join(tmp, "hull_labels.h5")
    r = subprocess.run(["/usr/bin/python3", bound, run, out], capture_output=True, text=True)
    ok = r.returncode == 0
    if ok:
        L = max(int(p[5:-3]) for p in os.listdir(run) if p.startswith("mesh_") and p.endswith(".h5"))
        ply, js = os.path.join(tmp, "hull.ply"), os.path.join(tmp, "agree.json")
        subprocess.run([os.path.join(BIN, "cut"), "--mesh", os.path.join(run, f"mesh_{L}.h5"), "--scores",
                        os.path.join(run, "scores.h5"), "--labels", out, "--out", os.path.join(tmp, "c.h5"),
                        "--ply", ply, "--quiet"], check=True, capture_output=True)
        subprocess.run([os.path.join(BIN, "silhouette-fix"), "--scene", os.path.join(run, "scene.h5"),
                        "--agreement", ply, os.path.join(run, "cut2.ply"), "--agreement-json", js, "--quiet"],
                       check=True, capture_output=True)
        a = json.load(open(js))
        hull, cut2 = a["hull.ply"]["mean_iou"], a["cut2.ply"]["mean_iou"]
        # the hull at cell resolution agrees with the silhouettes better than the second cut
        ok = hull > 0.95 and hull >= cut2 - 0.005
        print(f"cell hull IoU {hull:.4f}, second cut {cut2:.4f}")
    print(("ok  " if ok else "FAIL"), "cell_hull_bound.py", r.stdout.strip()[:200], r.stderr.strip()[-300:])
    passed += ok
    failed += not ok
    for script in sorted(glob.glob(os.path.join(SRC, "examples", "*.py"))):
        if script == bound:
            continue
        png = os.path.join(tmp, os.path.basename(script) + ".png")
        r = subprocess.run(["/usr/bin/python3", script, run, png], capture_output=True, text=True)
        ok = r.returncode == 0 and os.path.exists(png) and os.path.getsize(png) > 5000
        print(("ok  " if ok else "FAIL"), os.path.basename(script), r.stdout.strip().splitlines()[:3], r.stderr.strip()[-300:])
        passed += ok
        failed += not ok
print(f"{passed} passed, {failed} failed")
sys.exit(1 if failed else 0)
