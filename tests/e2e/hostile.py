"""Hostile inputs for the e2e tests, made from scratch (no image library needed):
image files whose headers declare absurd sizes or lie about their contents, HDF5 files
whose datasets declare more than they hold, PLY headers that promise what the body lacks,
nonsense scene geometry (par file and bounding box edits of a valid dataset), and a
write-failure harness (a file size limit, as a full disk).

Each generator returns bytes or writes a file; the tests decide what must happen."""
import os
import resource
import shutil
import struct
import subprocess
import zlib

import numpy as np


# ---- images -----------------------------------------------------------------------------
def _chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)


def png(width, height, rows=None, depth=8, colour=2, crc_ok=True):
    """A PNG whose header declares width x height. rows: the pixel rows to store (bytes per
    row without the filter byte); default a few rows of zeros, far fewer than declared."""
    ihdr = struct.pack(">IIBBBBB", width, height, depth, colour, 0, 0, 0)
    if rows is None:
        rows = [bytes(3 * min(width, 16))] * min(height, 4)
    raw = b"".join(b"\x00" + r for r in rows)
    idat = _chunk(b"IDAT", zlib.compress(raw))
    if not crc_ok:
        idat = idat[:-4] + b"\x00\x00\x00\x00"
    return b"\x89PNG\r\n\x1a\n" + _chunk(b"IHDR", ihdr) + idat + _chunk(b"IEND", b"")


def png_rgb(pixels):
    """A valid 8-bit RGB PNG of an (h, w, 3) uint8 array."""
    h, w, _ = pixels.shape
    return png(w, h, rows=[pixels[y].tobytes() for y in range(h)])


def png_rgb16(width, height):
    """A valid 16-bit RGB PNG (decodable, but not 8-bit)."""
    return png(width, height, rows=[bytes(6 * width)] * height, depth=16)


def jpeg(width, height):
    """A JPEG that is only a start-of-frame segment declaring width x height."""
    # (length 11: itself, precision, height, width, component count, one component)
    sof = b"\xff\xc0" + struct.pack(">HBHHB", 11, 8, height, width, 1) + b"\x01\x11\x00"
    return b"\xff\xd8" + sof + b"\xff\xd9"


def bmp(width, height):
    """A BMP header declaring width x height, 24 bits, without pixel data."""
    info = struct.pack("<IiiHHIIiiII", 40, width, height, 1, 24, 0, 0, 2835, 2835, 0, 0)
    return b"BM" + struct.pack("<IHHI", 14 + len(info), 0, 0, 14 + len(info)) + info


def pnm(width, height):
    return f"P6\n# hostile\n{width} {height}\n255\n".encode() + bytes(16)


def tiff(width, height):
    """A little-endian TIFF whose first directory declares width x height."""
    entries = [(256, 4, 1, width), (257, 4, 1, height), (258, 3, 1, 8), (277, 3, 1, 3)]
    ifd = struct.pack("<H", len(entries)) + b"".join(struct.pack("<HHII", *e) for e in entries) + struct.pack("<I", 0)
    return b"II*\x00" + struct.pack("<I", 8) + ifd


def hostile_images(w, h):
    """(name, bytes, words the error must hold) for one image of a dataset of w x h images."""
    big = 60000
    good = png_rgb(np.full((h, w, 3), 128, np.uint8))
    return [
        ("png_60000", png(big, big), ["60000 x 60000", "memory budget"]),
        ("jpeg_60000", jpeg(big, big), ["60000 x 60000", "memory budget"]),
        ("bmp_60000", bmp(big, big), ["60000 x 60000", "memory budget"]),
        ("pnm_60000", pnm(big, big), ["60000 x 60000", "memory budget"]),
        ("tiff_60000", tiff(big, big), ["60000 x 60000", "memory budget"]),
        # within the budget by its header, past what the decoder accepts (2^30 pixels)
        ("png_wide", png(2 ** 20, 1025), ["cannot decode"]),
        ("png_empty_size", png(0, 0), ["cannot decode"]),
        ("png_truncated", good[: len(good) // 2], ["cannot decode"]),
        ("png_bad_crc", png(w, h, crc_ok=False), ["cannot decode"]),
        ("png_16bit", png_rgb16(w, h), ["8-bit"]),
        ("png_other_size", png_rgb(np.zeros((h // 2, w // 2, 3), np.uint8)), ["all images"]),
        ("zero_bytes", b"", ["cannot decode"]),
        ("garbage", os.urandom(3000), ["cannot decode"]),
    ]


# ---- HDF5 and PLY files that declare more than they hold ---------------------------------
def h5_declaring(src, dst, name, shape, dtype):
    """Copies src to dst with dataset `name` replaced by a chunked, compressed one of the
    declared shape that stores nothing (a few bytes on disk, GiBs when read)."""
    import h5py
    shutil.copy(src, dst)
    with h5py.File(dst, "r+") as f:
        del f[name]
        f.create_dataset(name, shape=shape, dtype=dtype, chunks=True, compression="gzip")


def ply_declaring(path, vertices, faces=0):
    """A binary PLY header declaring far more elements than its few bytes of body hold."""
    head = ("ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
            "property float z\nelement face %d\nproperty list uchar int vertex_indices\nend_header\n") % (vertices, faces)
    with open(path, "wb") as f:
        f.write(head.encode() + bytes(64))


# ---- nonsense scenes: edits of a valid Middlebury-layout dataset ---------------------------
def read_par(path):
    lines = open(path).read().split("\n")
    n = int(lines[0])
    rows = [l.split() for l in lines[1:1 + n]]
    return rows


def write_par(path, rows):
    with open(path, "w") as f:
        f.write(f"{len(rows)}\n" + "".join(" ".join(r) + "\n" for r in rows))


def centre(row):
    R = np.array([float(x) for x in row[10:19]]).reshape(3, 3)
    t = np.array([float(x) for x in row[19:22]])
    return -R.T @ t


def face_away(row):
    """The camera at the same place, turned half a turn about its own y axis."""
    R = np.array([float(x) for x in row[10:19]]).reshape(3, 3)
    t = np.array([float(x) for x in row[19:22]])
    D = np.diag([-1.0, 1.0, -1.0])
    return row[:10] + [repr(v) for v in (D @ R).reshape(-1)] + [repr(v) for v in D @ t]


def par_file(ds):
    return next(os.path.join(ds, f) for f in os.listdir(ds) if f.endswith("_par.txt"))


def nonsense_scenes(ds, tmp):
    """(name, dataset folder, 'refuse' or 'warn', words the message must hold): copies of the
    valid dataset `ds` with one nonsense edit each."""
    out = []

    def variant(name, edit):
        d = os.path.join(tmp, name)
        shutil.copytree(ds, d)
        edit(d)
        return d

    def box(lo, hi):
        def f(d):
            with open(os.path.join(d, "bbox.txt"), "w") as b:
                b.write(" ".join(map(repr, lo)) + "\n" + " ".join(map(repr, hi)) + "\n")
        return f

    rows = read_par(par_file(ds))
    c0 = centre(rows[0])
    out.append(("box_1e30", variant("box_1e30", box([-1e30] * 3, [1e30] * 3)), "refuse", ["inside the box", "1e+30"]))
    out.append(("box_around_camera", variant("box_around_camera", box(list(c0 - 0.01), list(c0 + 0.01))), "refuse",
                ["inside the box", rows[0][0]]))
    out.append(("box_overflow", variant("box_overflow", box([-1e308] * 3, [1e308] * 3)), "refuse", ["not a finite box"]))

    def one_view(d):
        p = par_file(d)
        write_par(p, read_par(p)[:1])
    out.append(("one_view", variant("one_view", one_view), "refuse", ["1 view", "two views"]))

    def turn(k):
        def f(d):
            p = par_file(d)
            r = read_par(p)
            for i in range(k):
                r[i] = face_away(r[i])
            write_par(p, r)
        return f
    out.append(("facing_away", variant("facing_away", turn(1)), "warn", [rows[0][0], "sees none of the box"]))
    out.append(("all_but_one_away", variant("all_but_one_away", turn(len(rows) - 1)), "refuse",
                ["only 1 of", "see the box"]))

    def black(k):
        def f(d):
            for r in read_par(par_file(d))[:k]:
                im = os.path.join(d, r[0])
                h, w = _png_size(im)
                open(im, "wb").write(png_rgb(np.zeros((h, w, 3), np.uint8)))
        return f
    out.append(("one_black", variant("one_black", black(1)), "warn", [rows[0][0], "uniform"]))
    out.append(("all_black", variant("all_black", black(len(rows))), "refuse", ["every image is uniform"]))

    def no_mask(d):
        os.remove(os.path.join(d, "silhouettes", rows[1][0]))
    out.append(("missing_mask", variant("missing_mask", no_mask), "warn", ["silhouettes", rows[1][0], "no mask"]))

    def duplicate(d):
        p = par_file(d)
        r = read_par(p)
        base, ext = os.path.splitext(r[0][0])
        twin = base + "_twin" + ext
        shutil.copy(os.path.join(d, r[0][0]), os.path.join(d, twin))
        shutil.copy(os.path.join(d, "silhouettes", r[0][0]), os.path.join(d, "silhouettes", twin))
        write_par(p, r + [[twin] + r[0][1:]])
    out.append(("duplicate_camera", variant("duplicate_camera", duplicate), "warn", ["same pose"]))
    return out


def _png_size(path):
    head = open(path, "rb").read(24)
    w, h = struct.unpack(">II", head[16:24])
    return h, w


# ---- write failures ----------------------------------------------------------------------
def run_with_file_limit(argv, limit_bytes, env=None):
    """Runs argv with a file size limit (RLIMIT_FSIZE, as `ulimit -f`): every write past
    limit_bytes fails, as on a full disk. The stages turn the limit's signal (SIGXFSZ) into
    an ordinary write error themselves."""
    def limit():
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit_bytes, limit_bytes))
    return subprocess.run(argv, capture_output=True, text=True, preexec_fn=limit, env=env)
