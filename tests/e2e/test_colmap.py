#!/usr/bin/env python3
"""COLMAP workspaces end to end.

1. `synth --colmap` writes the tiny scene (16 views 320x240, as tests/e2e/tiny_run.py) in both
   layouts; `ingest` gives the same cameras from the Middlebury folder, the COLMAP text model,
   the binary model and the model folder itself (projection matrices equal to 1e-9
   relative), the same images and silhouettes, and every points3D lands on its recorded
   observations (< 1e-6 px). Without silhouettes the box comes from the sparse points.
2. When Debian's `colmap` is installed: feature_extractor, exhaustive_matcher and
   point_triangulator with the known poses on the rendered images (CPU SIFT); the model
   ingests with the same cameras and a box from its points close to the object's; the
   pipeline runs on it end to end (LEVELS=2, through cut2, with the rendered silhouettes);
   without colmap (skipped with a message) the same run uses the synthetic export. Then
   label, cut and silhouette-fix run on that run's intermediates with the silhouettes
   removed: label works from the box, the votes and silhouettes estimated from Q (every view gets one,
   some cells are exterior by them), silhouette-fix passes the labels through.
3. TETMVS_COLMAP_QUALITY=1 (opt-in, about half an hour on 2 cores): the scene reconstructed in
   both layouts, with and without silhouettes; the COLMAP runs in the Middlebury layout's box
   (BOX=) agree with it within 5 % on accuracy and completeness (cut2 and final); the runs in
   the COLMAP layout's own box and the no-silhouette vs silhouette gaps are printed, not
   asserted (docs/colmap.md).

usage: test_colmap.py BIN_DIR SOURCE_DIR
"""
import json
import os
import shutil
import sqlite3
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
SYNTH_ARGS = ["--object", "torus", "--cameras", "ring", "--views", "16", "--size", "320x240"]


def run(args, **kw):
    return subprocess.run([str(a) for a in args], capture_output=True, text=True, **kw)


def ok(r, what):
    expect(r.returncode == 0, f"{what} failed: {r.stderr.strip()[-600:]}")
    return r.returncode == 0


def read_scene(f):
    with h5py.File(f) as h:
        return {k: h[k][()] for k in ["cameras/names", "cameras/K", "cameras/R", "cameras/t", "images/rgb",
                                      "silhouettes/mask", "silhouettes/valid", "box/min", "box/max"]} | \
            {"source": h["box"].attrs["source"]}


def P(s):
    return np.einsum("nij,njk->nik", s["cameras/K"], np.concatenate([s["cameras/R"], s["cameras/t"][:, :, None]], 2))


def read_text_model(d):
    """images: id -> (name, [(x, y, pid)]); points: id -> xyz"""
    images, points = {}, {}
    lines = [l for l in open(os.path.join(d, "images.txt")).read().split("\n")]
    i = 0
    while i < len(lines):
        l = lines[i].strip()
        if not l or l.startswith("#"):
            i += 1
            continue
        f = l.split()
        obs = lines[i + 1].split()
        images[int(f[0])] = (f[9], [(float(obs[k]), float(obs[k + 1]), int(obs[k + 2])) for k in range(0, len(obs), 3)])
        i += 2
    for l in open(os.path.join(d, "points3D.txt")):
        if l.strip() and not l.startswith("#"):
            f = l.split()
            points[int(f[0])] = np.array([float(v) for v in f[1:4]])
    return images, points


def projections_land(scene, model_dir, what):
    images, points = read_text_model(model_dir)
    names = [n.decode() if isinstance(n, bytes) else n for n in scene["cameras/names"]]
    worst, n = 0.0, 0
    for iid, (name, obs) in images.items():
        v = names.index(name)
        K, R, t = scene["cameras/K"][v], scene["cameras/R"][v], scene["cameras/t"][v]
        for x, y, pid in obs:
            if pid < 0:
                continue
            q = K @ (R @ points[pid] + t)
            worst = max(worst, abs(q[0] / q[2] + 0.5 - x), abs(q[1] / q[2] + 0.5 - y))
            n += 1
    expect(n > 1000, f"{what}: only {n} observations")
    expect(worst < 1e-6, f"{what}: points3D land {worst:.3g} px from their observations")
    return n, worst


def gt_vertices(ply):
    data = open(ply, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().split("\n")
    nv = int(next(l for l in header if l.startswith("element vertex")).split()[2])
    props = []
    for l in header[header.index(next(l for l in header if l.startswith("element vertex"))) + 1:]:
        if not l.startswith("property"):
            break
        props.append(l.split()[1])
    assert all(p == "float" for p in props), props
    return np.frombuffer(data, np.float32, nv * len(props), end).reshape(nv, len(props))[:, :3].astype(float)


def same_cameras(a, b, what):
    na = [n.decode() if isinstance(n, bytes) else n for n in a["cameras/names"]]
    nb = [n.decode() if isinstance(n, bytes) else n for n in b["cameras/names"]]
    expect(na == nb, f"{what}: names differ {na} / {nb}")
    if na != nb:
        return float("nan")
    Pa, Pb = P(a), P(b)
    rel = max(np.linalg.norm(Pa[i] - Pb[i]) / np.linalg.norm(Pa[i]) for i in range(len(Pa)))
    expect(rel < 1e-9, f"{what}: projection matrices differ by {rel:.3g} (relative)")
    return rel


def quaternion(R):
    """(w, x, y, z) of a rotation matrix, from its largest component (any angle)."""
    tr = np.trace(R)
    c = np.argmax([tr, R[0, 0], R[1, 1], R[2, 2]])
    if c == 0:
        w = np.sqrt(1 + tr) / 2
        q = [w, (R[2, 1] - R[1, 2]) / (4 * w), (R[0, 2] - R[2, 0]) / (4 * w), (R[1, 0] - R[0, 1]) / (4 * w)]
    else:
        i = c - 1
        j, k = (i + 1) % 3, (i + 2) % 3
        r = np.sqrt(1 + R[i, i] - R[j, j] - R[k, k]) / 2
        v = [0.0, 0.0, 0.0]
        v[i] = r
        v[j] = (R[j, i] + R[i, j]) / (4 * r)
        v[k] = (R[k, i] + R[i, k]) / (4 * r)
        q = [(R[k, j] - R[j, k]) / (4 * r)] + v
    q = np.array(q) / np.linalg.norm(q)
    return q if q[0] >= 0 else -q


def colmap_route(tmp, mb, gt):
    """Debian's colmap on the rendered images with the known poses -> a workspace."""
    env = dict(os.environ, QT_QPA_PLATFORM="offscreen")
    ws = os.path.join(tmp, "colmap_ws")
    os.makedirs(os.path.join(ws, "known"))
    shutil.copytree(os.path.join(mb, "images_only"), os.path.join(ws, "images"))
    scene = read_scene(os.path.join(tmp, "mb.h5"))
    K = scene["cameras/K"][0]
    db = os.path.join(ws, "db.db")
    cam = f"{K[0, 0]!r},{K[1, 1]!r},{K[0, 2] + 0.5!r},{K[1, 2] + 0.5!r}"
    t0 = time.time()
    steps = [
        ["colmap", "feature_extractor", "--database_path", db, "--image_path", os.path.join(ws, "images"),
         "--ImageReader.single_camera", "1", "--ImageReader.camera_model", "PINHOLE",
         "--ImageReader.camera_params", cam, "--SiftExtraction.use_gpu", "0", "--SiftExtraction.num_threads", "2"],
        ["colmap", "exhaustive_matcher", "--database_path", db, "--SiftMatching.use_gpu", "0",
         "--SiftMatching.num_threads", "2"],
    ]
    for s in steps:
        r = run(s, env=env)
        if not ok(r, " ".join(s[:2])):
            return None
    # the known poses, with the database's image and camera ids
    con = sqlite3.connect(db)
    rows = con.execute("select image_id, name, camera_id from images").fetchall()
    cams = con.execute("select camera_id, width, height from cameras").fetchall()
    con.close()
    expect(len(rows) == 16 and len(cams) == 1, f"colmap database: {len(rows)} images, {len(cams)} cameras")
    names = [n.decode() for n in scene["cameras/names"]]
    with open(os.path.join(ws, "known", "cameras.txt"), "w") as f:
        f.write(f"{cams[0][0]} PINHOLE {cams[0][1]} {cams[0][2]} {cam.replace(',', ' ')}\n")
    with open(os.path.join(ws, "known", "images.txt"), "w") as f:
        for iid, name, cid in rows:
            v = names.index(name)
            R, t = scene["cameras/R"][v], scene["cameras/t"][v]
            q = quaternion(R)
            f.write(f"{iid} {' '.join(repr(float(x)) for x in q)} {' '.join(repr(float(x)) for x in t)} {cid} {name}\n\n")
    open(os.path.join(ws, "known", "points3D.txt"), "w").close()
    os.makedirs(os.path.join(ws, "sparse"))
    s = ["colmap", "point_triangulator", "--database_path", db, "--image_path", os.path.join(ws, "images"),
         "--input_path", os.path.join(ws, "known"), "--output_path", os.path.join(ws, "sparse"),
         "--Mapper.ba_refine_focal_length", "0", "--Mapper.ba_refine_principal_point", "0",
         "--Mapper.ba_refine_extra_params", "0", "--Mapper.num_threads", "2"]
    if not ok(run(s, env=env), "colmap point_triangulator"):
        return None
    print(f"colmap: features, matching and triangulation in {time.time() - t0:.1f} s")
    shutil.copy(gt, os.path.join(ws, "gt.ply"))
    return ws


def pipeline(ws, run_dir, target, extra=()):
    t0 = time.time()
    r = tiny_run.make(BIN, SRC, [target], [f"DATA_DIR={ws}"] + list(extra), run_dir=run_dir, check=False)
    ok(r, f"pipeline on {ws} ({target})")
    return time.time() - t0


def evals(run_dir):
    out = {}
    for s in ["cut1", "cut2", "final"]:
        f = os.path.join(run_dir, f"eval_{s}.json")
        if os.path.exists(f):
            j = json.load(open(f))
            out[s] = j
    return out


def metric(j, key):
    """accuracy (distance within which 90 % of the surface lies) or completeness (fraction)."""
    return float(j[key]["value"])


def main():
    tmp = tempfile.mkdtemp(prefix="tetmvs_colmap_")
    t_start = time.time()
    try:
        mb, ws, wsb, wsn = (os.path.join(tmp, n) for n in ["mb", "ws", "ws_bin", "ws_nosil"])
        if not ok(run([os.path.join(BIN, "synth")] + SYNTH_ARGS + ["--out", mb, "--colmap", ws, "-q"]), "synth --colmap"):
            return
        ok(run([os.path.join(BIN, "synth")] + SYNTH_ARGS + ["--out", os.path.join(tmp, "mb2"), "--colmap", wsb,
                                                            "--colmap-binary", "--colmap-no-silhouettes", "-q"]),
           "synth --colmap-binary")
        expect(os.path.exists(os.path.join(wsb, "sparse", "images.bin")) and
               not os.path.exists(os.path.join(wsb, "silhouettes")), "binary export layout")
        shutil.copytree(ws, wsn, ignore=shutil.ignore_patterns("silhouettes"))
        out = {}
        for name, d in [("mb", mb), ("ws", ws), ("ws_bin", wsb), ("ws_model", os.path.join(ws, "sparse")),
                        ("ws_nosil", wsn)]:
            f = os.path.join(tmp, name + ".h5")
            if ok(run([os.path.join(BIN, "ingest"), d, "-o", f, "-q"]), f"ingest {name}"):
                out[name] = read_scene(f)
        if len(out) < 5:
            return
        a = out["mb"]
        for name in ["ws", "ws_bin", "ws_model", "ws_nosil"]:
            rel = same_cameras(a, out[name], f"{name} vs Middlebury")
            expect(np.array_equal(a["images/rgb"], out[name]["images/rgb"]), f"{name}: images differ")
            print(f"{name}: cameras equal to the Middlebury ones within {rel:.2g} (relative)")
        for name in ["ws", "ws_model"]:
            expect(np.array_equal(a["silhouettes/valid"], out[name]["silhouettes/valid"]) and
                   np.array_equal(a["silhouettes/mask"], out[name]["silhouettes/mask"]), f"{name}: silhouettes differ")
            expect(out[name]["source"] == "visual hull and sparse points", f"{name}: box from {out[name]['source']}")
        n, worst = projections_land(out["ws"], os.path.join(ws, "sparse"), "COLMAP cameras")
        projections_land(a, os.path.join(ws, "sparse"), "Middlebury cameras")
        print(f"{n} observations, worst {worst:.2g} px from the projection of their point")
        # no silhouettes: the box of the sparse points holds the object and is not much larger
        s = out["ws_nosil"]
        expect(s["silhouettes/valid"].sum() == 0, "ws_nosil: silhouettes")
        expect(s["source"] == "sparse points", f"ws_nosil: box from {s['source']}")
        V = gt_vertices(os.path.join(mb, "gt.ply"))
        glo, ghi = V.min(0), V.max(0)
        lo, hi = s["box/min"], s["box/max"]
        expect(np.all(lo <= glo) and np.all(hi >= ghi), f"points box {lo} {hi} does not hold the object {glo} {ghi}")
        grow = (hi - lo) / (ghi - glo)
        expect(np.all(grow < 1.35), f"points box larger than the object by {grow} per axis")
        print(f"box from the sparse points: {grow.round(3)} x the object's extent per axis")

        # 2. Debian's colmap, then the pipeline without silhouettes
        os.makedirs(os.path.join(mb, "images_only"))
        for nm in a["cameras/names"]:
            shutil.copy(os.path.join(mb, nm.decode()), os.path.join(mb, "images_only"))
        cws = None
        if shutil.which("colmap"):
            cws = colmap_route(tmp, mb, os.path.join(mb, "gt.ply"))
        else:
            print("SKIPPED: Debian's colmap is not installed (apt-get install colmap); the pipeline runs on the "
                  "synthetic export without silhouettes instead")
        if cws:
            f = os.path.join(tmp, "colmap.h5")
            if ok(run([os.path.join(BIN, "ingest"), cws, "-o", f, "-q"]), "ingest colmap's model"):
                c = read_scene(f)
                rel = same_cameras(a, c, "colmap's model vs the truth")
                print(f"colmap's model: cameras within {rel:.2g} of the truth, box from {c['source']}")
                lo, hi = c["box/min"], c["box/max"]
                inter = np.clip(np.minimum(hi, ghi) - np.maximum(lo, glo), 0, None).prod()
                iou = inter / ((hi - lo).prod() + (ghi - glo).prod() - inter)
                expect(iou > 0.5, f"colmap's box {lo} {hi} vs the object {glo} {ghi}: IoU {iou:.2f}")
                print(f"colmap's sparse-point box vs the object's: IoU {iou:.2f}")
        # the pipeline end to end on colmap's model (or, without colmap, on the synthetic export),
        # with the rendered silhouettes; LEVELS=2 keeps it to seconds
        target = cws or ws
        if cws:
            shutil.copytree(os.path.join(mb, "silhouettes"), os.path.join(cws, "silhouettes"))
        rd = os.path.join(tmp, "run")
        secs = pipeline(target, rd, "cut2", ["LEVELS=2"])
        for c in ["cut1", "cut2"]:  # (make's evaluate target would run deform too)
            if os.path.exists(os.path.join(rd, c + ".ply")):
                ok(run([os.path.join(BIN, "evaluate"), "--mesh", os.path.join(rd, c + ".ply"), "--gt",
                        os.path.join(target, "gt.ply"), "--cameras", os.path.join(rd, "scene.h5"), "--out",
                        os.path.join(rd, f"eval_{c}.json"), "-q"]), f"evaluate {c}")
        e = evals(rd)
        expect("cut2" in e, "no eval_cut2.json")
        if "cut2" in e:
            acc, comp = metric(e["cut2"], "accuracy"), metric(e["cut2"], "completeness")
            print(f"{'colmap' if cws else 'synthetic'} workspace, pipeline to cut2 (LEVELS=2) in {secs:.0f} s: "
                  f"accuracy {acc:.3g}, completeness {comp:.3f}")
            expect(comp > 0.8 and acc < 0.003, f"cut2 of the workspace: accuracy {acc}, completeness {comp}")
        if os.path.exists(os.path.join(rd, "cut1.h5")):
            no_silhouettes(rd)
        # 3. quality in both layouts (opt-in)
        if os.environ.get("TETMVS_COLMAP_QUALITY"):
            quality(tmp, mb, ws, wsn)
        else:
            print("SKIPPED: the layout quality comparison (set TETMVS_COLMAP_QUALITY=1)")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    print(f"test_colmap: {time.time() - t_start:.0f} s")
    CHECKS.finish()


def no_silhouettes(rd):
    """label, cut and silhouette-fix on the run's intermediates with the silhouettes removed."""
    scene = os.path.join(rd, "scene_nosil.h5")
    shutil.copy(os.path.join(rd, "scene.h5"), scene)
    with h5py.File(scene, "r+") as h:
        h["silhouettes/valid"][...] = 0
        h["silhouettes/mask"][...] = 0
    L = max(int(p[5:-3]) for p in os.listdir(rd) if p.startswith("mesh_") and p.endswith(".h5"))
    mesh, scores = os.path.join(rd, f"mesh_{L}.h5"), os.path.join(rd, "scores.h5")
    lab, c1, sf, c2 = (os.path.join(rd, n) for n in ["labels_ns.h5", "cut1_ns.h5", "silfix_ns.h5", "cut2_ns.h5"])
    b = lambda n: os.path.join(BIN, n)
    if not ok(run([b("label"), "--scene", scene, "--mesh", mesh, "--scores", scores, "--out", lab, "-q"]), "label without silhouettes"):
        return
    with h5py.File(lab) as h:
        expect(h.attrs["rule_outside_hull"] == 0, "label without silhouettes: cells outside a hull")
        expect(int((h["cells/label"][()] > 0).sum()) > 0, "label without silhouettes: no interior cell")
        expect(int((h["cells/label"][()] < 0).sum()) > int(h.attrs["rule_boundary"]), "label without silhouettes: no exterior cell from the votes")
        # every view gets a silhouette estimated from Q; it carves (reason 8) and drops false points
        expect(int(h.attrs["q_sil_views"]) == len(h5py.File(scene)["cameras/names"]), "label without silhouettes: views without a Q silhouette")
        expect(int(h.attrs["rule_outside_q_hull"]) > 0 and int((h["cells/reason"][()] == 8).sum()) == int(h.attrs["rule_outside_q_hull"]),
               "label without silhouettes: no exterior cell from the silhouettes of Q")
    if not ok(run([b("cut"), "--mesh", mesh, "--scores", scores, "--labels", lab, "--out", c1, "--ply", c1[:-3] + ".ply", "-q"]), "cut without silhouettes"):
        return
    if not ok(run([b("silhouette-fix"), "--scene", scene, "--mesh", mesh, "--scores", scores, "--labels", lab,
                   "--cut", c1, "--out", sf, "--png-dir", os.path.join(rd, "silfix_ns"), "-q"]), "silhouette-fix pass-through"):
        return
    with h5py.File(sf) as h, h5py.File(lab) as l:
        expect("note" in h.attrs and h["constraints/cell"].shape == (0,) and h["views/view"].shape == (0,),
               "silfix.h5 without silhouettes: not a pass-through")
        expect(np.array_equal(h["cells/label"][()], l["cells/label"][()]), "silhouette-fix changed the labels")
        expect(h.attrs["schema"] == "tetmvs.labels", "silfix.h5 schema")
    if ok(run([b("cut"), "--mesh", mesh, "--scores", scores, "--labels", sf, "--out", c2, "--ply", c2[:-3] + ".ply", "-q"]), "second cut without silhouettes"):
        with h5py.File(c1) as x, h5py.File(c2) as y:
            expect(np.array_equal(x["cells/inside"][()], y["cells/inside"][()]), "the second cut differs from the first")
    print("without silhouettes: label, cut, silhouette-fix (pass-through) and the second cut work")


def quality(tmp, mb, ws, wsn):
    parent = os.path.join(tmp, "mbsets")
    os.makedirs(parent)
    shutil.copytree(mb, os.path.join(parent, "torus-sil"), ignore=shutil.ignore_patterns("images_only"))
    shutil.copytree(mb, os.path.join(parent, "torus-nosil"), ignore=shutil.ignore_patterns("images_only", "silhouettes"))
    # The Middlebury layout takes synth's bbox.txt, a COLMAP workspace a box from the hull and
    # the sparse points: other boxes, other BCC lattices, other meshes. The asserted comparison
    # gives the COLMAP runs the same box (ingest.box), so it compares the ingest paths alone;
    # the runs with the COLMAP layout's own box are reported too (docs/colmap.md).
    lo, hi = (np.array([float(x) for x in l.split()]) for l in open(os.path.join(mb, "bbox.txt")).read().split("\n")[:2])
    box = "BOX=" + ",".join(f"{x:.17g}" for x in list(lo) + list(hi))
    runs = {
        "middlebury+sil": (["DATA=torus-sil", f"DATA_DIR={parent}"], None),
        "colmap+sil": ([box], ws),
        "colmap+sil (own box)": ([], ws),
        "middlebury-nosil": (["DATA=torus-nosil", f"DATA_DIR={parent}", "AUTO_SILHOUETTES=false"], None),
        "colmap-nosil": ([box], wsn),
        "colmap-nosil (own box)": ([], wsn),
    }
    res = {}
    for name, (extra, w) in runs.items():
        rd = os.path.join(tmp, "q_" + name.replace(" ", "_").replace("(", "").replace(")", ""))
        t0 = time.time()
        args = extra + ([f"DATA_DIR={w}"] if w else [])
        r = tiny_run.make(BIN, SRC, ["all"], args, run_dir=rd, check=False)
        if not ok(r, f"quality run {name}"):
            continue
        res[name] = evals(rd)
        print(f"{name}: {time.time() - t0:.0f} s; " + "; ".join(
            f"{s} acc {metric(j, 'accuracy'):.4g} comp {metric(j, 'completeness'):.4g}" for s, j in res[name].items()))
    for a, b in [("middlebury+sil", "colmap+sil (own box)"), ("middlebury-nosil", "colmap-nosil (own box)"),
                 ("middlebury+sil", "middlebury-nosil"), ("colmap+sil", "colmap-nosil")]:
        if a in res and b in res:
            print(f"{a} vs {b} (not asserted): " + "; ".join(
                f"{s} {k} {metric(res[a][s], k):.4g} vs {metric(res[b][s], k):.4g}"
                for s in ["cut1", "final"] if s in res[a] and s in res[b] for k in ["accuracy", "completeness"]))
    for a, b in [("middlebury+sil", "colmap+sil"), ("middlebury-nosil", "colmap-nosil")]:
        if a not in res or b not in res:
            continue
        # the surfaces the pipeline delivers (cut1, before silhouette-fix, is printed above);
        # with the same box the two ingest paths give the same scene, so the same results
        for s in ["cut2", "final"]:
            expect(s in res[a] and s in res[b], f"{s}: no evaluation in {a} or {b}")
            if s not in res[a] or s not in res[b]:
                continue
            for k in ["accuracy", "completeness"]:
                x, y = metric(res[a][s], k), metric(res[b][s], k)
                expect(abs(x - y) <= 0.05 * abs(x), f"{s} {k}: {a} {x:.4g} vs {b} {y:.4g} (more than 5 %)")


if __name__ == "__main__":
    sys.exit(main())
