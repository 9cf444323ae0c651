#!/usr/bin/python3
"""glint's renders of the SPD scenes next to the SPD's own pictures.

    bench/spd-figure.py GLINT_BINARY [OUT_DIR]      (default OUT_DIR: docs/img)

Renders bench/spd/balls.nff and tetra.nff at 512 x 512 (1 spp, max depth 5,
SPD-style) into OUT_DIR/spd-balls.png and spd-tetra.png, and writes
OUT_DIR/spd-compare.png: one row per scene, glint on the left, the SPD's
picture (bench/spd/NAME-published.png) on the right. Standard library only:
the PNGs are decoded here (8-bit RGB, the published files' kind) and the
figure is written with scripts/montage.py's PNG writer.
"""

import os
import struct
import subprocess
import sys
import tempfile
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "scripts"))
from montage import read_ppm, write_png  # noqa: E402

SCENES = ("balls", "tetra")
GAP = 4
GAP_COLOR = b"\x20\x20\x20"


def read_png_rgb8(path):
    """Width, height and rows of an 8-bit RGB, non-interlaced PNG."""
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        sys.exit("%s: not a PNG" % path)
    pos, idat, w = 8, b"", 0
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        pos += 12 + length
        if kind == b"IHDR":
            w, h, depth, color, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or color != 2 or interlace:
                sys.exit("%s: only 8-bit RGB non-interlaced PNGs are read here" % path)
        elif kind == b"IDAT":
            idat += body
    raw = zlib.decompress(idat)
    stride, bpp, rows, prev = 3 * w, 3, [], bytearray(3 * w)
    for y in range(h):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for x in range(stride):  # undo the row's filter (PNG spec, filter method 0)
            a = line[x - bpp] if x >= bpp else 0
            b, c = prev[x], prev[x - bpp] if x >= bpp else 0
            if f == 1:
                line[x] = (line[x] + a) & 255
            elif f == 2:
                line[x] = (line[x] + b) & 255
            elif f == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        prev = line
    return w, h, rows


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    glint = sys.argv[1]
    out_dir = sys.argv[2] if len(sys.argv) == 3 else os.path.join(ROOT, "docs", "img")
    grid = []
    with tempfile.TemporaryDirectory() as tmp:
        for name in SCENES:
            scene = os.path.join(HERE, "spd", name + ".nff")
            common = [glint, "render", scene, "--width", "512", "--height", "512", "--spp", "1",
                      "--max-depth", "5", "--quiet"]
            subprocess.run(common + ["-o", os.path.join(out_dir, "spd-%s.png" % name)], check=True)
            ppm = os.path.join(tmp, name + ".ppm")
            subprocess.run(common + ["-o", ppm], check=True)
            grid.append((read_ppm(ppm), read_png_rgb8(os.path.join(HERE, "spd", name + "-published.png"))))
    width = max(a[0] + GAP + b[0] for a, b in grid)
    rows = []
    for i, (a, b) in enumerate(grid):
        if i:
            rows += [GAP_COLOR * width] * GAP
        for y in range(max(a[1], b[1])):
            left = a[2][y] if y < a[1] else GAP_COLOR * a[0]
            right = b[2][y] if y < b[1] else GAP_COLOR * b[0]
            row = left + GAP_COLOR * GAP + right
            rows.append(row + GAP_COLOR * (width - len(row) // 3))
    write_png(os.path.join(out_dir, "spd-compare.png"), width, len(rows), rows)
    print("wrote %s" % ", ".join(os.path.join(out_dir, f) for f in
                                 ["spd-%s.png" % n for n in SCENES] + ["spd-compare.png"]))


if __name__ == "__main__":
    main()
