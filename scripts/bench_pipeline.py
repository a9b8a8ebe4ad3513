#!/usr/bin/python3
"""Benchmark of the whole pipeline: runs `make -f pipeline.mk` from a clean run directory
and writes JSON with, per stage and per refinement level, the wall time, CPU time, peak
memory and the work counts the stage reported (faces tested, lattice points, NCC scores,
cells, graph nodes and edges), the adaptive mesh against a uniform BCC mesh of the same
finest cell size, the speed targets (a 48-view 640 x 480 object in 90 s wall and 180 CPU-s,
photoconsist in 60 CPU-s, 2 GB) with how far each is missed, and on a synthetic scene the
accuracy and completeness of cut1, cut2 and final and, per level, the recall and precision of
the crossing faces against the ground truth (both measured after the timed run).

  scripts/bench_pipeline.py --data dinoRing --levels 4
  scripts/bench_pipeline.py --data dtuScan37 --levels auto DATA_DIR=../shared/data/dtu  # the levels refine.target_pixels needs
  scripts/bench_pipeline.py --data synth-torus --levels 3 --out bench/results/synth-torus.json
  scripts/bench_pipeline.py --data dinoRing --recut      # also time a re-cut with another LAMBDA
  scripts/bench_pipeline.py --data synth-torus SYNTH_DIR=/tmp/t08 "SYNTH_FLAGS=--texture 0.08"  # a variant scene
  scripts/bench_pipeline.py --data synth-cup --ab "BUILD_DIR=/tmp/old/build" "" --repeat 2  # before / after

--ab A B compares two configurations (each a quoted list of make variables: another build,
other parameters) in one session, alternating A, B, A, B, ... --repeat times, each run from
a clean run directory (<run-dir>-A, <run-dir>-B): the machines are shared and noisy, and a
comparison of two sessions measures the neighbours. It writes per stage each run's wall and
CPU seconds, their means and B's change against A (--out: the comparison's JSON).

The run directory is /tmp/tetmvs-bench/<data>-L<levels> unless --run-dir is given; its
bench.json is also written there, so `make report` shows it. Timing is not a test: this
script never fails on a missed target, it records it.
"""
import argparse
import json
import os
import platform
import re
import shlex
import shutil
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

TARGETS = {  # a 48-view 640 x 480 object at the default LEVELS on 2 cores
    "pipeline_wall_s": 90.0,
    "pipeline_cpu_s": 180.0,
    "photoconsist_cpu_s": 60.0,
    "recut_wall_s": 20.0,
    "peak_memory_mb": 2048.0,
}


def counts_of(stage, summary):
    """Work counts from a stage's summary line: every key=value token, plus the few
    counts stages print in prose."""
    c = {}
    for k, v in re.findall(r"([A-Za-z_]+)=([0-9.eE+-]+)", summary):
        try:
            c[k] = float(v) if any(ch in v for ch in ".eE") else int(v)
        except ValueError:
            pass
    m = re.search(r"cells (\d+) -> (\d+)", summary)
    if m:
        c["cells_in"], c["cells"] = int(m.group(1)), int(m.group(2))
    m = re.search(r"graph (\d+) nodes (\d+) edges ([0-9.]+) MB", summary)
    if m:
        c["graph_nodes"], c["graph_edges"] = int(m.group(1)), int(m.group(2))
        c["graph_mb"] = float(m.group(3))
        c["graph_bytes_per_edge"] = c["graph_mb"] * 1048576.0 / max(1, c["graph_edges"])
    m = re.search(r"(\d+) vertices, (\d+) faces", summary)
    if m:
        c["vertices"], c["faces"] = int(m.group(1)), int(m.group(2))
    m = re.search(r"(\d+) rays", summary)
    if m:
        c["rays"] = int(m.group(1))
    return c


def level_of(args):
    m = re.search(r"--level (\d+)", args)
    return int(m.group(1)) if m else None


def output_of(args):
    m = re.search(r"(?:--out|-o)\s+(\S+)", args)
    return os.path.basename(m.group(1)) if m else None


def mesh_cells(path):
    try:
        import h5py
        with h5py.File(path, "r") as f:
            return int(f["cells"].shape[0])
    except Exception:
        return None


def synth_gt(args):
    """gt.ply of a synthetic scene (pipeline.mk's SYNTH_DIR, default data/)."""
    synth_dir = next((v.split("=", 1)[1] for v in args.vars if v.startswith("SYNTH_DIR=")), os.path.join(ROOT, "data"))
    return os.path.join(synth_dir, args.data, "gt.ply")


def build_dir(make_vars):
    """pipeline.mk's BUILD_DIR among the make variables (the last one given), else build/."""
    given = [v.split("=", 1)[1] for v in make_vars if v.startswith("BUILD_DIR=")]
    return given[-1] if given else os.path.join(ROOT, "build")


def crossing_recall(run_dir, entries, gt, bin_dir):
    """Per level, photoconsist's level pass run again with --gt on the run's own mesh, cache
    and parameters (its logged command line) into run_dir/recall/: the share of the faces the
    true surface crosses that the pass found (recall), of the found faces within two cells of
    the surface (precision), of the crossed cells made active (cell_recall), the active cells
    away from the surface (active_far; active_far_air: of those, in free space), and the counts."""
    import h5py
    out_dir = os.path.join(run_dir, "recall")
    os.makedirs(out_dir, exist_ok=True)
    rows = []
    for e in entries:
        a = e.get("args", "")
        if e.get("stage") != "photoconsist" or level_of(a) is None:
            continue
        argv = shlex.split(a)
        out = os.path.join(out_dir, f"pc_{level_of(a)}.h5")
        argv[argv.index("--out") + 1] = out
        subprocess.run([os.path.join(bin_dir, "photoconsist")] + argv + ["--gt", gt, "--quiet"], check=True)
        with h5py.File(out, "r") as f:
            ev = dict(f["eval"].attrs)
        rows.append({"level": level_of(a)} | {k: (round(float(v), 5) if isinstance(v, float) else int(v))
                                               for k, v in ev.items() if k in (
                                                   "recall", "precision", "cell_recall", "gt_crossed", "found",
                                                   "crossing", "crossing_near", "points_within_cell",
                                                   "active", "active_far", "active_far_air")})
    shutil.rmtree(out_dir)
    return rows


def levels_arg(text):
    """--levels: a whole number from 1 to 12, or auto."""
    if text == "auto":
        return text
    if text.isdigit() and 1 <= int(text) <= 12:
        return int(text)
    raise argparse.ArgumentTypeError(f"'{text}': give a whole number from 1 to 12, or auto")


def levels_of(args, run_dir):
    """The number of levels the run used: --levels, or with auto the one pipeline.mk chose
    (its levels.mk in the run directory)."""
    if args.levels != "auto":
        return args.levels
    p = os.path.join(run_dir, "levels.mk")
    m = re.search(r"LEVELS_AUTO\s*:=\s*(\d+)", open(p).read()) if os.path.exists(p) else None
    if not m:
        sys.exit(f"bench_pipeline: {p}: no LEVELS_AUTO line; was the run made with LEVELS=auto?")
    return int(m.group(1))


def run_make(args, run_dir, extra, targets):
    cmd = ["make", "-f", os.path.join(ROOT, "pipeline.mk"), f"DATA={args.data}", f"RUN_DIR={run_dir}",
           f"LEVELS={args.levels}", "QUIET=1"] + extra + targets
    t0 = time.monotonic()
    r = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.monotonic() - t0
    if r.returncode != 0:
        sys.exit(f"bench_pipeline: {' '.join(cmd)} failed (exit {r.returncode}):\n{r.stderr[-2000:]}")
    return wall


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", default="synth-torus", help="DATA of pipeline.mk (default synth-torus)")
    ap.add_argument("--levels", type=levels_arg, default=3,
                    help="LEVELS: a number from 1 to 12, or auto (the pipeline's default: as many as "
                         "refine.target_pixels needs; a DTU scan needs 6); default 3")
    ap.add_argument("--run-dir", help="run directory (default /tmp/tetmvs-bench/<data>-L<levels>)")
    ap.add_argument("--out", help="JSON output (default: <run-dir>/bench.json only)")
    ap.add_argument("--keep", action="store_true", help="do not delete the run directory first")
    ap.add_argument("--recut", action="store_true", help="also time a re-cut with LAMBDA changed")
    ap.add_argument("--collect", action="store_true",
                    help="run nothing: collect the numbers of an existing run directory (pipeline wall = sum of stages)")
    ap.add_argument("--ab", nargs=2, metavar=("A", "B"),
                    help="compare two configurations, each a quoted list of make variables (\"\" for none)")
    ap.add_argument("--repeat", type=int, default=2, help="with --ab: runs of each configuration (default 2)")
    ap.add_argument("vars", nargs="*", help="extra make variables, e.g. T=0.8")
    args = ap.parse_args()
    if args.ab and (args.collect or args.recut or args.keep):
        ap.error("--ab makes its own clean runs: not with --collect, --recut or --keep")
    if args.repeat < 1:
        ap.error(f"--repeat {args.repeat}: give at least 1")
    if args.ab:
        return compare(args)
    run_dir = os.path.abspath(args.run_dir or f"/tmp/tetmvs-bench/{args.data}-L{args.levels}")
    wall = None
    if not args.collect:
        prepare(args, run_dir, args.vars, clean=not args.keep)
        wall = run_make(args, run_dir, args.vars, ["final"])
        if args.data.startswith("synth-"):  # quality, not timed
            run_make(args, run_dir, args.vars, ["evaluate"])
    result = summarize(args, run_dir, wall)
    write_json(os.path.join(run_dir, "bench.json"), result)
    if args.out:
        write_json(args.out, result)
    print_result(args, result)


def prepare(args, run_dir, extra, clean=True):
    """A clean run directory, the programs built (compile time is not counted) and a
    synthetic scene rendered (its rendering is not part of the pipeline)."""
    if clean and os.path.isdir(run_dir):
        shutil.rmtree(run_dir)
    os.makedirs(run_dir, exist_ok=True)
    subprocess.run(["make", "-s", "-f", os.path.join(ROOT, "pipeline.mk"), "programs", f"BUILD_DIR={build_dir(extra)}"],
                   check=True)
    if args.data.startswith("synth-"):
        synth_vars = [v for v in args.vars if v.startswith(("SYNTH_DIR=", "SYNTH_FLAGS=", "SYNTH_CAMERAS="))]
        if not os.path.exists(synth_gt(args)):
            subprocess.run(["make", "-s", "-f", os.path.join(ROOT, "pipeline.mk"), f"DATA={args.data}",
                            f"BUILD_DIR={build_dir(extra)}"] + synth_vars + [synth_gt(args)], check=True)


def compare(args):
    """--ab: A and B alternately, --repeat times each; per stage the runs' seconds, their means
    and B's change against A."""
    base = os.path.abspath(args.run_dir or f"/tmp/tetmvs-bench/{args.data}-L{args.levels}")
    conf = {"A": args.vars + shlex.split(args.ab[0]), "B": args.vars + shlex.split(args.ab[1])}
    runs = {"A": [], "B": []}
    for k in range(args.repeat):
        for name in ("A", "B"):
            run_dir = f"{base}-{name}"
            prepare(args, run_dir, conf[name])
            wall = run_make(args, run_dir, conf[name], ["final"])
            r = summarize(args, run_dir, wall, quality=False)
            runs[name].append({"pipeline_wall_s": r["pipeline_wall_s"], "pipeline_cpu_s": r["pipeline_cpu_s"],
                               "peak_memory_mb": r["peak_memory_mb"], "per_stage": r["per_stage"]})
            print(f"run {k + 1} {name}: {r['pipeline_wall_s']} s wall, {r['pipeline_cpu_s']} CPU-s", flush=True)
    mean = lambda xs: round(sum(xs) / len(xs), 3)
    table = {}
    for key in ["pipeline"] + list(runs["A"][0]["per_stage"]):
        row = {}
        for name in ("A", "B"):
            for t in ("wall_s", "cpu_s"):
                xs = [r[f"pipeline_{t}"] if key == "pipeline" else r["per_stage"].get(key, {}).get(t, 0.0)
                      for r in runs[name]]
                row[f"{name}_{t}"] = xs
                row[f"{name}_{t}_mean"] = mean(xs)
        for t in ("wall_s", "cpu_s"):
            a = row[f"A_{t}_mean"]
            row[f"change_{t}"] = round(row[f"B_{t}_mean"] / a - 1.0, 4) if a > 0 else None
        table[key] = row
    result = {"schema": "tetmvs.bench_compare", "schema_version": 1, "data": args.data, "levels": args.levels,
              "make_vars": args.vars, "A": args.ab[0], "B": args.ab[1], "repeat": args.repeat,
              "order": "A, B alternately", "machine": {"cpus": os.cpu_count(), "platform": platform.platform()},
              "git": subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True,
                                    text=True).stdout.strip(),
              "stages": table, "runs": runs}
    if args.out:
        write_json(args.out, result)
    print(f"{args.data} L{args.levels}: A = [{args.ab[0]}], B = [{args.ab[1]}], {args.repeat} runs each, alternating")
    print(f"  {'stage':16s} {'A wall':>8s} {'B wall':>8s} {'change':>7s} {'A cpu':>8s} {'B cpu':>8s} {'change':>7s}")
    for key, row in table.items():
        ch = lambda t: "-" if row[f"change_{t}"] is None else f"{100 * row[f'change_{t}']:+.1f}%"
        print(f"  {key:16s} {row['A_wall_s_mean']:8.1f} {row['B_wall_s_mean']:8.1f} {ch('wall_s'):>7s} "
              f"{row['A_cpu_s_mean']:8.1f} {row['B_cpu_s_mean']:8.1f} {ch('cpu_s'):>7s}")


def write_json(path, result):
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(path + ".tmp", "w") as f:
        f.write(json.dumps(result, indent=1))
    os.replace(path + ".tmp", path)


def summarize(args, run_dir, wall, quality=True):
    """The benchmark's JSON of a finished run directory (wall: the timed make, or None for
    --collect: the sum of the stages of the last run of each)."""
    entries = [json.loads(line) for line in open(os.path.join(run_dir, "stages.jsonl"))]
    entries = [e for e in entries if e.get("stage") not in ("synth", "report", "evaluate")]
    if wall is None:  # --collect: the last run of each stage/output
        last = {}
        for e in entries:
            last[(e["stage"], output_of(e.get("args", "")))] = e
        entries = list(last.values())
        wall = sum(e.get("seconds", 0.0) for e in entries)
    stages = []
    for e in entries:
        a = e.get("args", "")
        stages.append({
            "stage": e["stage"], "output": output_of(a),
            "level": {"photoconsist": level_of(a), "refine": counts_of("", e.get("summary", "")).get("level"),
                      "bcc-init": 0}.get(e["stage"]),
            "wall_s": round(e.get("seconds", 0.0), 3), "cpu_s": round(e.get("cpu_seconds", 0.0), 3),
            "peak_memory_mb": round(e.get("peak_memory_mb", 0.0), 1), "threads": e.get("threads"),
            # the stage's own estimate, checked against the budget before its big allocations
            "estimated_memory_mb": round(e["estimated_memory_mb"], 1) if "estimated_memory_mb" in e else None,
            "counts": counts_of(e["stage"], e.get("summary", "")), "summary": e.get("summary", ""),
        })
    per_stage = {}
    for s in stages:
        p = per_stage.setdefault(s["stage"], {"wall_s": 0.0, "cpu_s": 0.0, "peak_memory_mb": 0.0, "runs": 0})
        p["wall_s"] = round(p["wall_s"] + s["wall_s"], 3)
        p["cpu_s"] = round(p["cpu_s"] + s["cpu_s"], 3)
        p["peak_memory_mb"] = max(p["peak_memory_mb"], s["peak_memory_mb"])
        p["runs"] += 1
    c0 = mesh_cells(os.path.join(run_dir, "mesh_0.h5"))
    levels = levels_of(args, run_dir)
    cl = mesh_cells(os.path.join(run_dir, f"mesh_{levels}.h5"))
    result = {
        "schema": "tetmvs.bench_pipeline", "schema_version": 1,
        "data": args.data, "levels": levels, "levels_option": args.levels, "make_vars": args.vars, "run_dir": run_dir,
        "machine": {"cpus": os.cpu_count(), "platform": platform.platform()},
        "git": subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip(),
        "pipeline_wall_s": round(wall, 2),
        "pipeline_cpu_s": round(sum(s["cpu_s"] for s in stages), 2),
        "stages_wall_s": round(sum(s["wall_s"] for s in stages), 2),
        "peak_memory_mb": max(s["peak_memory_mb"] for s in stages),
        "per_stage": per_stage,
        # stages whose peak exceeded their memory estimate (an estimate too low lets a run
        # pass the budget check and then exhaust the machine)
        "memory_estimate_low": [f"{s['stage']} {s['output']}: peak {s['peak_memory_mb']} MB, estimate "
                                f"{s['estimated_memory_mb']} MB" for s in stages
                                if s["estimated_memory_mb"] and s["peak_memory_mb"] > s["estimated_memory_mb"]
                                and s["peak_memory_mb"] > 256],
        "stages": stages,
        "mesh": {"cells_level0": c0, "cells_final": cl,
                 "cells_uniform_same_finest": c0 * 8 ** levels if c0 else None,
                 "fraction_of_uniform": round(cl / (c0 * 8 ** levels), 5) if c0 and cl else None},
    }
    if args.recut and not args.collect:
        lam = "LAMBDA=1.5"
        t0 = time.monotonic()
        run_make(args, run_dir, args.vars + [lam], ["cut1"])
        result["recut"] = {"make_vars": [lam], "wall_s": round(time.monotonic() - t0, 2)}
    targets = {"pipeline_wall_s": result["pipeline_wall_s"], "pipeline_cpu_s": result["pipeline_cpu_s"],
               "photoconsist_cpu_s": per_stage.get("photoconsist", {}).get("cpu_s", 0.0),
               "peak_memory_mb": result["peak_memory_mb"]}
    if "recut" in result:
        targets["recut_wall_s"] = result["recut"]["wall_s"]
    result["targets"] = {k: {"target": TARGETS[k], "measured": v, "met": v <= TARGETS[k],
                             "missed_by": round(max(0.0, v / TARGETS[k] - 1.0), 3)} for k, v in targets.items()}
    for ev in ("cut1", "cut2", "final"):
        p = os.path.join(run_dir, f"eval_{ev}.json")
        if os.path.exists(p):
            d = json.load(open(p))
            q = {"accuracy_mm": round(d["accuracy"]["value"] * 1000, 4),
                 "completeness": round(d["completeness"]["value"], 5)}
            if d["accuracy"].get("value_seen") is not None:  # over the seen part (Middlebury's)
                q["accuracy_seen_mm"] = round(d["accuracy"]["value_seen"] * 1000, 4)
            if d.get("labels"):
                q["wrong_labels"] = {side: d["labels"][side]["wrong"] for side in ("interior", "exterior")}
            result.setdefault("quality", {})[ev] = q
    if quality and args.data.startswith("synth-") and os.path.exists(synth_gt(args)):
        result.setdefault("quality", {})["crossing_faces"] = crossing_recall(run_dir, entries, synth_gt(args),
                                                                        os.path.join(build_dir(args.vars), "bin"))
    return result


def print_result(args, result):
    per_stage = result["per_stage"]
    print(f"{args.data} L{result['levels']}: pipeline {result['pipeline_wall_s']} s wall, peak {result['peak_memory_mb']} MB")
    for k, s in per_stage.items():
        print(f"  {k:16s} {s['wall_s']:9.1f} s wall {s['cpu_s']:9.1f} s cpu {s['peak_memory_mb']:8.0f} MB  x{s['runs']}")
    for k, q in result.get("quality", {}).items():
        if k == "crossing_faces":
            for r in q:
                print(f"  level {r['level']} crossing faces: recall {r['recall']:.4f}, precision {r['precision']:.4f} "
                      f"({r['found']} of {r['gt_crossed']} crossed found, {r['crossing']} found in all); "
                      f"active cells {r['active']}, {r['active_far']} away from the surface ({r['active_far_air']} in free space)")
        else:
            print(f"  {k}: accuracy90 {q['accuracy_mm']} mm, completeness {100 * q['completeness']:.2f} %")
    for k, t in result["targets"].items():
        print(f"  target {k}: {t['measured']} vs {t['target']} -> {'met' if t['met'] else 'missed by %.0f %%' % (100 * t['missed_by'])}")


if __name__ == "__main__":
    main()
