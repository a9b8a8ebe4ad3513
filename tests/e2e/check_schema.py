#!/usr/bin/env python3
"""Checks HDF5 files against the tables in schemas/<name>.md.

usage: check_schema.py SCHEMA_MD FILE.h5 [FILE.h5 ...]
Exit status 0 when every file matches; prints one line per problem otherwise.
"""
import json
import re
import sys

import h5py
import numpy as np

COMMON = [
    ("/", "attr:schema", "string", ""),
    ("/", "attr:schema_version", "int64", ""),
    ("/", "attr:stage", "string", ""),
    ("/", "attr:params", "json", ""),
    ("/", "attr:inputs", "json", ""),
    ("/", "attr:created_by", "string", ""),
]


def parse_table(md_path):
    """Rows (path, kind, dtype, shape) of every table in a schema document.

    Tables are read by their header: `| path | kind | dtype | shape | meaning |`,
    `| dataset | dtype | shape | meaning |` (datasets), or `| attribute | type | meaning |`
    (root attributes).
    """
    rows = []
    header = None
    for line in open(md_path, encoding="utf-8"):
        line = line.strip()
        if not line.startswith("|"):
            header = None
            continue
        cells = [c.strip() for c in line.strip("|").split("|")]
        if header is None:
            header = [c.lower() for c in cells]
            continue
        if set("".join(cells)) <= set("-: "):
            continue
        row = dict(zip(header, cells))
        first = cells[0]
        if not first.startswith("`"):
            continue
        name = first.strip("`")
        if "path" in row and "kind" in row:
            rows.append((name, row["kind"], row.get("dtype", ""), row.get("shape", "")))
        elif "dataset" in row:
            rows.append((name, "dataset", row.get("dtype", ""), row.get("shape", "")))
        elif "attribute" in row:
            t = row.get("type", "")
            dtype = t if t in ("string", "json", "float64", "int64", "int32") else ("int64" if t == "int" else "")
            rows.append(("/", "attr:" + name, dtype, ""))
    return rows


def parse_shape(s):
    s = s.strip()
    if not s or not s.startswith("("):
        return None
    inner = s.strip("()")
    return [p.strip() for p in inner.split(",") if p.strip()]


def as_str(v):
    if isinstance(v, bytes):
        return v.decode()
    if isinstance(v, np.ndarray) and v.shape == ():
        return as_str(v[()])
    return str(v)


def check(md, fname):
    problems = []
    bind = {}
    expected_schema = None
    m = re.search(r"schema `([^`]+)`", open(md, encoding="utf-8").read())
    if m:
        expected_schema = m.group(1)
    with h5py.File(fname, "r") as f:
        for path, kind, dtype, shape in COMMON + parse_table(md):
            optional = kind.startswith("optional ")
            kind = kind.replace("optional ", "")
            if path not in f:
                if not optional:
                    problems.append(f"{fname}: {path} is missing")
                continue
            obj = f[path]
            if kind.startswith("attr:"):
                name = kind[5:]
                if name not in obj.attrs:
                    if not optional:
                        problems.append(f"{fname}: attribute {name} of {path} is missing")
                    continue
                v = obj.attrs[name]
                if dtype in ("string", "json"):
                    s = as_str(v)
                    if dtype == "json":
                        try:
                            json.loads(s)
                        except ValueError:
                            problems.append(f"{fname}: attribute {name} of {path} is not JSON")
                elif dtype.startswith(("int", "uint", "float")):
                    arr = np.asarray(v)
                    if arr.dtype.kind not in "iuf":
                        problems.append(f"{fname}: attribute {name} of {path} is not numeric")
                    elif not np.all(np.isfinite(arr)):
                        problems.append(f"{fname}: attribute {name} of {path} is not finite")
                continue
            if kind == "group":
                if not isinstance(obj, h5py.Group):
                    problems.append(f"{fname}: {path} is not a group")
                continue
            if not isinstance(obj, h5py.Dataset):
                problems.append(f"{fname}: {path} is not a dataset")
                continue
            if dtype == "string":
                if obj.dtype.kind not in "OSU":
                    problems.append(f"{fname}: {path} has dtype {obj.dtype}, expected string")
            elif not dtype:
                pass
            elif obj.dtype != np.dtype(dtype):
                problems.append(f"{fname}: {path} has dtype {obj.dtype}, expected {dtype}")
            elif obj.dtype.kind == "f" and obj.size and not np.all(np.isfinite(obj[()])):
                problems.append(f"{fname}: {path} holds NaN or inf")
            exp = parse_shape(shape)
            if exp is not None:
                if len(exp) != len(obj.shape):
                    problems.append(f"{fname}: {path} has shape {obj.shape}, expected {shape}")
                    continue
                for sym, got in zip(exp, obj.shape):
                    if sym.isdigit():
                        if int(sym) != got:
                            problems.append(f"{fname}: {path} has shape {obj.shape}, expected {shape}")
                    elif sym in ("*", "..."):
                        continue
                    elif sym in bind and bind[sym] != got:
                        problems.append(
                            f"{fname}: {path} dimension {sym}={got} disagrees with {sym}={bind[sym]} elsewhere")
                    else:
                        bind[sym] = got
        if expected_schema and as_str(f.attrs.get("schema", "")) != expected_schema:
            problems.append(f"{fname}: schema attribute is {as_str(f.attrs.get('schema', ''))}, expected {expected_schema}")
    return problems


def main():
    if len(sys.argv) < 3:
        print(__doc__)
        return 2
    md = sys.argv[1]
    problems = []
    for fname in sys.argv[2:]:
        problems += check(md, fname)
    for p in problems:
        print(p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
