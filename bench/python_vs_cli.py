#!/usr/bin/python3
"""The render phase of a scene from Python against the glint CLI's.

Both time the same thing: the pixel loop (the CLI's statistics line
"render X s"; Python's render.stats["render_seconds"]), with the same
threads, so loading, building and writing are left out on both sides. Runs
alternate (CLI, Python, CLI, ...) so that a machine's drift hits both; the
result is the median of the per-pair ratios Python / CLI.

Usage (from a build with GLINT_PYTHON):
  PYTHONPATH=build/python /usr/bin/python3 bench/python_vs_cli.py \
      --glint build/glint [--scene scenes/showcase.json] [--runs 10] [--threads 2]
Not part of the tests. Run it on a quiet machine.
"""
import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile

import glint


def cli_seconds(cli, scene, threads, out):
    p = subprocess.run([cli, "render", scene, "-o", out, "--threads", str(threads)],
                       capture_output=True, text=True, check=True)
    m = re.search(r"render ([0-9.]+) s", p.stderr)
    if not m:
        sys.exit(f"no statistics line from the CLI:\n{p.stderr}")
    return float(m.group(1))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--glint", required=True, help="the glint CLI of the same build")
    ap.add_argument("--scene", default=os.path.join(os.path.dirname(__file__), "..", "scenes", "showcase.json"))
    ap.add_argument("--runs", type=int, default=10)
    ap.add_argument("--threads", type=int, default=os.cpu_count())
    args = ap.parse_args()
    scene = glint.load(args.scene)
    glint.render(scene, threads=args.threads)  # prepared once, as a notebook would be
    ratios, py_times, cli_times = [], [], []
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "out.pfm")
        for i in range(args.runs):
            c = cli_seconds(args.glint, args.scene, args.threads, out)
            p = glint.render(scene, threads=args.threads).stats["render_seconds"]
            cli_times.append(c)
            py_times.append(p)
            ratios.append(p / c)
            print(f"run {i + 1}: cli {c:.3f} s, python {p:.3f} s, ratio {p / c:.3f}", flush=True)
    print(f"median: cli {statistics.median(cli_times):.3f} s, python {statistics.median(py_times):.3f} s, "
          f"ratio (python / cli) {statistics.median(ratios):.3f} over {args.runs} alternated runs, "
          f"{args.threads} threads, {os.path.basename(args.scene)}")


if __name__ == "__main__":
    main()
