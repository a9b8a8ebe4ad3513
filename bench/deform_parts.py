#!/usr/bin/env python3
"""Sums the per-part wall seconds that deform logs for each iteration
("deform: iteration N seconds (wall/cpu): footprints 0.12/0.10, ...") and prints a
table of wall/CPU seconds per part (CPU = process CPU of all threads).

Usage: bench/deform_parts.py deform.log [more.log ...]   (one column per log)
Run deform with its log kept, e.g.
  /usr/bin/time -v bin/deform --scene RUN/scene.h5 --mesh RUN/cut2.ply --out /tmp/x/final.ply \
      --stats /tmp/x/deform.h5 2> /tmp/x/deform.log
"""
import re
import sys


def parts(path):
    tot, order = {}, []
    extra = {}
    for line in open(path, errors="replace"):
        m = re.search(r"deform: iteration \d+ seconds \(wall/cpu\): (.*)$", line)
        if m:
            for item in m.group(1).split(", "):
                name, val = item.rsplit(" ", 1)
                w, c = (float(x) for x in val.split("/"))
                if name not in tot:
                    order.append(name)
                    tot[name] = [0.0, 0.0]
                tot[name][0] += w
                tot[name][1] += c
        m = re.search(r"Elapsed \(wall clock\) time.*: (.*)$", line)
        if m:
            f = [float(x) for x in m.group(1).split(":")]
            extra["wall (time -v)"] = f[-1] + 60 * f[-2] + (3600 * f[-3] if len(f) > 2 else 0)
        for key in ("User time (seconds)", "System time (seconds)"):
            if key in line:
                extra["cpu"] = extra.get("cpu", 0.0) + float(line.split(":")[-1])
        m = re.search(r"silhouette IoU [0-9.]+ -> ([0-9.]+)", line)
        if m:
            extra["final IoU"] = float(m.group(1))
        m = re.search(r"intersections \d+ -> (\d+)", line)
        if m:
            extra["final intersections"] = float(m.group(1))
        m = re.search(r"(\d+) vertices, (\d+) faces, \d+ components", line)
        if m:
            extra["final vertices"] = float(m.group(1))
    tot["sum of parts"] = [sum(v[0] for v in tot.values()), sum(v[1] for v in tot.values())]
    order.append("sum of parts")
    return tot, order, extra


def main():
    cols = [parts(p) for p in sys.argv[1:]]
    names = []
    for _, order, extra in cols:
        for n in order + list(extra):
            if n not in names:
                names.append(n)
    print("| part (wall / CPU s) | " + " | ".join(sys.argv[1:]) + " |")
    print("| --- |" + " --- |" * len(cols))
    for n in names:
        row = []
        for tot, _, extra in cols:
            v = tot.get(n, extra.get(n))
            if isinstance(v, list):
                row.append(f"{v[0]:.1f} / {v[1]:.1f}")
            else:
                row.append("" if v is None else (f"{v:.4f}" if n == "final IoU" else f"{v:.1f}"))
        print(f"| {n} | " + " | ".join(row) + " |")


if __name__ == "__main__":
    main()
