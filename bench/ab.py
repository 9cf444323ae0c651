#!/usr/bin/env python3
"""Two glint builds on the same scenes: the render phase (the "render X s" of
glint's summary line), the builds alternated run by run so that a machine's
drift hits both, and per scene the median of the pair-by-pair ratios A / B.

usage: bench/ab.py A_GLINT B_GLINT SCENE... [--runs 9] [--threads 2] [-- RENDER_ARGS...]
e.g.   bench/ab.py build/glint /tmp/glint-before scenes/showcase.json ../shared/bench/spd/balls.nff

A ratio below 1 means A renders faster. Each build's image is checked to be
byte-identical to the other's (PFM output), so a speed change that moves a
pixel shows here too.
"""
import argparse
import filecmp
import os
import re
import statistics
import subprocess
import sys
import tempfile

RENDER = re.compile(r"render ([0-9.]+) s")


def render_seconds(glint, scene, out, threads, extra):
    scene = os.path.abspath(scene)
    cmd = [glint, "render", scene, "-o", out, "--threads", str(threads), *extra]
    run = subprocess.run(cmd, capture_output=True, text=True, cwd=os.path.dirname(scene))
    if run.returncode != 0:
        sys.exit(f"error: {' '.join(cmd)} exited {run.returncode}: {run.stderr.strip()}")
    m = RENDER.search(run.stderr)
    if not m:
        sys.exit(f"error: no 'render X s' in the output of {' '.join(cmd)}: {run.stderr.strip()}")
    return float(m.group(1))


def main():
    argv = sys.argv[1:]
    extra = []
    if "--" in argv:
        extra = argv[argv.index("--") + 1:]
        argv = argv[:argv.index("--")]
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("a")
    p.add_argument("b")
    p.add_argument("scenes", nargs="+")
    p.add_argument("--runs", type=int, default=9)
    p.add_argument("--threads", type=int, default=2)
    args = p.parse_args(argv)
    args.a, args.b = os.path.abspath(args.a), os.path.abspath(args.b)
    with tempfile.TemporaryDirectory() as tmp:
        print(f"{'scene':<24} {'A (s)':>8} {'B (s)':>8} {'A / B':>7}   ({args.runs} alternated pairs, median)")
        for scene in args.scenes:
            out_a, out_b = os.path.join(tmp, "a.pfm"), os.path.join(tmp, "b.pfm")
            render_seconds(args.a, scene, out_a, args.threads, extra)  # warm-up, and the images
            render_seconds(args.b, scene, out_b, args.threads, extra)
            same = filecmp.cmp(out_a, out_b, shallow=False)
            a, b, ratios = [], [], []
            for _ in range(args.runs):
                a.append(render_seconds(args.a, scene, out_a, args.threads, extra))
                b.append(render_seconds(args.b, scene, out_b, args.threads, extra))
                ratios.append(a[-1] / b[-1])
            name = os.path.basename(scene)
            print(f"{name:<24} {statistics.median(a):8.4f} {statistics.median(b):8.4f} "
                  f"{statistics.median(ratios):7.3f}   images {'identical' if same else 'DIFFER'}")


if __name__ == "__main__":
    main()
