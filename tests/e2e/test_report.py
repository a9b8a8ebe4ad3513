#!/usr/bin/env python3
"""End-to-end: `make report` on the small synthetic run gives a self-contained HTML page
whose numbers are the run's, and (when Debian's chromium is installed) a real browser
renders it to a non-blank screenshot. Also checks `make help`.

usage: test_report.py BIN_DIR SOURCE_DIR
"""
import base64
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import zlib

import h5py

sys.path.insert(0, os.path.dirname(__file__))
import harness  # noqa: E402
import tiny_run  # noqa: E402

BIN, SRC = sys.argv[1], sys.argv[2]
CHECKS = harness.Checks()
expect = CHECKS.expect


def png_size(data):
    """(width, height) from a PNG's IHDR."""
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        return None
    return int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")


def jpeg_size(data):
    """(width, height) from a JPEG's start-of-frame segment."""
    if data[:2] != b"\xff\xd8":
        return None
    pos = 2
    while pos + 9 < len(data) and data[pos] == 0xFF:
        marker, length = data[pos + 1], int.from_bytes(data[pos + 2:pos + 4], "big")
        if marker in (0xC0, 0xC1, 0xC2):
            return int.from_bytes(data[pos + 7:pos + 9], "big"), int.from_bytes(data[pos + 5:pos + 7], "big")
        pos += 2 + length
    return None


def image_size(src):
    data = base64.b64decode(src.split(",", 1)[1])
    return png_size(data) if src.startswith("data:image/png;") else jpeg_size(data)


def png_grey_spread(path):
    """Fraction of rows of an 8-bit RGB/RGBA PNG that are not one flat colour (a blank
    page gives 0). Decodes the PNG with zlib; filters are undone row by row."""
    with open(path, "rb") as f:
        data = f.read()
    w, h = png_size(data)
    pos, idat, ctype = 8, b"", None
    while pos < len(data):
        n = int.from_bytes(data[pos:pos + 4], "big")
        kind = data[pos + 4:pos + 8]
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            ctype = body[9]
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    bpp = {2: 3, 6: 4}[ctype]
    raw = zlib.decompress(idat)
    stride = w * bpp
    prev = bytearray(stride)
    varied = 0
    for y in range(h):
        ft = raw[y * (stride + 1)]
        row = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = row[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if ft == 1:
                row[i] = (row[i] + a) & 255
            elif ft == 2:
                row[i] = (row[i] + b) & 255
            elif ft == 3:
                row[i] = (row[i] + (a + b) // 2) & 255
            elif ft == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                row[i] = (row[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        if len(set(row[0::bpp])) > 1:
            varied += 1
        prev = row
    return varied / h


def main():
    run = tiny_run.build(BIN, SRC, "report")
    page = os.path.join(run, "report", "index.html")
    expect(os.path.exists(page), "report/index.html written")
    html = open(page, encoding="utf-8").read()

    # self-contained: every image inline and a real PNG, nothing fetched from elsewhere
    srcs = re.findall(r'<img[^>]*src="([^"]*)"', html)
    expect(len(srcs) >= 8, f"the page shows at least 8 pictures (has {len(srcs)})")
    bad = [s[:40] for s in srcs if not s.startswith(("data:image/png;base64,", "data:image/jpeg;base64,"))]
    expect(not bad, f"every picture is an inline PNG or JPEG (not: {bad})")
    sizes = [image_size(s) for s in srcs if s.startswith("data:")]
    expect(all(sz and sz[0] >= 64 and sz[1] >= 64 for sz in sizes), f"inline pictures decode as PNG/JPEG of size: {sizes}")
    # thumbnails a browser handles: one view at most 640 px wide, a sheet of views 1280
    expect(all(sz and sz[0] <= 1280 for sz in sizes), f"pictures at most 1280 px wide: {sizes}")
    expect(not re.search(r'(src|href)="(https?:|file:|/)', html), "no external references")

    # the sections a user looks for
    for h in ["Results", "Surfaces", "Input views and silhouettes", "Adaptive mesh per level",
              "Quasi-dense points", "Labels", "Silhouette fix", "Stages: time and memory", "Parameters"]:
        expect(f"<h2>{h}" in html, f"section '{h}' present")

    # the numbers are the run's: evaluate's accuracy and completeness for every surface
    for s in ["cut1", "cut2", "final"]:
        ev = os.path.join(run, f"eval_{s}.json")
        if not os.path.exists(ev):
            continue
        d = json.load(open(ev))
        acc = f"{d['accuracy']['value'] / d['pixel_size']:.3g} px; {d['accuracy']['value']:.3g}"
        comp = f"{d['completeness']['value'] * 100:.4g} %"
        row = re.search(rf"<tr><td>{s}\.ply</td>(.*?)</tr>", html)
        expect(row is not None, f"results row for {s}.ply")
        if row:
            expect(acc in row.group(1), f"{s}: accuracy {acc} (pixels; world units) shown in its row: {row.group(1)[:300]}")
            expect(comp in row.group(1), f"{s}: completeness {comp} shown in its row")
            if "labels" in d:  # the cut's hard labels against the ground truth
                li, le = d["labels"]["interior"], d["labels"]["exterior"]
                wrong = f"{li['wrong']} ({li['wrong_whole']}) / {le['wrong']} ({le['wrong_whole']})"
                expect(wrong in row.group(1), f"{s}: wrong labels {wrong} shown in its row")
    expect("wrong labels" in html, "the results table has a wrong-labels column")

    # the silhouette agreement of every surface in every view with a silhouette: a chart and
    # a table with a row per view, an IoU per surface in [0, 1]
    expect("<h2>Silhouette agreement per view" in html, "section 'Silhouette agreement per view' present")
    table = re.search(r"<summary>IoU per view</summary><table>(.*?)</table>", html, re.S)
    expect(table is not None, "the per-view IoU table")
    if table:
        surfaces = [s for s in ["cut1", "cut2", "final"] if os.path.exists(os.path.join(run, f"{s}.ply"))]
        header = re.findall(r"<th>([^<]*)</th>", table.group(1))
        expect(header[-len(surfaces):] == [f"{s}.ply" for s in surfaces], f"one IoU column per surface: {header}")
        rows = re.findall(r"<tr><td class=num>(\d+)</td><td>[^<]*</td><td>(yes|no)</td>((?:<td class=num>[^<]*</td>)+)</tr>",
                          table.group(1))
        with h5py.File(os.path.join(run, "scene.h5"), "r") as f:
            views = int(f["silhouettes/valid"][:].astype(bool).sum())
        expect(views >= 2 and len(rows) == views, f"{len(rows)} rows for {views} views with a silhouette")
        ious = [float(x) for _, _, cells in rows for x in re.findall(r"<td class=num>([^<]*)</td>", cells)]
        expect(len(ious) == len(rows) * len(surfaces) and all(0 <= x <= 1 for x in ious),
               f"an IoU in [0, 1] per view and surface ({len(ious)} values)")
    stages_log = [json.loads(line)["stage"] for line in open(os.path.join(run, "stages.jsonl"))]
    for st in set(stages_log) - {"report"}:
        expect(re.search(rf"<tr><td>{re.escape(st)}( → [^<]*)?</td><td class=num>[0-9.e+-]+</td>", html) is not None,
               f"stage {st} in the time/memory table with its wall time")
    expect("cut.lambda" in html and "photo.T" in html, "parameters listed")

    # a benchmark's bench.json (scripts/bench_pipeline.py) adds its tables, with the crossing
    # faces' recall and precision per level on a synthetic scene
    bench = {"git": "abc1234", "machine": {"cpus": 2}, "levels": 2,
             "targets": {"pipeline_wall_s": {"measured": 40.5, "target": 90.0, "met": True}},
             "mesh": {"cells_final": 1000, "cells_uniform_same_finest": 4000, "fraction_of_uniform": 0.25},
             "stages": [], "quality": {"crossing_faces": [
                 {"level": 1, "gt_crossed": 17024, "found": 17020, "recall": 0.99977, "crossing": 49587,
                  "crossing_near": 48469, "precision": 0.97751, "active": 30000, "active_far": 2500,
                  "active_far_air": 2000},
                 {"level": 0, "gt_crossed": 4280, "found": 4280, "recall": 1.0, "crossing": 8060,
                  "crossing_near": 8060, "precision": 1.0}]}}
    with open(os.path.join(run, "bench.json"), "w") as f:
        json.dump(bench, f)
    bench_page = os.path.join(run, "report", "bench.html")
    r = subprocess.run([os.path.join(BIN, "report"), run, "--out", bench_page, "--quiet"], capture_output=True, text=True)
    expect(r.returncode == 0, f"report with bench.json exits 0: {r.stderr[-300:]}")
    bhtml = open(bench_page, encoding="utf-8").read() if os.path.exists(bench_page) else ""
    expect("<h2>Benchmark" in bhtml, "the benchmark section is shown")
    expect(re.search(r"<tr><td>1</td><td class=num>17024</td><td class=num>17020 \(0\.9998\)</td>"
                     r"<td class=num>49587</td><td class=num>48469 \(0\.9775\)</td><td class=num>30000</td>"
                     r"<td class=num>2500 \(2000\)</td></tr>", bhtml) is not None,
           "the crossing faces' row of level 1: crossed, found (recall), found in all, near (precision), "
           "active cells, away from the surface (in free space)")
    expect(re.search(r"<tr><td>0</td><td class=num>4280</td>.*?<td>-</td><td>-</td></tr>", bhtml) is not None,
           "a row of an older benchmark without the active cells' counts shows dashes")
    os.remove(os.path.join(run, "bench.json"))

    # a real browser
    chromium = shutil.which("chromium")
    if not chromium:
        print("SKIP browser check: chromium is not installed (scripts/setup.sh installs it when it can)")
    else:
        with tempfile.TemporaryDirectory() as tmp:
            shot = os.path.join(tmp, "shot.png")
            r = subprocess.run([chromium, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
                                f"--user-data-dir={tmp}/profile", "--window-size=1200,2400",
                                f"--screenshot={shot}", "file://" + page],
                               capture_output=True, text=True, timeout=180)
            expect(r.returncode == 0 and os.path.exists(shot), f"chromium screenshot: rc {r.returncode} {r.stderr[-300:]}")
            if os.path.exists(shot):
                spread = png_grey_spread(shot)
                expect(spread > 0.5, f"the rendered page is not blank: {spread:.2f} of rows vary")
                keep = os.path.join(run, "report", "screenshot.png")
                shutil.copy(shot, keep)
                print("screenshot:", keep)

    # make help lists every parameter with a readable default
    r = subprocess.run(["make", "-s", "-f", os.path.join(SRC, "pipeline.mk"), "help",
                        f"BUILD_DIR={tiny_run.paths(BIN)['build']}"], capture_output=True, text=True)
    expect(r.returncode == 0, f"make help exits 0: {r.stderr[-300:]}")
    table = json.load(open(os.path.join(SRC, "params", "defaults.json")))
    g = lambda key: f"{table[key]['value']:g}"  # noqa: E731 (make help prints %g)
    for var, default in [("LAMBDA", g("cut.lambda")), ("SIGMA", g("cut.sigma")), ("T", g("photo.T")), ("LEVELS", None)]:
        if default is None:
            expect(f"{var}=" in r.stdout, f"make help shows {var}")
        else:
            expect(re.search(rf"^\s+{var}\s+{re.escape(default)}\s", r.stdout, re.M) is not None,
                   f"make help lists {var} with default {default}")
    CHECKS.finish()


if __name__ == "__main__":
    main()
