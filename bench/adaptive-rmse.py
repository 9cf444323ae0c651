#!/usr/bin/env python3
"""Adaptive sampling against plain sampling: RMSE against a reference render.

    bench/adaptive-rmse.py [GLINT] [SCENE]     (defaults: build/glint scenes/showcase.json)

Renders SCENE at 160x90 to PFM (exact linear floats): a 256 spp reference,
plain 4, 16 and 32 spp, and adaptive 4 -> 64 at threshold 0.05, then prints
each one's RMSE over all pixels and channels (linear values) and its camera
rays (and the share of pixels refined) from glint's statistics lines. Python 3 standard library only.
"""
import os
import re
import struct
import subprocess
import sys
import tempfile

W, H = 160, 90


def read_pfm(path):
    with open(path, "rb") as f:
        assert f.readline().strip() == b"PF", path
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        fmt = "<" if scale < 0 else ">"
        return struct.unpack(fmt + "%df" % (3 * w * h), f.read(12 * w * h))


def render(glint, scene, out, *args):
    log = subprocess.run([glint, "render", scene, "-o", out, "--width", str(W), "--height", str(H), *args],
                         check=True, capture_output=True, text=True).stderr
    camera = re.search(r"rays: (\S+) camera", log)
    refined = re.search(r"adaptive: .*\(([0-9.]+%)\)", log)
    return (camera.group(1) if camera else "?") + (", %s of the pixels refined" % refined.group(1) if refined else "")


def main(argv):
    glint = argv[1] if len(argv) > 1 else "build/glint"
    scene = argv[2] if len(argv) > 2 else "scenes/showcase.json"
    with tempfile.TemporaryDirectory() as tmp:
        ref_path = os.path.join(tmp, "ref.pfm")
        render(glint, scene, ref_path, "--spp", "256")
        ref = read_pfm(ref_path)
        runs = [("4 spp", ["--spp", "4"]), ("16 spp", ["--spp", "16"]), ("32 spp", ["--spp", "32"]),
                ("4 -> 64 adaptive, threshold 0.05",
                 ["--spp", "4", "--adaptive-max-spp", "64", "--adaptive-threshold", "0.05"])]
        print("%dx%d, RMSE against 256 spp (linear values)" % (W, H))
        for name, args in runs:
            path = os.path.join(tmp, "x.pfm")
            camera = render(glint, scene, path, *args)
            img = read_pfm(path)
            rmse = (sum((a - b) ** 2 for a, b in zip(img, ref)) / len(ref)) ** 0.5
            print("%-34s RMSE %.4f   camera rays %s" % (name, rmse, camera))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
