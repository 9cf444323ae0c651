#!/usr/bin/python3
"""glint against POV-Ray 3.7 on SPD scenes, and glint's time per ray on bigger sphereflakes.

    bench/spd-vs-povray.py GLINT_BINARY [SCENE.nff ...] [options]
    e.g. bench/spd-vs-povray.py build/glint          (bench/spd/balls.nff and tetra.nff)
         bench/spd-vs-povray.py build/glint --stand-ins --flake-depths ''
                        (balls, tetra, then our stand-ins for gears, mount, rings, teapot, tree)

Each SCENE.nff needs the SPD's own POV-Ray export of the same scene beside it,
SCENE.pov. --stand-ins [NAMES] also writes bench/spd_scenes.py's stand-ins
for the SPD scenes we do not have (each an .nff and a .pov in the export's
style; default all five) into the temporary folder and times them after the
others. For each scene, glint and POV-Ray take turns, --runs times each:

    GLINT render SCENE.nff --width 512 --height 512 --spp 1 --max-depth 5
          --threads T -o OUT.png --stats-json STATS.json
    povray +W512 +H512 -D -A +WT<T> -V +OOUT.png SCENE.pov    (in SCENE's folder)

POV-Ray renders the export as it is (its own camera, lights and finishes; one
ray through each pixel center, no antialiasing, at most 5 levels as the
export's default max_trace_level). The wall time of each process (start to
exit) is measured here; the phases come from the programs themselves: glint's
--stats-json (load, build, render, write) and POV-Ray's statistics (Parse
and Bounding Time as its load, Trace Time). Every number printed is the
median over the runs; the ratios are POV-Ray's median over glint's.

Then (unless --flake-depths is empty) it writes sphereflakes of the given
depths with bench/sphereflake.py (our own generator) and renders each with
glint alone at each of --flake-threads, the depths taking turns, and prints
the render phase over the total rays (--stats-json) against the sphere count.

Needs povray (Debian: apt-get install povray) unless --no-povray.
"""

import argparse
import json
import math
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_SCENES = [os.path.join(HERE, "spd", "balls.nff"), os.path.join(HERE, "spd", "tetra.nff")]
SIZE = 512
STAND_INS = "gears,mount,rings,teapot,tree"


def run_glint(glint, scene, threads, tmp):
    out, stats = os.path.join(tmp, "glint.png"), os.path.join(tmp, "glint-stats.json")
    for f in (out, stats):
        if os.path.exists(f):
            os.remove(f)
    cmd = [glint, "render", scene, "--width", str(SIZE), "--height", str(SIZE), "--spp", "1",
           "--max-depth", "5", "--threads", str(threads), "-o", out, "--stats-json", stats, "--quiet"]
    t0 = time.perf_counter()
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    wall = time.perf_counter() - t0
    if p.returncode != 0 or not os.path.exists(stats):
        sys.exit("error: glint failed on %s (exit %d):\n%s" % (scene, p.returncode, p.stdout.decode()[-2000:]))
    with open(stats, encoding="utf-8") as f:
        s = json.load(f)
    sec = s["seconds"]
    return {"wall": wall, "load": sec["load"] + sec["build"], "trace": sec["render"], "write": sec["write"],
            "rays": s["rays"]["total"], "stats": s}


POV_TIME = re.compile(r"^\s*(Parse|Bounding|Trace) Time:.*\(([0-9.]+) seconds\)", re.M)


def run_povray(pov, threads, tmp, home):
    out = os.path.join(tmp, "povray.png")
    if os.path.exists(out):
        os.remove(out)
    cmd = ["povray", "+W%d" % SIZE, "+H%d" % SIZE, "-D", "-A", "+WT%d" % threads, "-V", "+O" + out,
           os.path.basename(pov)]
    env = dict(os.environ, HOME=home)
    t0 = time.perf_counter()
    p = subprocess.run(cmd, cwd=os.path.dirname(pov), env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    wall = time.perf_counter() - t0
    log = p.stdout.decode(errors="replace")
    if p.returncode != 0 or not os.path.exists(out):
        sys.exit("error: povray failed on %s (exit %d):\n%s" % (pov, p.returncode, log[-2000:]))
    t = {k: float(v) for k, v in POV_TIME.findall(log)}
    return {"wall": wall, "load": t.get("Parse", 0.0) + t.get("Bounding", 0.0), "trace": t.get("Trace", 0.0)}


def med(runs, key):
    return statistics.median(r[key] for r in runs)


def compare(args, tmp):
    # An empty user config: no "cannot open the user configuration file"
    # warning, and no personal ~/.povray settings in the measurement.
    home = os.path.join(tmp, "home")
    os.makedirs(os.path.join(home, ".povray", "3.7"), exist_ok=True)
    open(os.path.join(home, ".povray", "3.7", "povray.conf"), "w").close()
    rows = []
    for scene in args.scenes:
        pov = os.path.splitext(scene)[0] + ".pov"
        name = os.path.splitext(os.path.basename(scene))[0]
        g, p = [], []
        for i in range(args.runs):
            print("%s: run %d/%d" % (name, i + 1, args.runs), file=sys.stderr)
            g.append(run_glint(args.glint, scene, args.threads, tmp))
            if not args.no_povray:
                p.append(run_povray(pov, args.threads, tmp, home))
        rows.append((name, g, p, load_average()))
    print("SPD scenes, %dx%d, 1 spp, max depth 5, %d threads; median of %d runs each, glint and POV-Ray taking turns"
          % (SIZE, SIZE, args.threads, args.runs))
    print("load = glint load+build / POV-Ray parse+bounding; trace = glint render / POV-Ray trace; wall = process start to exit")
    print("load avg = the 1-minute load average after the scene's runs (other processes slow both programs)")
    hdr = "%-8s %9s %9s %9s %9s | %9s %9s %9s | %8s %8s | %8s" % (
        "scene", "glint ld", "trace", "write", "wall", "pov ld", "trace", "wall", "trace x", "wall x", "load avg")
    print(hdr)
    logs = []
    for name, g, p, load in rows:
        line = "%-8s %9.3f %9.3f %9.3f %9.3f" % (name, med(g, "load"), med(g, "trace"), med(g, "write"), med(g, "wall"))
        if p:
            ratio = med(p, "wall") / med(g, "wall")
            logs.append(math.log(ratio))
            line += " | %9.3f %9.3f %9.3f | %7.2fx %7.2fx" % (
                med(p, "load"), med(p, "trace"), med(p, "wall"), med(p, "trace") / med(g, "trace"), ratio)
        print(line + " | %8s" % load)
    if logs:
        print("geometric mean of the wall-time ratios (POV-Ray / glint): %.2fx" % math.exp(sum(logs) / len(logs)))
    for name, g, _, _ in rows:
        r = g[0]["stats"]["rays"]
        print("%s rays (glint, 512x512): camera %d, camera hits %d, reflection %d, refraction %d, shadow %d, total %d"
              % (name, r["camera"], r["camera_hits"], r["reflection"], r["refraction"], r["shadow"], r["total"]))


def flakes(args, tmp):
    depths = [int(d) for d in args.flake_depths.split(",") if d]
    threads = [int(t) for t in args.flake_threads.split(",") if t]
    scenes = {}
    for d in depths:
        path = os.path.join(tmp, "flake%d.nff" % d)
        subprocess.run([sys.executable, os.path.join(HERE, "sphereflake.py"), str(d), "-o", path],
                       check=True, stderr=subprocess.DEVNULL)
        scenes[d] = path
    runs = {(d, t): [] for d in depths for t in threads}
    for i in range(args.flake_runs):
        for t in threads:
            for d in depths:
                print("sphereflake depth %d, %d thread(s): run %d/%d" % (d, t, i + 1, args.flake_runs), file=sys.stderr)
                runs[(d, t)].append(run_glint(args.glint, scenes[d], t, tmp))
    print()
    print("glint on sphereflakes (bench/sphereflake.py), %dx%d, 1 spp, max depth 5; median of %d runs;"
          " ns/ray = render phase / total rays" % (SIZE, SIZE, args.flake_runs))
    cols = "".join(" %10s %7s" % ("%dT ns/ray" % t, "rel") for t in threads)
    print("%-6s %10s %10s %9s %9s%s" % ("depth", "spheres", "rays", "load s", "build s", cols))
    base = {t: None for t in threads}
    for d in depths:
        spheres = sum(9 ** k for k in range(d + 1))
        first = runs[(d, threads[0])]
        st = [r["stats"]["seconds"] for r in first]
        line = "%-6d %10d %10d %9.3f %9.3f" % (d, spheres, first[0]["rays"], statistics.median(s["load"] for s in st),
                                                statistics.median(s["build"] for s in st))
        for t in threads:
            ns = statistics.median(r["trace"] / r["rays"] * 1e9 for r in runs[(d, t)])
            base[t] = base[t] or ns
            line += " %10.1f %6.2fx" % (ns, ns / base[t])
        print(line)


def load_average():
    return open("/proc/loadavg").read().split()[0]


def write_stand_ins(names, tmp):
    """bench/spd_scenes.py's stand-ins, NAME.nff and NAME.pov, into tmp/stand-ins; their .nff paths."""
    folder = os.path.join(tmp, "stand-ins")
    subprocess.run([sys.executable, os.path.join(HERE, "spd_scenes.py"), folder, "--scenes", ",".join(names)],
                   check=True, stdout=subprocess.DEVNULL)
    return [os.path.join(folder, n + ".nff") for n in names]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__.split("\n\n", 2)[2])
    ap.add_argument("glint", help="the glint binary")
    ap.add_argument("scenes", nargs="*", help="SPD scenes (.nff with the .pov beside it); default: bench/spd/balls, tetra")
    ap.add_argument("--runs", type=int, default=5, help="runs of each program per scene (default 5)")
    ap.add_argument("--threads", type=int, default=2, help="threads for both programs (default 2)")
    ap.add_argument("--no-povray", action="store_true", help="time glint alone")
    ap.add_argument("--stand-ins", nargs="?", const=STAND_INS, default="", metavar="NAMES",
                    help="also time bench/spd_scenes.py's stand-ins (comma separated; default %s)" % STAND_INS)
    ap.add_argument("--flake-depths", default="2,3,4,5,6",
                    help="sphereflake depths, comma separated, '' for none (default 2,3,4,5,6: 91 to 597,871 spheres)")
    ap.add_argument("--flake-threads", default="1,2", help="thread counts for the sphereflakes (default 1,2)")
    ap.add_argument("--flake-runs", type=int, default=3, help="runs per sphereflake and thread count (default 3)")
    args = ap.parse_args()
    if not os.path.isfile(args.glint) or not os.access(args.glint, os.X_OK):
        sys.exit("error: glint binary not found or not executable: %s" % args.glint)
    args.glint = os.path.abspath(args.glint)
    args.scenes = [os.path.abspath(s) for s in (args.scenes or DEFAULT_SCENES)]
    for s in args.scenes:
        if not s.lower().endswith(".nff") or not os.path.isfile(s):
            sys.exit("error: not an .nff file: %s" % s)
        if not args.no_povray and not os.path.isfile(os.path.splitext(s)[0] + ".pov"):
            sys.exit("error: need %s beside it" % (os.path.splitext(s)[0] + ".pov"))
    if not args.no_povray and shutil.which("povray") is None:
        sys.exit("error: povray not found (Debian: apt-get install povray)")
    stand_ins = [n for n in args.stand_ins.split(",") if n]
    for n in stand_ins:
        if n not in STAND_INS.split(","):
            sys.exit("error: unknown stand-in %r (expected some of %s)" % (n, STAND_INS))
    if args.runs < 1 or args.flake_runs < 1:
        sys.exit("error: --runs and --flake-runs must be at least 1")
    print("machine load before the runs: %s" % open("/proc/loadavg").read().split()[:3], file=sys.stderr)
    # under /tmp: POV-Ray's default I/O security settings let it write there
    tmp = tempfile.mkdtemp(prefix="spd-vs-povray.", dir="/tmp")
    try:
        if stand_ins:
            args.scenes += write_stand_ins(stand_ins, tmp)
        if args.scenes:
            compare(args, tmp)
        if args.flake_depths:
            flakes(args, tmp)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
