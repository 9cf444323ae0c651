#!/usr/bin/python3
"""glint against Tachyon on the same scenes: the pictures checked, then timed.

    bench/vs-tachyon.py GLINT_BINARY [SCENE.nff|SCENE.json ...] [options]
    e.g. bench/vs-tachyon.py build/glint --check-only --threads 1
                        (pictures only: balls, tetra, the stand-ins rings, teapot,
                         tree, and make_bench.py's spheres and bunny)
         bench/vs-tachyon.py build/glint --runs 5 --threads 1,2
         bench/vs-tachyon.py build/glint --stand-ins '' --bench terrain

Scenes: the SCENE files given (default bench/spd/balls.nff and tetra.nff),
then bench/spd_scenes.py's stand-ins (--stand-ins NAMES, default all five;
a scene with a transmitting material, T > 0 in the NFF, is left out:
gears and mount, as Tachyon has no refraction), then make_bench.py's glint
JSON scenes (--bench NAMES, default spheres,bunny; terrain, 1M triangles,
only when asked for). '' for none. Needs tachyon (Debian: apt-get install
tachyon-bin-nox).

For each scene, glint's own JSON (for an NFF file, what `glint convert`
writes) is the scene. This script writes the same scene in Tachyon's .dat
language and renders both, at the scene's size times --scale:

    GLINT render S.json -o OUT --width W --height H --spp 1 --max-depth D --threads T
    tachyon S.dat -o OUT -format PPM -numthreads T -aasamples 0 -normalfixup guess
            -shade_phong          (-shade_blinn for a blinn-phong scene)

1. Check (always; --check-only stops here): glint writes .pfm, quantized to
   8 bits the way Tachyon quantizes ((int)(x * 255), clamped); a pixel is
   background when every channel is within one step of the background
   color. The hit/background masks must agree on at least 98% of the
   pixels (else the exit status is 1). Also printed: the pixels whose
   colors agree within 2% (5/255) in every channel; on scenes without
   background pixels (balls, rings, spheres, terrain: a floor fills the
   view) the masks agree trivially and this column is the evidence.
   Side-by-side pictures, glint | Tachyon (each at most 256 pixels wide or
   high, both sRGB-encoded from the same 8-bit values), go to
   docs/img/vs-tachyon-<scene>.png (--img-dir).
2. Time (--runs N, default 5, for each of --threads, default 2; a list
   such as 1,2 times each): glint and Tachyon take turns, both writing an
   8-bit PPM. Printed per scene, medians over the runs: glint's load+build
   and render phases (its stderr summary line) against Tachyon's "Scene
   Parsing" + "Preprocessing" and "Ray Tracing Time", the wall time of each
   process (start to exit), the ratios Tachyon / glint, and at the end the
   geometric means of the ratios.

Why the comparison is fair: both programs trace the same rays through the
same geometry and shade them with the same formula (Tachyon 0.99, Debian's
0.99~b6; its source, not only its manual, decides the points below).

- Camera: Tachyon's image plane lies one unit along VIEWDIR and is 1/ZOOM
  high (ASPECTRATIO 1 means square pixels, the width following from W/H),
  so ZOOM = 0.5 / tan(fov_y / 2): ZOOM 1 is 53.13 degrees vertically, not
  the 90 of its manual. Two more things differ: Tachyon's right vector is
  up x view (glint: view x up), so its picture is the mirror image of
  glint's, and it shoots pixel (x, y) through the plane point (x + 1,
  y + 1) pixel sizes from the lower left corner, not (x + 0.5, y + 0.5).
  The .dat therefore also gives a FRUSTUM (0.99 reads it as left right
  bottom top, in the image plane at distance 1) that runs from right to
  left and is shifted by half a pixel: Tachyon's ray through each pixel is
  then glint's ray through that pixel's center. Checked: on a test scene of
  spheres and a polygon (no reflection depth limit reached) Tachyon's
  image equals glint's, quantized, in every pixel and channel; with the
  frustum half a pixel off, 3% of the pixels differ. ZOOM is written too
  (the parser wants it; the frustum overrides it).
- Lights: point lights as LIGHT with RAD 0 (invisible: no extra object),
  directional lights as DIRECTIONAL_LIGHT (the same direction: the way the
  light travels). Tachyon has no ambient light; a texture has AMBIENT ka
  times its COLOR. With COLOR = R_d / max(R_d), DIFFUSE = max(R_d) and
  AMBIENT = R_a * (sum of the lights' L_a) / COLOR, Tachyon's
  COLOR * (DIFFUSE * sum(L n.l) + AMBIENT) is exactly glint's
  sum(R_a L_a) + sum(R_d L_d n.l) whenever R_a is a multiple of R_d
  (NFF: R_a = R_d; make_bench.py: gray).
- Highlights: PHONG PLASTIC R_s (the light's color times R_s, untinted:
  glint's R_s L_s) with PHONG_SIZE = shininess, and -shade_phong, whose
  formula is glint's max(0, r.v)^alpha with r = 2(n.l)n - l (-shade_blinn
  for blinn-phong: max(0, n.h)^alpha; Tachyon's default is Blinn's).
  Mirror reflection: SPECULAR = reflectivity (Tachyon's reflected-ray
  weight, untinted). RAYDEPTH = max_depth, both counting the camera ray as
  level 1. Shadows (-fullshade, Tachyon's default), no antialiasing
  (ANTIALIASING 0, -aasamples 0), the same resolution and BACKGROUND.
- Geometry: spheres, planes, triangles, finite cylinders (FCYLINDER BASE
  APEX: 0.99's parser wants these, not the manual's CENTER AXIS; RING caps
  when glint's has caps), disks (RING) and untransformed boxes (BOX) are
  Tachyon's own exact primitives. Polygons are cut into a fan of TRIs from
  vertex 0 (STRIs with the vertex normals for an NFF `pp`: glint
  interpolates within the same fan triangles); a concave one by ear
  clipping. Meshes are TRIs (flat) or STRIs with glint's vertex normals
  (smooth: the file's, else the angle-weighted average at each vertex).
  Tachyon turns an STRI's normal toward the viewer by the triangle's
  winding, glint by the interpolated normal itself: -normalfixup guess is
  glint's rule (without it teapot's handle and spout, wound against their
  normals, are dark).

What is not matched:

- Cones: Tachyon has none, so each cone's side is --cone-segments (16)
  segments of two STRIs with the cone's normals, its radius enlarged by
  the factor that gives the polygon the circle's area (the silhouette is
  within about 1% of the radius), caps as RINGs. For tree this is 32
  triangles per cone against glint's one analytic cone: Tachyon does
  different work there, so its tree times are not like for like.
- Depth limit: where a reflected ray is not cast (beyond RAYDEPTH), Tachyon
  adds k * background, glint nothing: deep interreflections differ a
  little in color (balls: 95.6% of the pixels within 5/255; 99.8% with a
  black background).
- Colors: glint's light has separate L_d and L_s (Tachyon: one COLOR; the
  scenes here have L_d = L_s); color-valued reflectivity and specular
  (Tachyon: numbers; averaged) and an ambient that is not a multiple of the
  diffuse color (averaged) are noted; Tachyon's ATTENUATION (glint's
  formula) scales the diffuse term only, not the highlight (noted). Tachyon
  writes linear values, glint's PNGs are sRGB.
- Not written at all (the scene is skipped with the reason): refraction
  and fresnel, spot and area lights, textures, non-uniform scales of
  quadrics, orthographic cameras, .ply/.gltf meshes. An OBJ's own .mtl
  materials are not read: a mesh without a `material` gets glint's default
  material (noted). Both render 1 sample per pixel whatever the scene says.

So only the masks must agree (the geometry and the camera), not the
colors; the color agreement is printed to show how close the shading is.
"""

import argparse
import json
import math
import os
import re
import shutil
import statistics
import struct
import subprocess
import sys
import tempfile
import time
import zlib

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from spd_scenes import add, cross, dot, length, mul, sub, triangulate  # noqa: E402  (vectors; ear clipping)

DEFAULT_SCENES = [os.path.join(HERE, "spd", "balls.nff"), os.path.join(HERE, "spd", "tetra.nff")]
STAND_INS = "gears,mount,rings,teapot,tree"
BENCH = "spheres,bunny"
BENCH_ALL = "spheres,bunny,terrain"
DEFAULT_IMG_DIR = os.path.join(HERE, os.pardir, "docs", "img")
MASK_MIN = 0.98          # masks must agree on at least this fraction of the pixels
COLOR_TOL = 5            # 8-bit steps (linear) for the color agreement printed
THUMB = 256              # side-by-side pictures: each half at most this wide or high


class Unsupported(Exception):
    """The scene uses something Tachyon's .dat cannot say (the scene is skipped)."""


# ---------------------------------------------------------------------------
# small vector helpers


def normalize(a):
    n = length(a)
    if n == 0:
        raise Unsupported("zero-length vector")
    return (a[0] / n, a[1] / n, a[2] / n)


def color3(c, default):
    """A glint color (number or [r, g, b]) as a 3-tuple."""
    if c is None:
        c = default
    if isinstance(c, dict):
        raise Unsupported("textured reflectance (%s)" % ", ".join(sorted(c)))
    if isinstance(c, (int, float)):
        return (float(c),) * 3
    return tuple(float(x) for x in c)


def g(x):
    return "%.9g" % x


def gv(v):
    return "%s %s %s" % (g(v[0]), g(v[1]), g(v[2]))


# ---------------------------------------------------------------------------
# transforms (glint's: scale, then rotate, then translate; or a row-major matrix)


def transform_matrix(t):
    if t is None:
        return None
    if "matrix" in t:
        m = [float(x) for x in t["matrix"]]
        return [m[0:4], m[4:8], m[8:12], m[12:16]]
    s = t.get("scale", 1)
    s = (float(s),) * 3 if isinstance(s, (int, float)) else tuple(float(x) for x in s)
    r = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    if "rotate" in t:
        ax = normalize(tuple(float(x) for x in t["rotate"]["axis"]))
        a = math.radians(float(t["rotate"]["angle"]))
        c, si, x, y, z = math.cos(a), math.sin(a), ax[0], ax[1], ax[2]
        r = [[c + x * x * (1 - c), x * y * (1 - c) - z * si, x * z * (1 - c) + y * si],
             [y * x * (1 - c) + z * si, c + y * y * (1 - c), y * z * (1 - c) - x * si],
             [z * x * (1 - c) - y * si, z * y * (1 - c) + x * si, c + z * z * (1 - c)]]
    tr = tuple(float(x) for x in t.get("translate", (0, 0, 0)))
    return [[r[i][0] * s[0], r[i][1] * s[1], r[i][2] * s[2], tr[i]] for i in range(3)] + [[0.0, 0.0, 0.0, 1.0]]


def xf_point(m, p):
    if m is None:
        return tuple(p)
    return tuple(m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2] + m[i][3] for i in range(3))


def xf_vector(m, v):
    if m is None:
        return tuple(v)
    return tuple(m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2] for i in range(3))


def xf_normal(m, n):
    """The inverse transpose of m's 3x3 part times n (not normalized)."""
    if m is None:
        return tuple(n)
    a = [row[:3] for row in m[:3]]
    # cofactor matrix = det * inverse transpose; the scale does not matter for a normal
    cof = [[a[1][1] * a[2][2] - a[1][2] * a[2][1], a[1][2] * a[2][0] - a[1][0] * a[2][2], a[1][0] * a[2][1] - a[1][1] * a[2][0]],
           [a[0][2] * a[2][1] - a[0][1] * a[2][2], a[0][0] * a[2][2] - a[0][2] * a[2][0], a[0][1] * a[2][0] - a[0][0] * a[2][1]],
           [a[0][1] * a[1][2] - a[0][2] * a[1][1], a[0][2] * a[1][0] - a[0][0] * a[1][2], a[0][0] * a[1][1] - a[0][1] * a[1][0]]]
    det = a[0][0] * cof[0][0] + a[0][1] * cof[0][1] + a[0][2] * cof[0][2]
    sgn = 1.0 if det > 0 else -1.0
    return tuple(sgn * (cof[i][0] * n[0] + cof[i][1] * n[1] + cof[i][2] * n[2]) for i in range(3))


def uniform_scale(m, what):
    """The scale factor of a similarity transform (Tachyon's quadrics cannot be stretched)."""
    if m is None:
        return 1.0
    cols = [length((m[0][j], m[1][j], m[2][j])) for j in range(3)]
    cols_dot = [dot((m[0][i], m[1][i], m[2][i]), (m[0][j], m[1][j], m[2][j])) for i, j in ((0, 1), (0, 2), (1, 2))]
    if max(cols) - min(cols) > 1e-9 * max(cols) or max(abs(d) for d in cols_dot) > 1e-9 * max(cols) ** 2:
        raise Unsupported("%s with a non-uniform scale or shear (Tachyon has no ellipsoids)" % what)
    return cols[0]


# ---------------------------------------------------------------------------
# meshes (glint's OBJ rules, as far as the bench scenes need them)


def read_obj(path):
    """Vertices, normals, triangles (vertex index triples) and the triangles' normal index triples
    (None for a corner without one; the whole list None when the file has no normals) of an OBJ file."""
    vs, vns, tris, ntris = [], [], [], []
    with open(path, encoding="utf-8-sig", errors="replace") as fh:
        for line in fh:
            t = line.split()
            if not t or t[0].startswith("#"):
                continue
            if t[0] == "v":
                vs.append((float(t[1]), float(t[2]), float(t[3])))
            elif t[0] == "vn":
                vns.append((float(t[1]), float(t[2]), float(t[3])))
            elif t[0] == "f":
                vi, ni = [], []
                for w in t[1:]:
                    parts = w.split("/")
                    i = int(parts[0])
                    vi.append(i - 1 if i > 0 else len(vs) + i)
                    if len(parts) == 3 and parts[2]:
                        i = int(parts[2])
                        ni.append(i - 1 if i > 0 else len(vns) + i)
                    else:
                        ni.append(None)
                n = len(vi)
                if n < 3:
                    continue
                if n == 4:
                    # glint: a quad on its shorter diagonal
                    p = [vs[i] for i in vi]
                    cut = ((0, 1, 2), (0, 2, 3)) if length(sub(p[0], p[2])) <= length(sub(p[1], p[3])) \
                        else ((0, 1, 3), (1, 2, 3))
                else:
                    cut = [(0, k, k + 1) for k in range(1, n - 1)]
                for a, b, c in cut:
                    tris.append((vi[a], vi[b], vi[c]))
                    ntris.append((ni[a], ni[b], ni[c]))
    return vs, vns, tris, (ntris if vns else None)


def angle_weighted_normals(vs, tris):
    """Per-vertex normals: the angle-weighted average of the normals of the faces sharing the index."""
    acc = [[0.0, 0.0, 0.0] for _ in vs]
    for idx in tris:
        p = [vs[i] for i in idx]
        fn = cross(sub(p[1], p[0]), sub(p[2], p[0]))
        fl = length(fn)
        if fl == 0:
            continue
        fn = mul(fn, 1.0 / fl)
        for k in range(3):
            e1, e2 = sub(p[(k + 1) % 3], p[k]), sub(p[(k + 2) % 3], p[k])
            l1, l2 = length(e1), length(e2)
            if l1 == 0 or l2 == 0:
                continue
            ang = math.acos(max(-1.0, min(1.0, dot(e1, e2) / (l1 * l2))))
            for j in range(3):
                acc[idx[k]][j] += fn[j] * ang
    return [tuple(a) for a in acc]


# ---------------------------------------------------------------------------
# glint JSON -> Tachyon .dat


class DatWriter:
    def __init__(self, scene, scene_dir, width, height, cone_segments):
        self.scene, self.dir = scene, scene_dir
        self.w, self.h = width, height
        self.cone_segments = cone_segments
        self.notes = []
        self.textures = {}   # glint material name (None: default) -> TEXDEF name
        self.counts = {}

    def note(self, text):
        if text not in self.notes:
            self.notes.append(text)

    def count(self, what, n=1):
        self.counts[what] = self.counts.get(what, 0) + n

    # -- camera ---------------------------------------------------------------

    def camera(self):
        cam = self.scene["camera"]
        if cam.get("type", "perspective") != "perspective":
            raise Unsupported("orthographic camera")
        pos = tuple(float(x) for x in cam["position"])
        view = normalize(sub(tuple(float(x) for x in cam["look_at"]), pos))
        up = tuple(float(x) for x in cam.get("up", (0, 1, 0)))
        fov = math.radians(float(cam.get("fov_y", 45)))
        py = 2 * math.tan(fov / 2)          # glint's image plane at distance 1: height
        px = py * self.w / self.h           # and width (square pixels)
        # Tachyon: ray (x, y) for x = 1..W, y = 1..H (y = 1 the bottom row) goes to
        # lowleft + x (right-left)/W along its right vector (up x view = -glint's right)
        # + y (top-bottom)/H along up. Solve for glint's pixel centers:
        left = 0.5 * px * (1 + 1.0 / self.w)
        right = -0.5 * px * (1 - 1.0 / self.w)
        top = 0.5 * py * (1 - 1.0 / self.h)
        bottom = -0.5 * py * (1 + 1.0 / self.h)
        zoom = 0.5 / math.tan(fov / 2)
        depth = int(self.scene.get("render", {}).get("max_depth", 5))
        return ("CAMERA\n  ZOOM %s\n  ASPECTRATIO 1.0\n  ANTIALIASING 0\n  RAYDEPTH %d\n"
                "  CENTER %s\n  VIEWDIR %s\n  UPDIR %s\n  FRUSTUM %s %s %s %s\nEND_CAMERA\n\n"
                % (g(zoom), depth, gv(pos), gv(view), gv(up), g(left), g(right), g(bottom), g(top)))

    # -- lights ---------------------------------------------------------------

    def lights(self):
        out = []
        amb = [0.0, 0.0, 0.0]
        for i, li in enumerate(self.scene.get("lights", [])):
            kind = li.get("type")
            if kind == "ambient":
                a = color3(li.get("ambient", li.get("color")), 0.0)
                amb = [amb[k] + a[k] for k in range(3)]
                continue
            if kind not in ("point", "directional"):
                raise Unsupported("a %s light" % kind)
            a = color3(li.get("ambient"), 0.0)
            amb = [amb[k] + a[k] for k in range(3)]
            if "color" in li:
                ld = ls = color3(li["color"], 1.0)
            else:
                ld, ls = color3(li.get("diffuse"), 1.0), color3(li.get("specular"), 1.0)
            if max(abs(ld[k] - ls[k]) for k in range(3)) > 1e-12:
                self.note("light %d: specular %s differs from diffuse %s; Tachyon's one COLOR is the diffuse"
                          % (i, gv(ls), gv(ld)))
            if kind == "point":
                att = ""
                if "attenuation" in li:
                    c, l, q = (float(x) for x in li["attenuation"])
                    att = " ATTENUATION CONSTANT %s LINEAR %s QUADRATIC %s" % (g(c), g(l), g(q))
                    self.note("light %d: attenuation: Tachyon attenuates the diffuse term only, not the highlight" % i)
                out.append("LIGHT CENTER %s RAD 0%s COLOR %s\n" % (gv(li["position"]), att, gv(ld)))
            else:
                out.append("DIRECTIONAL_LIGHT DIRECTION %s COLOR %s\n" % (gv(li["direction"]), gv(ld)))
        self.ambient = tuple(amb)
        return "".join(out) + "\n"

    # -- materials ------------------------------------------------------------

    def texdef(self, name, m):
        """The TEXDEF of glint material m (None: the default material)."""
        m = m or {}
        if float(m.get("transparency", 0)) > 0:
            raise Unsupported("material %s: transparency (Tachyon has no refraction)" % name)
        if m.get("fresnel"):
            raise Unsupported("material %s: fresnel" % name)
        ra = color3(m.get("ambient"), 0.0)
        rd = color3(m.get("diffuse"), 0.8)
        rs = color3(m.get("specular"), 0.0)
        shine = float(m.get("shininess", 32))
        refl = color3(m.get("reflectivity"), 0.0)
        a = tuple(ra[k] * self.ambient[k] for k in range(3))     # glint's ambient term R_a * sum L_a
        kd = max(rd)
        if kd > 0:
            col = tuple(c / kd for c in rd)
        elif max(a) > 0:
            col = tuple(c / max(a) for c in a)
        else:
            col = (1.0, 1.0, 1.0)
        ka = 0.0
        if max(a) > 0:
            ratios = [a[k] / col[k] for k in range(3) if col[k] > 0]
            if any(a[k] > 0 and col[k] == 0 for k in range(3)) or max(ratios) - min(ratios) > 1e-9 * max(ratios):
                self.note("material %s: ambient %s is not a multiple of the diffuse color; averaged" % (name, gv(a)))
                ka = sum(a) / max(sum(col), 1e-30)
            else:
                ka = sum(ratios) / len(ratios)
        phong = ""
        if max(rs) > 0:
            if max(rs) - min(rs) <= 1e-12:
                phong = "PHONG PLASTIC %s PHONG_SIZE %s " % (g(rs[0]), g(shine))
            else:
                ratios = [rs[k] / col[k] for k in range(3) if col[k] > 0]
                if all(col[k] > 0 or rs[k] == 0 for k in range(3)) and max(ratios) - min(ratios) <= 1e-9 * max(ratios):
                    phong = "PHONG METAL %s PHONG_SIZE %s " % (g(ratios[0]), g(shine))   # tinted by COLOR
                else:
                    self.note("material %s: colored specular %s; averaged" % (name, gv(rs)))
                    phong = "PHONG PLASTIC %s PHONG_SIZE %s " % (g(sum(rs) / 3), g(shine))
        if max(refl) - min(refl) > 1e-12:
            self.note("material %s: colored reflectivity %s; averaged" % (name, gv(refl)))
        spec = sum(refl) / 3
        tex = "t%d" % (len(self.textures) + 1)
        return tex, ("TEXDEF %s AMBIENT %s DIFFUSE %s SPECULAR %s OPACITY 1 %sCOLOR %s TEXFUNC 0\n"
                     % (tex, g(ka), g(kd), g(spec), phong, gv(col)))

    def texture(self, name, out):
        if name not in self.textures:
            mats = self.scene.get("materials", {})
            if name is not None and name not in mats:
                raise Unsupported("unknown material %r" % name)
            tex, text = self.texdef(name if name is not None else "(default)", mats.get(name) if name else None)
            out.write(text)
            self.textures[name] = tex
        return self.textures[name]

    # -- objects --------------------------------------------------------------

    def tri(self, out, tex, a, b, c, na=None, nb=None, nc=None):
        if length(cross(sub(b, a), sub(c, a))) == 0:
            return
        if na is None:
            out.write("TRI V0 %s V1 %s V2 %s %s\n" % (gv(a), gv(b), gv(c), tex))
            self.count("TRI")
        else:
            out.write("STRI V0 %s V1 %s V2 %s N0 %s N1 %s N2 %s %s\n"
                      % (gv(a), gv(b), gv(c), gv(na), gv(nb), gv(nc), tex))
            self.count("STRI")

    def ring(self, out, tex, center, normal, inner, outer):
        out.write("RING CENTER %s NORMAL %s INNER %s OUTER %s %s\n" % (gv(center), gv(normal), g(inner), g(outer), tex))
        self.count("RING")

    def cone_side(self, out, tex, base, apex, rb, ra):
        """A cone's side as cone_segments segments of two STRIs with the cone's own normals."""
        n = self.cone_segments
        axis = sub(apex, base)
        h = length(axis)
        w = mul(axis, 1.0 / h)
        u = normalize(cross(w, (1.0, 0.0, 0.0) if abs(w[0]) < 0.9 else (0.0, 1.0, 0.0)))
        v = cross(w, u)
        k = math.sqrt(2 * math.pi / (n * math.sin(2 * math.pi / n)))   # polygon area = circle area
        ring_b, ring_a, norms = [], [], []
        for i in range(n):
            t = 2 * math.pi * i / n
            d = add(mul(u, math.cos(t)), mul(v, math.sin(t)))
            ring_b.append(add(base, mul(d, rb * k)))
            ring_a.append(add(apex, mul(d, ra * k)))
            norms.append(normalize(add(mul(d, h), mul(w, rb - ra))))
        for i in range(n):
            j = (i + 1) % n
            if rb > 0:
                self.tri(out, tex, ring_b[i], ring_b[j], ring_a[j] if ra > 0 else apex, norms[i], norms[j], norms[j])
            if ra > 0:
                self.tri(out, tex, ring_b[i], ring_a[j], ring_a[i], norms[i], norms[j], norms[i])
        self.count("cone")

    def polygon(self, out, tex, verts, normals):
        n = len(verts)
        if normals is None:
            nrm = (0.0, 0.0, 0.0)
            for i in range(n):   # Newell
                a, b = verts[i], verts[(i + 1) % n]
                nrm = add(nrm, ((a[1] - b[1]) * (a[2] + b[2]), (a[2] - b[2]) * (a[0] + b[0]), (a[0] - b[0]) * (a[1] + b[1])))
            convex = all(dot(cross(sub(verts[(i + 1) % n], verts[i]), sub(verts[(i + 2) % n], verts[(i + 1) % n])), nrm)
                         >= 0 for i in range(n))
            tris = [(0, i, i + 1) for i in range(1, n - 1)] if convex else triangulate(verts)
            for a, b, c in tris:
                self.tri(out, tex, verts[a], verts[b], verts[c])
        else:
            for i in range(1, n - 1):
                self.tri(out, tex, verts[0], verts[i], verts[i + 1], normals[0], normals[i], normals[i + 1])
        self.count("polygon")

    def mesh(self, out, tex, o, m):
        smooth = o.get("smooth", True)
        if "file" in o:
            path = os.path.join(self.dir, o["file"])
            if not path.lower().endswith(".obj"):
                raise Unsupported("mesh file %s (only .obj is read here)" % o["file"])
            vs, vns, tris, ntris = read_obj(path)
            if "material" not in o:
                self.note("mesh %s: its .mtl materials are not read; glint's default material" % o["file"])
        else:
            vs = [tuple(float(x) for x in p) for p in o["vertices"]]
            tris = [tuple(int(i) for i in t) for t in o["triangles"]]
            vns = [tuple(float(x) for x in p) for p in o.get("normals", [])]
            ntris = tris if vns else None
        if m is not None:
            vs = [xf_point(m, p) for p in vs]
        if not smooth:
            for a, b, c in tris:
                self.tri(out, tex, vs[a], vs[b], vs[c])
            self.count("mesh")
            return
        vns = [xf_normal(m, n) for n in vns]
        computed = None
        for k, idx in enumerate(tris):
            p = [vs[i] for i in idx]
            ns = []
            for j in range(3):
                ni = ntris[k][j] if ntris is not None else None
                nv = vns[ni] if ni is not None else None
                if nv is None or length(nv) == 0:
                    if computed is None:
                        computed = angle_weighted_normals(vs, tris)
                    nv = computed[idx[j]]
                if length(nv) == 0:
                    nv = cross(sub(p[1], p[0]), sub(p[2], p[0]))
                ns.append(normalize(nv) if length(nv) > 0 else (0.0, 0.0, 1.0))
            self.tri(out, tex, p[0], p[1], p[2], *ns)
        self.count("mesh")

    def objects(self, out):
        for o in self.scene["objects"]:
            tex = self.texture(o.get("material"), out)
            kind = o["type"]
            m = transform_matrix(o.get("transform"))
            if kind == "sphere":
                s = uniform_scale(m, "sphere")
                out.write("SPHERE CENTER %s RAD %s %s\n" % (gv(xf_point(m, o["center"])), g(float(o["radius"]) * s), tex))
                self.count("SPHERE")
            elif kind == "plane":
                out.write("PLANE CENTER %s NORMAL %s %s\n"
                          % (gv(xf_point(m, o["point"])), gv(normalize(xf_normal(m, o["normal"]))), tex))
                self.count("PLANE")
            elif kind == "triangle":
                self.tri(out, tex, *[xf_point(m, p) for p in o["vertices"]])
            elif kind == "polygon":
                verts = [xf_point(m, p) for p in o["vertices"]]
                normals = None
                if "normals" in o:
                    normals = [normalize(xf_normal(m, normalize(tuple(float(x) for x in n)))) for n in o["normals"]]
                self.polygon(out, tex, verts, normals)
            elif kind == "box":
                lo, hi = tuple(float(x) for x in o["min"]), tuple(float(x) for x in o["max"])
                if m is None:
                    out.write("BOX MIN %s MAX %s %s\n" % (gv(lo), gv(hi), tex))
                    self.count("BOX")
                else:
                    c = [xf_point(m, (hi[0] if i & 1 else lo[0], hi[1] if i & 2 else lo[1], hi[2] if i & 4 else lo[2]))
                         for i in range(8)]
                    for q in ((0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)):
                        self.tri(out, tex, c[q[0]], c[q[1]], c[q[2]])
                        self.tri(out, tex, c[q[0]], c[q[2]], c[q[3]])
            elif kind in ("cylinder", "cone"):
                s = uniform_scale(m, kind)
                base, apex = xf_point(m, o["base"]), xf_point(m, o["apex"])
                if kind == "cylinder":
                    rb = ra = float(o["radius"]) * s
                else:
                    rb, ra = float(o["base_radius"]) * s, float(o["apex_radius"]) * s
                if rb == ra:
                    out.write("FCYLINDER BASE %s APEX %s RAD %s %s\n" % (gv(base), gv(apex), g(rb), tex))
                    self.count("FCYLINDER")
                else:
                    self.cone_side(out, tex, base, apex, rb, ra)
                if o.get("caps", True):
                    axis = normalize(sub(apex, base))
                    if rb > 0:
                        self.ring(out, tex, base, mul(axis, -1), 0, rb)
                    if ra > 0:
                        self.ring(out, tex, apex, axis, 0, ra)
            elif kind == "disk":
                s = uniform_scale(m, "disk")
                self.ring(out, tex, xf_point(m, o["center"]), normalize(xf_normal(m, o["normal"])),
                          float(o.get("inner_radius", 0)) * s, float(o["radius"]) * s)
            elif kind == "mesh":
                self.mesh(out, tex, o, m)
            else:
                raise Unsupported("object type %s" % kind)

    def write(self, path):
        r = self.scene.get("render", {})
        if int(r.get("samples_per_pixel", 1)) != 1:
            self.note("samples_per_pixel %s: both are rendered with 1" % r.get("samples_per_pixel"))
        if "animation" in self.scene:
            self.note("animation: frame 0 only")
        bg = color3(r.get("background"), 0.0)
        with open(path, "w") as out:
            out.write("BEGIN_SCENE\n  RESOLUTION %d %d\n\n" % (self.w, self.h))
            out.write(self.camera())
            out.write("BACKGROUND %s\n\n" % gv(bg))
            out.write(self.lights())
            self.objects(out)
            out.write("\nEND_SCENE\n")
        return bg


# ---------------------------------------------------------------------------
# images


def read_pfm(path):
    with open(path, "rb") as f:
        data = f.read()
    parts = data.split(b"\n", 3)
    if parts[0].strip() != b"PF":
        sys.exit("error: %s: not an RGB PFM" % path)
    w, h = (int(x) for x in parts[1].split())
    scale = float(parts[2])
    a = np.frombuffer(parts[3], dtype="<f4" if scale < 0 else ">f4", count=w * h * 3).reshape(h, w, 3)
    return a[::-1].astype(np.float64)      # rows bottom to top in the file


def read_ppm(path):
    with open(path, "rb") as f:
        data = f.read()
    m = re.match(rb"P6\s+(\d+)\s+(\d+)\s+(\d+)\s", data)
    if not m:
        sys.exit("error: %s: not a binary PPM" % path)
    w, h = int(m.group(1)), int(m.group(2))
    return np.frombuffer(data, dtype=np.uint8, count=w * h * 3, offset=m.end()).reshape(h, w, 3)


def quantize(x):
    """Tachyon's 8-bit quantization of linear values: (int)(x * 255), clamped to 0..255."""
    return np.clip(np.floor(np.asarray(x, dtype=np.float64) * 255.0), 0, 255).astype(np.int32)


def srgb8(lin8):
    x = lin8.astype(np.float64) / 255.0
    y = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
    return np.clip(np.round(y * 255.0), 0, 255).astype(np.uint8)


def shrink(img, size):
    """Box-filtered down by an integer factor to at most size pixels wide and high."""
    h, w = img.shape[:2]
    f = max(1, -(-max(w, h) // size))
    h2, w2 = h // f, w // f
    a = img[:h2 * f, :w2 * f].astype(np.float64).reshape(h2, f, w2, f, 3).mean(axis=(1, 3))
    return a


def write_png(path, rgb):
    h, w = rgb.shape[:2]
    raw = b"".join(b"\x00" + rgb[y].tobytes() for y in range(h))

    def chunk(tag, body):
        return struct.pack(">I", len(body)) + tag + body + struct.pack(">I", zlib.crc32(tag + body) & 0xffffffff)

    png = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
           + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(png)
    os.replace(tmp, path)


# ---------------------------------------------------------------------------
# running the two programs

GLINT_LINE = re.compile(r"render ([0-9.]+) s \(total ([0-9.]+) s: load ([0-9.]+), build ([0-9.]+), write ([0-9.]+)\)")
TACHYON_TIME = re.compile(r"^\s*(Scene Parsing|Preprocessing|Ray Tracing|Image I/O) Time:\s+([0-9.]+) seconds", re.M)


def run_glint(args, s, threads, out):
    if os.path.exists(out):
        os.remove(out)
    cmd = [args.glint, "render", s["json"], "-o", out, "--width", str(s["w"]), "--height", str(s["h"]),
           "--spp", "1", "--max-depth", str(s["depth"]), "--threads", str(threads)]
    t0 = time.perf_counter()
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    wall = time.perf_counter() - t0
    err = p.stderr.decode(errors="replace")
    if p.returncode != 0 or not os.path.exists(out):
        sys.exit("error: glint failed on %s (exit %d):\n%s" % (s["json"], p.returncode, err[-2000:]))
    m = GLINT_LINE.search(err)
    if not m:
        sys.exit("error: no 'render X s (total ...)' summary line in glint's stderr:\n%s" % err[-2000:])
    render, _, load, build, write = (float(x) for x in m.groups())
    return {"wall": wall, "load": load + build, "trace": render, "write": write}


def run_tachyon(args, s, threads, out):
    if os.path.exists(out):
        os.remove(out)
    cmd = [args.tachyon, s["dat"], "-o", out, "-format", "PPM", "-numthreads", str(threads), "-aasamples", "0",
           "-normalfixup", "guess", "-shade_blinn" if s["model"] == "blinn-phong" else "-shade_phong"]
    t0 = time.perf_counter()
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    wall = time.perf_counter() - t0
    log = p.stdout.decode(errors="replace")
    if p.returncode != 0 or not os.path.exists(out) or "Parse Error" in log or "Aborting render" in log:
        sys.exit("error: tachyon failed on %s (exit %d):\n%s" % (s["dat"], p.returncode, log[-2000:]))
    t = {k: float(v) for k, v in TACHYON_TIME.findall(log)}
    if "Ray Tracing" not in t:
        sys.exit("error: no 'Ray Tracing Time' in tachyon's output:\n%s" % log[-2000:])
    return {"wall": wall, "load": t.get("Scene Parsing", 0.0) + t.get("Preprocessing", 0.0),
            "trace": t["Ray Tracing"], "write": t.get("Image I/O", 0.0)}


# ---------------------------------------------------------------------------
# scenes


def prepare(args, path, tmp):
    """The scene's glint JSON and its Tachyon .dat; None (with the reason printed) when it cannot be written."""
    name = os.path.splitext(os.path.basename(path))[0]
    if path.lower().endswith(".nff"):
        js = os.path.join(tmp, name + ".json")
        p = subprocess.run([args.glint, "convert", path, "-o", js], stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
        if p.returncode != 0:
            sys.exit("error: glint convert failed on %s:\n%s" % (path, p.stdout.decode(errors="replace")))
    else:
        js = path
    with open(js, encoding="utf-8-sig") as f:
        scene = json.load(f)
    r = scene.get("render", {})
    w = max(1, int(round(int(r.get("width", 640)) * args.scale)))
    h = max(1, int(round(int(r.get("height", 480)) * args.scale)))
    dat = os.path.join(tmp, name + ".dat")
    wr = DatWriter(scene, os.path.dirname(os.path.abspath(js)), w, h, args.cone_segments)
    try:
        bg = wr.write(dat)
    except Unsupported as e:
        print("%s: skipped: %s" % (name, e))
        return None
    counts = ", ".join("%d %s" % (n, k) for k, n in sorted(wr.counts.items()))
    print("%s: %dx%d; Tachyon gets %s" % (name, w, h, counts))
    for n in wr.notes:
        print("  note: %s" % n)
    return {"name": name, "json": js, "dat": dat, "w": w, "h": h, "bg": bg,
            "depth": int(r.get("max_depth", 5)), "model": r.get("shading_model", "phong")}


def check(args, s, tmp):
    """Render both once; the mask agreement (and the side-by-side picture)."""
    threads = args.threads[0]
    gout, tout = os.path.join(tmp, "check-glint.pfm"), os.path.join(tmp, "check-tachyon.ppm")
    run_glint(args, s, threads, gout)
    run_tachyon(args, s, threads, tout)
    gi, ti = quantize(read_pfm(gout)), read_ppm(tout).astype(np.int32)
    if gi.shape != ti.shape:
        sys.exit("error: %s: glint's image is %s, Tachyon's %s" % (s["name"], gi.shape, ti.shape))
    bg = quantize(s["bg"])
    gm = np.all(np.abs(gi - bg) <= 1, axis=2)
    tm = np.all(np.abs(ti - bg) <= 1, axis=2)
    agree = float(np.mean(gm == tm))
    colors = float(np.mean(np.all(np.abs(gi - ti) <= COLOR_TOL, axis=2)))
    if args.img_dir:
        os.makedirs(args.img_dir, exist_ok=True)
        a, b = shrink(gi, THUMB), shrink(ti, THUMB)
        gap = np.full((a.shape[0], 4, 3), 255.0)
        side = srgb8(np.round(np.concatenate([a, gap, b], axis=1)).astype(np.int32))
        side[:, a.shape[1]:a.shape[1] + 4] = 255
        write_png(os.path.join(args.img_dir, "vs-tachyon-%s.png" % s["name"]), side)
    return {"agree": agree, "colors": colors, "bg_glint": float(gm.mean()), "bg_tachyon": float(tm.mean()),
            "glint_only": int(np.sum(~gm & tm)), "tachyon_only": int(np.sum(gm & ~tm))}


def med(runs, key):
    return statistics.median(r[key] for r in runs)


def timing(args, scenes, tmp):
    gout, tout = os.path.join(tmp, "glint.ppm"), os.path.join(tmp, "tachyon.ppm")
    for threads in args.threads:
        rows = []
        for s in scenes:
            g_runs, t_runs = [], []
            for i in range(args.runs):
                print("%s, %d thread(s): run %d/%d" % (s["name"], threads, i + 1, args.runs), file=sys.stderr)
                g_runs.append(run_glint(args, s, threads, gout))
                t_runs.append(run_tachyon(args, s, threads, tout))
            rows.append((s, g_runs, t_runs, open("/proc/loadavg").read().split()[0]))
        print()
        print("%d thread(s), 1 spp, median of %d runs each, glint and Tachyon taking turns" % (threads, args.runs))
        print("load = glint load+build / Tachyon scene parsing+preprocessing; trace = glint render / Tachyon"
              " Ray Tracing Time; wall = process start to exit; x = Tachyon / glint")
        print("%-8s %10s %9s %9s %9s | %9s %9s %9s | %8s %8s | %8s" % (
            "scene", "size", "glint ld", "trace", "wall", "tach ld", "trace", "wall", "trace x", "wall x", "load avg"))
        lt, lw = [], []
        for s, gr, tr, load in rows:
            rt, rw = med(tr, "trace") / med(gr, "trace"), med(tr, "wall") / med(gr, "wall")
            lt.append(math.log(rt))
            lw.append(math.log(rw))
            print("%-8s %10s %9.3f %9.3f %9.3f | %9.3f %9.3f %9.3f | %7.2fx %7.2fx | %8s" % (
                s["name"], "%dx%d" % (s["w"], s["h"]), med(gr, "load"), med(gr, "trace"), med(gr, "wall"),
                med(tr, "load"), med(tr, "trace"), med(tr, "wall"), rt, rw, load))
        print("geometric mean, Tachyon / glint (%d thread(s)): trace %.2fx, wall %.2fx"
              % (threads, math.exp(sum(lt) / len(lt)), math.exp(sum(lw) / len(lw))))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__.split("\n\n", 2)[2])
    ap.add_argument("glint", help="the glint binary")
    ap.add_argument("scenes", nargs="*", help="scenes, .nff or glint .json (default bench/spd/balls.nff, tetra.nff)")
    ap.add_argument("--stand-ins", default=STAND_INS, metavar="NAMES",
                    help="bench/spd_scenes.py stand-ins, comma separated, '' for none (default %s; those"
                         " with refraction are left out)" % STAND_INS)
    ap.add_argument("--bench", default=BENCH, metavar="NAMES",
                    help="make_bench.py scenes, comma separated, '' for none (default %s; also terrain)" % BENCH)
    ap.add_argument("--terrain-tris", type=int, default=1000000, help="terrain's triangles (default 1000000)")
    ap.add_argument("--runs", type=int, default=5, help="runs of each program per scene (default 5)")
    ap.add_argument("--threads", default="2", help="threads for both programs, or a list such as 1,2 (default 2);"
                                                    " the check uses the first")
    ap.add_argument("--check-only", action="store_true", help="only render once each and compare the pictures")
    ap.add_argument("--scale", type=float, default=1.0, help="image size factor on every scene's own size (default 1)")
    ap.add_argument("--cone-segments", type=int, default=16, help="segments of a cone's side for Tachyon (default 16)")
    ap.add_argument("--img-dir", default=DEFAULT_IMG_DIR,
                    help="where the side-by-side pictures go, '' for nowhere (default docs/img)")
    ap.add_argument("--tachyon", default="tachyon", help="the tachyon binary (default: tachyon on the PATH)")
    ap.add_argument("--keep", metavar="DIR", help="write the scenes and images here and keep them")
    args = ap.parse_intermixed_args()
    if not os.path.isfile(args.glint) or not os.access(args.glint, os.X_OK):
        sys.exit("error: glint binary not found or not executable: %s" % args.glint)
    args.glint = os.path.abspath(args.glint)
    if shutil.which(args.tachyon) is None:
        sys.exit("error: tachyon not found (Debian: apt-get install tachyon-bin-nox)")
    try:
        args.threads = [int(t) for t in args.threads.split(",") if t]
    except ValueError:
        sys.exit("error: --threads takes numbers, comma separated")
    if not args.threads or min(args.threads) < 1 or args.runs < 1 or args.scale <= 0 or args.cone_segments < 3:
        sys.exit("error: --threads and --runs must be at least 1, --scale above 0, --cone-segments at least 3")
    scenes = [os.path.abspath(s) for s in (args.scenes or DEFAULT_SCENES)]
    for s in scenes:
        if not os.path.isfile(s) or not s.lower().endswith((".nff", ".json")):
            sys.exit("error: not an .nff or .json file: %s" % s)
    stand_ins = [n for n in args.stand_ins.split(",") if n]
    for n in stand_ins:
        if n not in STAND_INS.split(","):
            sys.exit("error: unknown stand-in %r (expected some of %s)" % (n, STAND_INS))
    bench = [n for n in args.bench.split(",") if n]
    for n in bench:
        if n not in BENCH_ALL.split(","):
            sys.exit("error: unknown bench scene %r (expected some of %s)" % (n, BENCH_ALL))
    if args.img_dir:
        args.img_dir = os.path.abspath(args.img_dir)

    if args.keep:
        tmp = os.path.abspath(args.keep)
        os.makedirs(tmp, exist_ok=True)
    else:
        tmp = tempfile.mkdtemp(prefix="vs-tachyon.", dir="/tmp")
    try:
        if stand_ins:
            folder = os.path.join(tmp, "stand-ins")
            subprocess.run([sys.executable, os.path.join(HERE, "spd_scenes.py"), folder, "--scenes", ",".join(stand_ins)],
                           check=True, stdout=subprocess.DEVNULL)
            scenes += [os.path.join(folder, n + ".nff") for n in stand_ins]
        if bench:
            folder = os.path.join(tmp, "bench-scenes")
            subprocess.run([sys.executable, os.path.join(HERE, "make_bench.py"), "--only", ",".join(bench), "-o", folder,
                            "--terrain-tris", str(args.terrain_tris)], check=True, stdout=subprocess.DEVNULL)
            scenes += [os.path.join(folder, n + ".json") for n in bench]
        print("machine load before the runs: %s" % open("/proc/loadavg").read().split()[:3], file=sys.stderr)
        prepared = [p for p in (prepare(args, s, tmp) for s in scenes) if p]
        if not prepared:
            sys.exit("error: no scene left to compare")
        print()
        print("pictures (%d thread(s)): hit/background masks, pixel == background color within 1/255 (linear)"
              % args.threads[0])
        print("%-8s %10s %9s %9s %9s %8s %8s %9s" % ("scene", "size", "masks", "bg glint", "bg tach", "g only",
                                                     "t only", "colors"))
        failed = []
        for s in prepared:
            c = check(args, s, tmp)
            ok = c["agree"] >= MASK_MIN
            if not ok:
                failed.append(s["name"])
            print("%-8s %10s %8.3f%% %8.2f%% %8.2f%% %8d %8d %8.2f%%%s" % (
                s["name"], "%dx%d" % (s["w"], s["h"]), 100 * c["agree"], 100 * c["bg_glint"], 100 * c["bg_tachyon"],
                c["glint_only"], c["tachyon_only"], 100 * c["colors"], "" if ok else "   MASKS DISAGREE"))
        print("masks: the pixels where both are background or both are not; bg: background pixels;"
              " g only / t only: pixels only glint / only Tachyon hit; colors: every channel within %d/255" % COLOR_TOL)
        if args.img_dir:
            print("side-by-side pictures (glint | Tachyon): %s/vs-tachyon-<scene>.png" % os.path.relpath(args.img_dir))
        if failed:
            print("error: the masks agree on less than %g%% of the pixels: %s" % (100 * MASK_MIN, ", ".join(failed)))
        if not args.check_only:
            timing(args, prepared, tmp)
        if failed:
            sys.exit(1)
    finally:
        if not args.keep:
            shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
