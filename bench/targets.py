#!/usr/bin/python3
"""Measure issue #16's targets in one run and print them as a table.

    bench/targets.py BUILD_DIR [--runs N] [--povray] [--scenes DIR]

BUILD_DIR holds `glint` and `bench/glint_bench_accel` (a Release build with
the Embree plugin). Each figure is measured side by side in this one run
(the machine's speed changes from hour to hour; ratios taken in one run are
what compare): the bench scenes come from make_bench.py (generated into
--scenes if missing), every glint run is a separate process, runs of the
two sides of a ratio alternate, and each figure is the median of --runs
(default 9). --povray adds the end-to-end comparison with POV-Ray 3.7
(bench/vs-povray.sh, min of 5). Not measured here: the 10M figures (bytes per
triangle, per-ray cost against 100k), which take minutes and 5 GB; see
docs/performance.md. Standard library only; prints Markdown.
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def run(cmd, **kw):
    out = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kw)
    if out.returncode != 0:
        sys.exit(f"error: {' '.join(cmd)} failed ({out.returncode}): {out.stderr.strip()[-500:]}")
    return out


class Glint:
    def __init__(self, binary, tmp):
        self.binary, self.tmp = binary, tmp

    def render(self, scene, *args):
        """Phases (--stats-json), wall time, and /usr/bin/time's faults, peak KB and system time."""
        stats = os.path.join(self.tmp, "stats.json")
        cmd = ["/usr/bin/time", "-f", "%R %M %S", self.binary, "render", scene, "-o",
               os.path.join(self.tmp, "out.png"), "--quiet", "--stats-json", stats, *args]
        start = time.perf_counter()
        out = run(cmd)
        wall = time.perf_counter() - start
        faults, peak_kb, system = out.stderr.strip().splitlines()[-1].split()
        with open(stats) as f:
            seconds = json.load(f)["seconds"]
        return {**seconds, "wall": wall, "faults": int(faults), "peak_kb": int(peak_kb), "system": float(system)}


def median(runs, key):
    return statistics.median(r[key] for r in runs)


def alternate(runs, *sides):
    """Each side (a function of no arguments) run `runs` times, the sides taking turns."""
    results = [[] for _ in sides]
    for _ in range(runs):
        for i, side in enumerate(sides):
            results[i].append(side())
    return results


def bench_ratios(bench):
    """glint_bench_accel on the 1M terrain: the bvh/embree row, 1 and 2 threads."""
    out = run([bench, "--sizes", "1000000", "--threads", "1,2", "--repeat", "5"]).stdout
    row = next(line for line in out.splitlines() if line.startswith("bvh/embree"))
    numbers = [float(x) for x in re.findall(r"\d+\.\d+", row)]
    # build, B/tri, peak B/tri | 1T camera shadow mirror packets | 2T ...
    return {"bytes": numbers[1], "peak_bytes": numbers[2], "1T": numbers[3:7], "2T": numbers[7:11]}


def povray_ratios(glint, scenes):
    env = dict(os.environ, RUNS="5", BENCH_SCENES=scenes)
    out = run(["bash", os.path.join(HERE, "vs-povray.sh"), glint, "spheres", "bunny", "terrain"], env=env).stdout
    ratios = {}
    for line in out.splitlines():
        m = re.match(r"\s*(spheres|bunny|terrain)\b.*?([\d.]+)x\s*$", line)
        if m:
            ratios[m.group(1)] = float(m.group(2))
    return ratios


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build", help="build folder with glint and bench/glint_bench_accel")
    parser.add_argument("--runs", type=int, default=9)
    parser.add_argument("--povray", action="store_true", help="also glint against POV-Ray 3.7 (needs povray)")
    parser.add_argument("--scenes", default=os.path.join(HERE, "bench-scenes"))
    args = parser.parse_args()
    binary = os.path.abspath(os.path.join(args.build, "glint"))
    bench = os.path.abspath(os.path.join(args.build, "bench", "glint_bench_accel"))
    for path in (binary, bench):
        if not os.access(path, os.X_OK):
            sys.exit(f"error: {path} not found (build the project first)")
    names = ["spheres", "bunny", "terrain", "terrain-normals"]
    missing = [n for n in names if not os.path.exists(os.path.join(args.scenes, n + ".json"))]
    if missing:
        run([sys.executable, os.path.join(HERE, "make_bench.py"), "-o", args.scenes, "--only", ",".join(missing)])
    scene = {n: os.path.join(args.scenes, n + ".json") for n in names}

    rows = []

    def row(measure, value, target, met):
        rows.append((measure, value, target, "met" if met else "**not met**"))

    with tempfile.TemporaryDirectory() as tmp:
        glint = Glint(binary, tmp)
        runs = args.runs

        ours, embree = alternate(runs, lambda: glint.render(scene["terrain"], "--threads", "2", "--accel", "bvh"),
                                 lambda: glint.render(scene["terrain"], "--threads", "2", "--accel", "embree"))
        e2e = median(embree, "total") / median(ours, "total")
        row("1M terrain end to end, Embree's time / ours", f"{e2e:.2f} ({median(embree, 'total'):.3f} / "
            f"{median(ours, 'total'):.3f} s)", ">= 1.25", e2e >= 1.25)
        build = median(ours, "build") / median(embree, "build")
        row("BVH build in `glint render`, 1M: ours / Embree's", f"{build:.2f} ({median(ours, 'build'):.3f} / "
            f"{median(embree, 'build'):.3f} s)", "<= 1.0", build <= 1.0)
        faults, peak_pages = median(ours, "faults"), median(ours, "peak_kb") / 4
        row("minor page faults / peak pages (4 KiB), 1M terrain", f"{faults / peak_pages:.2f} ({faults:.0f} for "
            f"{median(ours, 'peak_kb') / 1024:.1f} MB)", "<= 1.1", faults <= 1.1 * peak_pages)
        kernel = statistics.median(r["system"] / r["wall"] for r in ours)
        row("kernel time / wall, 1M terrain", f"{100 * kernel:.0f}% ({median(ours, 'system'):.2f} s of "
            f"{median(ours, 'wall'):.2f} s)", "<= 10%", kernel <= 0.10)
        stages = ", ".join(f"{k} {median(ours, k):.3f}" for k in ("load", "build", "render", "write", "total"))
        rows.append(("1M terrain stages, s (not a target)", stages, "", ""))

        normals = [glint.render(scene["terrain-normals"], "--threads", "2", "--width", "64", "--height", "64")
                   for _ in range(runs)]
        load = median(normals, "load")
        row("load of the 1M OBJ with vertex normals", f"{load:.3f} s", "<= 0.3 s", load <= 0.3)

        spheres = [glint.render(scene["spheres"], "--threads", "2") for _ in range(runs)]
        fixed = statistics.median(r["wall"] - r["render"] for r in spheres)
        row("fixed cost, 1000 spheres at 1920x1080 (wall - render)", f"{1000 * fixed:.0f} ms", "<= 80 ms",
            fixed <= 0.080)

        showcase = os.path.join(ROOT, "scenes", "showcase.json")
        size = ["--width", "1280", "--height", "960", "--spp", "4"]
        one, two = alternate(max(3, runs // 3), lambda: glint.render(showcase, "--threads", "1", *size),
                             lambda: glint.render(showcase, "--threads", "2", *size))
        scaling = median(one, "wall") / median(two, "wall")
        row("2 threads against 1, showcase 1280x960 4 spp", f"{scaling:.2f}x", ">= 1.9x", scaling >= 1.9)

        k = bench_ratios(bench)
        kinds = ("camera", "shadow", "mirror", "packets")
        for threads, label in (("2T", "2 threads"), ("1T", "1 thread")):
            values = " / ".join(f"{v:.2f}" for v in k[threads])
            row(f"render path / bare Embree, {' / '.join(kinds)}, {label}", values, ">= 1.0 each",
                min(k[threads]) >= 1.0)
        row("bytes per triangle / Embree's, 1M (target at 10M)", f"{k['bytes']:.2f}", "<= 0.7", k["bytes"] <= 0.7)
        row("peak memory while building / Embree's, 1M", f"{k['peak_bytes']:.2f}", "<= 1.2",
            k["peak_bytes"] <= 1.2)

        if args.povray:
            ratios = povray_ratios(binary, args.scenes)
            values = " / ".join(f"{ratios.get(n, 0):.2f}x" for n in ("spheres", "bunny", "terrain"))
            row("against POV-Ray 3.7: spheres / bunny / terrain", values, ">= 8x each",
                all(ratios.get(n, 0) >= 8 for n in ("spheres", "bunny", "terrain")))

    print(f"Issue #16's targets, {time.strftime('%Y-%m-%d %H:%M')}, {args.runs} runs "
          f"(load average {os.getloadavg()[0]:.1f})\n")
    print("| measure | measured | target | |\n| --- | --- | --- | --- |")
    for r in rows:
        print("| " + " | ".join(r) + " |")


if __name__ == "__main__":
    main()
