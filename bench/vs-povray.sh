#!/usr/bin/env bash
# Time glint against POV-Ray 3.7 on the benchmark scenes.
#
#   vs-povray.sh GLINT_BINARY [scene...]
#   e.g. bench/vs-povray.sh build/glint            (from the repository's root)
#
# scene: a name (spheres, bunny, terrain; looked up in $BENCH_SCENES, default
# bench-scenes/ next to this script, generated with make_bench.py if missing)
# or a path to NAME.json / NAME.pov / NAME (both files must exist).
# For each scene, glint and POV-Ray are run $RUNS times each (default 3),
# alternating; the minimum wall time of each is reported:
#   GLINT render NAME.json -o OUT.png --threads $THREADS --quiet $GLINT_ARGS
#   povray -D -A +WT$THREADS +W<w> +H<h> +OOUT.png NAME.pov     (size from NAME.json)
# THREADS defaults to 2.  Exit status: 0 ok, 1 glint failed, 2 usage, 3 POV-Ray failed.
# Needs bash, coreutils, python3 (standard library) and povray.
set -u

usage() { echo "usage: $0 GLINT_BINARY [scene...]   (env: RUNS=3 THREADS=2 BENCH_SCENES=dir GLINT_ARGS=...)" >&2; exit 2; }
[ $# -ge 1 ] || usage
case "$1" in -h|--help) usage;; esac

KIT=$(cd "$(dirname "$0")" && pwd)
GLINT=$1; shift
if [[ "$GLINT" != */* ]]; then GLINT=$(command -v "$GLINT" || echo "$GLINT"); fi
[ -x "$GLINT" ] && [ -f "$GLINT" ] || { echo "error: glint binary not found or not executable: $GLINT" >&2; exit 2; }
GLINT=$(cd "$(dirname "$GLINT")" && pwd)/$(basename "$GLINT")
command -v povray >/dev/null || { echo "error: povray not found (Debian/Ubuntu: apt-get install povray)" >&2; exit 2; }
command -v python3 >/dev/null || { echo "error: python3 not found" >&2; exit 2; }

RUNS=${RUNS:-3}
THREADS=${THREADS:-2}
SCENE_DIR=${BENCH_SCENES:-$KIT/bench-scenes}
read -r -a GLINT_EXTRA <<< "${GLINT_ARGS:-}"
[ $# -gt 0 ] || set -- spheres bunny terrain

# under /tmp: POV-Ray's default I/O security config lets it write there
TMP=$(mktemp -d /tmp/vs-povray.XXXXXX) || exit 2
trap 'rm -rf "$TMP"' EXIT
# An empty user config silences POV-Ray's "cannot open the user configuration file" warning
# (and keeps a personal ~/.povray config out of the measurement).
mkdir -p "$TMP/home/.povray/3.7" && : > "$TMP/home/.povray/3.7/povray.conf"

now() { date +%s.%N; }

# resolve the scene arguments to absolute base paths (without extension)
BASES=()
for s in "$@"; do
  case "$s" in
    *.json|*.pov) b=${s%.*} ;;
    */*)          b=$s ;;
    *)            b=$SCENE_DIR/$s ;;
  esac
  if [ ! -f "$b.json" ] || [ ! -f "$b.pov" ]; then
    n=$(basename "$b")
    if [[ "$s" != */* && "$s" != *.* ]] && [[ " spheres bunny terrain " == *" $n "* ]]; then
      echo "generating $n into $SCENE_DIR ..." >&2
      python3 "$KIT/make_bench.py" -o "$SCENE_DIR" --only "$n" >&2 || exit 2
    else
      echo "error: need $b.json and $b.pov" >&2; exit 2
    fi
  fi
  BASES+=("$(cd "$(dirname "$b")" && pwd)/$(basename "$b")")
done

RESULTS=$TMP/results.tsv
: > "$RESULTS"
for b in "${BASES[@]}"; do
  name=$(basename "$b")
  read -r W H < <(python3 -c 'import json,sys; r=json.load(open(sys.argv[1],encoding="utf-8-sig")).get("render",{}); print(r.get("width",640), r.get("height",480))' "$b.json") \
    || { echo "error: cannot read $b.json" >&2; exit 2; }
  gt=(); pt=()
  for ((i = 1; i <= RUNS; i++)); do
    echo "$name: run $i/$RUNS" >&2
    rm -f "$TMP/x.png"
    t0=$(now)
    "$GLINT" render "$b.json" -o "$TMP/x.png" --threads "$THREADS" --quiet "${GLINT_EXTRA[@]}" > "$TMP/glint.log" 2>&1
    rc=$?
    t1=$(now)
    if [ $rc -ne 0 ] || [ ! -s "$TMP/x.png" ]; then
      echo "error: glint failed on $b.json (exit $rc$([ -s "$TMP/x.png" ] || echo ', no output image')):" >&2
      tail -n 20 "$TMP/glint.log" >&2
      exit 1
    fi
    gt+=("$t0 $t1")
    rm -f "$TMP/y.png"
    t0=$(now)
    (cd "$(dirname "$b")" && HOME="$TMP/home" povray -D -A +WT"$THREADS" +W"$W" +H"$H" +O"$TMP/y.png" "$name.pov") > "$TMP/pov.log" 2>&1
    rc=$?
    t1=$(now)
    if [ $rc -ne 0 ] || [ ! -s "$TMP/y.png" ]; then
      echo "error: povray failed on $b.pov (exit $rc):" >&2
      tail -n 20 "$TMP/pov.log" >&2
      exit 3
    fi
    pt+=("$t0 $t1")
  done
  printf '%s\t%s\t%s\n' "$name" "$(IFS=,; echo "${gt[*]}")" "$(IFS=,; echo "${pt[*]}")" >> "$RESULTS"
done

python3 - "$RESULTS" "$THREADS" "$RUNS" <<'EOF'
import math, sys
rows = []
for line in open(sys.argv[1]):
    name, g, p = line.rstrip("\n").split("\t")
    best = lambda s: min(float(b) - float(a) for a, b in (x.split() for x in s.split(",")))
    rows.append((name, best(g), best(p)))
print("threads %s, min of %s runs, wall seconds (process start to exit)" % (sys.argv[2], sys.argv[3]))
print("%-12s %10s %10s %8s" % ("scene", "glint s", "povray s", "ratio"))
for n, g, p in rows:
    print("%-12s %10.3f %10.3f %7.2fx" % (n, g, p, p / g))
geo = math.exp(sum(math.log(p / g) for _, g, p in rows) / len(rows))
print("geomean speedup vs POV-Ray: %.2fx" % geo)
EOF
