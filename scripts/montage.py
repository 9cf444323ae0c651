#!/usr/bin/env python3
"""Lays binary PPM images side by side (one row, 4 px dark gaps) into a PNG.

    montage.py OUT.png IN1.ppm IN2.ppm ...

Standard library only (zlib for the PNG), so the figures script needs nothing
beyond glint itself and python3.
"""
import struct
import sys
import zlib


def read_ppm(path):
    data = open(path, "rb").read()
    fields, pos = [], 0
    while len(fields) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            pos = data.index(b"\n", pos) + 1
            continue
        end = pos
        while not data[end:end + 1].isspace():
            end += 1
        fields.append(data[pos:end])
        pos = end
    if fields[0] != b"P6" or int(fields[3]) != 255:
        raise SystemExit(f"{path}: not an 8-bit binary PPM")
    w, h = int(fields[1]), int(fields[2])
    pixels = data[pos + 1:pos + 1 + 3 * w * h]
    return w, h, [pixels[3 * w * y:3 * w * (y + 1)] for y in range(h)]


def write_png(path, w, h, rows):
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    raw = b"".join(b"\x00" + r for r in rows)
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    open(path, "wb").write(png)


def main():
    out, inputs = sys.argv[1], sys.argv[2:]
    images = [read_ppm(p) for p in inputs]
    gap = 4
    height = max(h for _, h, _ in images)
    width = sum(w for w, _, _ in images) + gap * (len(images) - 1)
    background = b"\x20\x20\x20"
    rows = []
    for y in range(height):
        row = b""
        for i, (w, h, pixels) in enumerate(images):
            if i:
                row += background * gap
            row += pixels[y] if y < h else background * w
        rows.append(row)
    write_png(out, width, height, rows)


if __name__ == "__main__":
    main()
