#!/usr/bin/env python3
"""Every examples/*.py inspection script runs on the small end-to-end run and writes its PNG.

usage: test_examples.py BIN_DIR SOURCE_DIR
"""
import glob
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
    for script in sorted(glob.glob(os.path.join(SRC, "examples", "*.py"))):
        png = os.path.join(tmp, os.path.basename(script) + ".png")
        r = subprocess.run(["/usr/bin/python3", script, run, png], capture_output=True, text=True)
        ok = r.returncode == 0 and os.path.exists(png) and os.path.getsize(png) > 5000
        print(("ok  " if ok else "FAIL"), os.path.basename(script), r.stdout.strip().splitlines()[:3], r.stderr.strip()[-300:])
        passed += ok
        failed += not ok
print(f"{passed} passed, {failed} failed")
sys.exit(1 if failed else 0)
