#!/usr/bin/python3
"""Stand-ins for the SPD scenes we do not have: gears, mount, rings, teapot, tree.

    bench/spd_scenes.py OUTDIR [--scenes gears,mount,rings,teapot,tree] [--pov-polygons]

Writes OUTDIR/NAME.nff and, beside it, OUTDIR/NAME.pov: the same scene as
POV-Ray 3.1 scene text in the style of the SPD programs' own POV-Ray export
(compare bench/spd/balls.pov and tetra.pov): its camera (location, unit
direction, right and up of length 2 tan(angle/2)), one light_source of
color 1/sqrt(n) per NFF light, a declared texture per NFF `f` (pigment with
`filter T`, finish with ambient, diffuse, phong = Ks, reflection Ks,
`refraction 1.0 ior`), every `c` as an open `cone` (cylinders too), every
`s` as a `sphere`, every `p` cut into `triangle`s (POV-Ray 3.1 has no
general polygon object the export uses; a concave gear face is cut by ear
clipping, n - 2 triangles) and every `pp` triangle as a `smooth_triangle`.
With --pov-polygons a polygon of more than 3 vertices becomes one POV-Ray
`polygon` instead.

These are our own constructions from the SPD's published descriptions (the
SPD README's "Database Analysis" and statistics table), not the SPD
programs nor their data; they have the published primitive counts and the
character of each database, not its exact geometry, view or lights:

  gears   9,345 polygons: a 4 x 4 x 4 array of meshing 36-tooth gears, each
          two concave 144-vertex faces and 144 rectangles around its rim, on
          a reflective square; a quarter of the gears transmit (T > 0, an
          index of refraction, no Ks); 5 lights; little background.
  mount   8,192 triangles of a fractal (midpoint displacement) mountain and
          4 glass spheres; 1 light; about a third background.
  rings   140 objects in a pyramid (7 x 7 up to 1 x 1), each six pentagonal
          rings laid on faces of a dodecahedron, a ring 5 spheres joined by
          5 cylinders: 4,200 cylinders, 4,200 spheres, 1 ground polygon;
          reflective; 3 lights; no background.
  teapot  "teapot-like": a surface of revolution (body, lid, knob) with a
          swept handle and spout, 9,120 triangles `pp 3` with vertex
          normals (no Utah teapot data), on a 12 x 12 checkerboard of 144
          polygons; all reflective; 2 lights.
  tree    a binary tree after Aono and Kunii, 12 levels: 4,095 cones (the
          branches) and 4,095 spheres (their joints and tips) and a ground
          polygon; 7 lights; no reflection.

Numbers are written with %g (6 significant digits), as the SPD programs do.
"""

import argparse
import math
import os
import sys

# ---------------------------------------------------------------------------
# vectors


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def mul(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def length(a):
    return math.sqrt(dot(a, a))


def normalize(a):
    n = length(a)
    return (a[0] / n, a[1] / n, a[2] / n)


def perpendicular_frame(axis):
    """Two unit vectors perpendicular to the unit vector axis and to each other."""
    helper = (1.0, 0.0, 0.0) if abs(axis[0]) < 0.9 else (0.0, 1.0, 0.0)
    u = normalize(cross(helper, axis))
    return u, cross(axis, u)


def rotate(v, axis, angle):
    """v rotated by angle (radians) about the unit vector axis (Rodrigues)."""
    c, s = math.cos(angle), math.sin(angle)
    return add(add(mul(v, c), mul(cross(axis, v), s)), mul(axis, dot(axis, v) * (1.0 - c)))


def hash01(*ints):
    """A deterministic pseudo-random number in [0, 1) from integers (our own mixer)."""
    h = 0x9E3779B9
    for i in ints:
        h = (h ^ (i & 0xFFFFFFFF)) * 0x85EBCA6B & 0xFFFFFFFF
        h ^= h >> 13
        h = h * 0xC2B2AE35 & 0xFFFFFFFF
        h ^= h >> 16
    return h / 4294967296.0


def hsv(h, s, v):
    """An RGB color from hue (turns), saturation and value."""
    h = (h % 1.0) * 6.0
    i = int(h)
    f = h - i
    p, q, t = v * (1 - s), v * (1 - s * f), v * (1 - s * (1 - f))
    return [(v, t, p), (q, v, p), (p, v, t), (p, q, v), (t, p, v), (v, p, q)][i % 6]


# ---------------------------------------------------------------------------
# number formatting: C's %g, with no "-0"


def g(x):
    return "%g" % (x + 0.0)


def gv(v):
    return "%s %s %s" % (g(v[0]), g(v[1]), g(v[2]))


def pv(v):
    return "<%s, %s, %s>" % (g(v[0]), g(v[1]), g(v[2]))


# ---------------------------------------------------------------------------
# polygon triangulation for the POV-Ray export (ear clipping)


def triangulate(verts):
    """Indices of n - 2 triangles covering the simple planar polygon verts (any winding, may be concave)."""
    n = len(verts)
    if n == 3:
        return [(0, 1, 2)]
    # Newell's normal; drop its largest axis to work in 2D.
    nx = ny = nz = 0.0
    for i in range(n):
        a, b = verts[i], verts[(i + 1) % n]
        nx += (a[1] - b[1]) * (a[2] + b[2])
        ny += (a[2] - b[2]) * (a[0] + b[0])
        nz += (a[0] - b[0]) * (a[1] + b[1])
    ax = max(range(3), key=lambda k: abs((nx, ny, nz)[k]))
    u, v = [(1, 2), (2, 0), (0, 1)][ax]
    sign = 1.0 if (nx, ny, nz)[ax] > 0 else -1.0
    p = [(q[u], q[v]) for q in verts]

    def area2(a, b, c):
        return sign * ((p[b][0] - p[a][0]) * (p[c][1] - p[a][1]) - (p[b][1] - p[a][1]) * (p[c][0] - p[a][0]))

    def inside(i, a, b, c):
        return area2(a, b, i) >= 0 and area2(b, c, i) >= 0 and area2(c, a, i) >= 0

    idx = list(range(n))
    tris = []
    guard = 0
    while len(idx) > 3:
        m = len(idx)
        for k in range(m):
            a, b, c = idx[k - 1], idx[k], idx[(k + 1) % m]
            if area2(a, b, c) <= 0:
                continue  # reflex or flat corner: not an ear
            if any(inside(i, a, b, c) for i in idx if i not in (a, b, c) and
                   p[i] != p[a] and p[i] != p[b] and p[i] != p[c]):
                continue
            tris.append((a, b, c))
            del idx[k]
            break
        else:
            guard += 1
            if guard > 1:
                raise ValueError("polygon could not be triangulated (self-intersecting?)")
            # numerically stuck: cut the flattest corner
            k = min(range(m), key=lambda k: abs(area2(idx[k - 1], idx[k], idx[(k + 1) % m])))
            tris.append((idx[k - 1], idx[k], idx[(k + 1) % m]))
            del idx[k]
    tris.append(tuple(idx))
    return tris


# ---------------------------------------------------------------------------
# the scene and its two writers


class Material:
    def __init__(self, color, kd, ks=0.0, shine=0.0, kt=0.0, ior=1.0, ka=0.1, phong=None):
        self.color, self.kd, self.ks, self.shine, self.kt, self.ior, self.ka = color, kd, ks, shine, kt, ior, ka
        # The NFF has no separate highlight weight; the export's phong is Ks.
        self.phong = ks if phong is None else phong


class Scene:
    def __init__(self, name):
        self.name = name
        self.background = (0.078, 0.361, 0.753)
        self.view = None
        self.lights = []
        self.items = []  # ("f", Material) or (kind, data...)
        self.counts = {"s": 0, "c": 0, "p": 0, "pp": 0, "f": 0}

    def set_view(self, frm, at, up, angle, hither=0.01, res=512):
        self.view = (frm, at, up, angle, hither, res)

    def light(self, pos):
        self.lights.append(pos)

    def material(self, m):
        self.items.append(("f", m))
        self.counts["f"] += 1

    def sphere(self, c, r):
        self.items.append(("s", c, r))
        self.counts["s"] += 1

    def cone(self, base, br, apex, ar):
        self.items.append(("c", base, br, apex, ar))
        self.counts["c"] += 1

    def polygon(self, verts):
        self.items.append(("p", verts))
        self.counts["p"] += 1

    def patch(self, verts, normals):
        self.items.append(("pp", verts, normals))
        self.counts["pp"] += 1

    # -- NFF ----------------------------------------------------------------

    def write_nff(self, path):
        frm, at, up, angle, hither, res = self.view
        out = ["b %s\n" % gv(self.background),
               "v\nfrom %s\nat %s\nup %s\nangle %s\nhither %s\nresolution %d %d\n"
               % (gv(frm), gv(at), gv(up), g(angle), g(hither), res, res)]
        for l in self.lights:
            out.append("l %s\n" % gv(l))
        for it in self.items:
            k = it[0]
            if k == "f":
                m = it[1]
                out.append("f %s %s %s %s %s %s\n" % (gv(m.color), g(m.kd), g(m.ks), g(m.shine), g(m.kt), g(m.ior)))
            elif k == "s":
                out.append("s %s %s\n" % (gv(it[1]), g(it[2])))
            elif k == "c":
                out.append("c %s %s %s %s\n" % (gv(it[1]), g(it[2]), gv(it[3]), g(it[4])))
            elif k == "p":
                out.append("p %d\n" % len(it[1]))
                out.extend("%s\n" % gv(v) for v in it[1])
            else:
                out.append("pp %d\n" % len(it[1]))
                out.extend("%s %s\n" % (gv(v), gv(n)) for v, n in zip(it[1], it[2]))
        write_text(path, "".join(out))

    # -- POV-Ray 3.1, the SPD export's style ---------------------------------

    def write_pov(self, path, pov_polygons=False):
        frm, at, up, angle, hither, res = self.view
        # The numbers the NFF reader will see, so both files describe the same scene.
        rd = lambda v: tuple(float(g(x)) for x in v)
        frm, at, up = rd(frm), rd(at), rd(up)
        d = normalize(sub(at, frm))
        scale = 2.0 * math.tan(math.radians(angle) / 2.0)
        right = mul(normalize(cross(d, up)), scale)
        upv = mul(normalize(cross(right, d)), scale)
        out = ["// POV-Ray 3 scene file\n",
               "background { color red %s green %s blue %s }\n\n" % tuple(g(c) for c in self.background),
               "camera {\n    location  %s\n    direction %s\n    right     %s\n    up        %s\n} // camera\n\n"
               % (pv(frm), pv(d), pv(right), pv(upv))]
        lc = g(1.0 / math.sqrt(len(self.lights)))
        for l in self.lights:
            out.append("light_source {\n    %s color red %s green %s blue %s\n} // light\n\n" % (pv(l), lc, lc, lc))
        tex = None
        ntex = 0
        for it in self.items:
            k = it[0]
            if k == "f":
                m = it[1]
                ntex += 1
                tex = "txt%03d" % ntex
                pig = "color red %s green %s blue %s" % tuple(g(c) for c in m.color)
                if m.kt > 0:
                    pig += " filter %s" % g(m.kt)
                fin = ["ambient %s" % g(m.ka), "diffuse %s" % g(m.kd)]
                if m.phong != 0:
                    fin.append("phong %s  phong_size %s" % (g(m.phong), g(m.shine)))
                if m.ks != 0:
                    fin.append("reflection %s" % g(m.ks))
                if m.kt != 0:
                    fin.append("refraction 1.0 ior %s" % g(m.ior))
                out.append("#declare %s = texture {\n    pigment {\n        %s\n    } // pigment\n"
                           "    // normal { bumps, ripples, etc. }\n    finish {\n%s    } // finish\n"
                           "} // texture %s\n\n" % (tex, pig, "".join("        %s\n" % f for f in fin), tex))
            elif k == "s":
                out.append("sphere { %s, %s  texture { %s } }\n\n" % (pv(it[1]), g(it[2]), tex))
            elif k == "c":
                out.append("cone {\n    %s, %s,\n    %s, %s open\n    texture { %s }\n}\n\n"
                           % (pv(it[3]), g(it[4]), pv(it[1]), g(it[2]), tex))
            elif k == "p":
                verts = [rd(v) for v in it[1]]
                if pov_polygons and len(verts) > 3:
                    out.append("polygon {\n    %d,\n    %s\n    texture { %s }\n}\n\n" % (
                        len(verts) + 1, ",\n    ".join(pv(v) for v in verts + [verts[0]]), tex))
                    continue
                for a, b, c in triangulate(verts):
                    out.append("object {\n    triangle {\n        %s,\n        %s,\n        %s\n    } // tri\n"
                               "    texture { %s }\n} // object\n\n" % (pv(verts[a]), pv(verts[b]), pv(verts[c]), tex))
            else:
                vs, ns = it[1], it[2]
                for a, b, c in triangulate([rd(v) for v in vs]) if len(vs) > 3 else [(0, 1, 2)]:
                    out.append("object {\n    smooth_triangle {\n        %s, %s,\n        %s, %s,\n        %s, %s\n"
                               "    } // tri\n    texture { %s }\n} // object\n\n"
                               % (pv(vs[a]), pv(ns[a]), pv(vs[b]), pv(ns[b]), pv(vs[c]), pv(ns[c]), tex))
        write_text(path, "".join(out))

    def summary(self):
        c = self.counts
        prims = c["s"] + c["c"] + c["p"] + c["pp"]
        return ("%s: %d primitives (%d spheres, %d cones/cylinders, %d polygons, %d patches), %d lights, %d surfaces"
                % (self.name, prims, c["s"], c["c"], c["p"], c["pp"], len(self.lights), c["f"]))


def write_text(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="ascii", newline="\n") as f:
        f.write(text)
    os.replace(tmp, path)


# ---------------------------------------------------------------------------
# gears


TEETH = 36          # 4 vertices per tooth: 144-vertex faces
TIP_HALF = 0.15     # tooth tip half-width, in tooth pitches
ROOT_FROM, ROOT_TO = 0.30, 0.70   # the gap's floor, in pitches after a tooth's center
ROOT_RATIO = 0.86   # root radius / tip radius
MESH_RATIO = 1.88   # center distance of meshing neighbors / tip radius (0.02 radial clearance)


def gear_outline(cx, cy, z, r_tip, phase):
    """The 144 outline points counterclockwise seen from +z, starting at a tooth tip's
    first corner so that the first two edges (across the tip) turn convexly."""
    pitch = 2.0 * math.pi / TEETH
    r_root = ROOT_RATIO * r_tip
    pts = []
    for k in range(TEETH):
        a = phase + k * pitch
        for da, r in ((-TIP_HALF, r_tip), (TIP_HALF, r_tip), (ROOT_FROM, r_root), (ROOT_TO, r_root)):
            pts.append((cx + r * math.cos(a + da * pitch), cy + r * math.sin(a + da * pitch), z))
    return pts


def gear(scene, cx, cy, z_top, thickness, r_tip, phase):
    top = gear_outline(cx, cy, z_top, r_tip, phase)
    z_bot = z_top - thickness
    scene.polygon(top)
    n = len(top)
    for i in range(n):
        a, b = top[i], top[(i + 1) % n]
        scene.polygon([(a[0], a[1], z_bot), (b[0], b[1], z_bot), b, a])
    bottom = [(p[0], p[1], z_bot) for p in reversed(top)]
    # reversed: ... tip2, tip1 | root2, root1, ...; start at a tip's second corner
    scene.polygon(bottom[2:] + bottom[:2])


def make_gears():
    s = Scene("gears")
    s.set_view((1.75, -2.05, 3.3), (-0.1, 0.15, 0.3), (0, 0, 1), 40.0)
    for l in ((3.5, -1.0, 4.5), (-3.0, -3.5, 3.0), (-2.5, 3.0, 4.0), (2.0, 3.5, 2.5), (0.3, -0.4, 5.0)):
        s.light(l)
    s.material(Material((0.85, 0.8, 0.7), 0.45, ks=0.45, shine=30.0, ka=0.1))
    s.polygon([(3.0, 3.0, 0.0), (-3.0, 3.0, 0.0), (-3.0, -3.0, 0.0), (3.0, -3.0, 0.0)])
    n = 4
    r_tip = 2.0 / ((n - 1) * MESH_RATIO + 2.0)   # the n gears of a row span 2 units
    d = MESH_RATIO * r_tip
    thickness = 0.07
    for iz in range(n):
        z_top = 0.3 + 0.28 * iz
        for iy in range(n):
            for ix in range(n):
                cx, cy = -1.0 + r_tip + ix * d, -1.0 + r_tip + iy * d
                color = hsv(hash01(ix, iy, iz, 7), 0.55 + 0.4 * hash01(ix, iy, iz, 8), 1.0)
                if (ix + 2 * iy + 3 * iz) % 4 == 1:
                    s.material(Material(color, 0.12, ks=0.0, shine=0.0, kt=0.85, ior=1.2, ka=0.0))
                else:
                    s.material(Material(color, 0.85, ks=0.0, shine=0.0, ka=0.1))
                # neighbors mesh: every other gear turned by half a tooth
                phase = (math.pi / TEETH) * ((ix + iy + iz) % 2)
                gear(s, cx, cy, z_top, thickness, r_tip, phase)
    return s


# ---------------------------------------------------------------------------
# mount


def fractal_heights(n_log2, roughness, seed):
    """A (2^k + 1)^2 grid of heights by midpoint displacement (square-diamond)."""
    n = 1 << n_log2
    h = [[0.0] * (n + 1) for _ in range(n + 1)]
    step, amp = n, 1.0
    while step > 1:
        half = step // 2
        for i in range(half, n, step):        # square step: cell centers
            for j in range(half, n, step):
                avg = (h[i - half][j - half] + h[i - half][j + half] + h[i + half][j - half] + h[i + half][j + half]) / 4
                h[i][j] = avg + amp * (2.0 * hash01(i, j, seed) - 1.0)
        for i in range(0, n + 1, half):       # diamond step: edge midpoints
            for j in range((i + half) % step, n + 1, step):
                acc, cnt = 0.0, 0
                for di, dj in ((-half, 0), (half, 0), (0, -half), (0, half)):
                    if 0 <= i + di <= n and 0 <= j + dj <= n:
                        acc += h[i + di][j + dj]
                        cnt += 1
                h[i][j] = acc / cnt + amp * (2.0 * hash01(i, j, seed + 1) - 1.0)
        step, amp = half, amp * roughness
    return h


def make_mount():
    s = Scene("mount")
    s.set_view((-0.15, -2.75, 1.25), (0.0, 0.3, 0.5), (0, 0, 1), 45.0)
    s.light((-6.0, -12.0, 14.0))
    k = 6
    n = 1 << k                       # 64 x 64 squares, two triangles each: 8,192
    h = fractal_heights(k, 0.55, 11)
    half = 1.6
    def point(i, j):
        x, y = -half + 2 * half * i / n, -half + 2 * half * j / n
        r2 = (x * x + y * y) / (half * half)
        base = 1.15 * math.exp(-2.2 * r2)    # a peak in the middle, falling to the edges
        return (x, y, max(0.0, base + 0.3 * h[i][j] * (0.35 + base)))
    pts = [[point(i, j) for j in range(n + 1)] for i in range(n + 1)]
    s.material(Material((0.62, 0.56, 0.46), 0.9, ks=0.0, ka=0.1))
    for i in range(n):
        for j in range(n):
            a, b, c, d = pts[i][j], pts[i + 1][j], pts[i + 1][j + 1], pts[i][j + 1]
            s.polygon([a, b, c])
            s.polygon([a, c, d])
    s.material(Material((1.0, 1.0, 1.0), 0.05, ks=0.15, shine=200.0, kt=0.9, ior=1.5, ka=0.0))
    for c, r in (((-0.55, -0.95, 0.8), 0.25), ((0.3, -1.35, 0.62), 0.18),
                 ((0.7, -0.55, 1.05), 0.26), ((-0.85, -0.2, 1.2), 0.22)):
        s.sphere(c, r)
    return s


# ---------------------------------------------------------------------------
# rings


PHI = (1.0 + math.sqrt(5.0)) / 2.0


def dodecahedron_vertices():
    v = [(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]
    for a in (-1, 1):
        for b in (-1, 1):
            v += [(0, a / PHI, b * PHI), (a / PHI, b * PHI, 0), (a * PHI, 0, b / PHI)]
    return v


def dodecahedron_face(verts, axis):
    """The five vertices of the face whose outward normal is axis, in order around it."""
    axis = normalize(axis)
    best = max(dot(v, axis) for v in verts)
    face = [v for v in verts if dot(v, axis) > best - 1e-9]
    u, w = perpendicular_frame(axis)
    face.sort(key=lambda v: math.atan2(dot(v, w), dot(v, u)))
    return face


def make_rings():
    s = Scene("rings")
    s.set_view((-5.0, -11.5, 9.5), (0.0, 0.0, 1.6), (0, 0, 1), 36.0)
    for l in ((-9.0, -14.0, 16.0), (12.0, -9.0, 11.0), (-4.0, 10.0, 18.0)):
        s.light(l)
    s.material(Material((0.55, 0.6, 0.5), 0.8, ks=0.0, ka=0.1))
    big = 40.0
    s.polygon([(big, big, -0.05), (-big, big, -0.05), (-big, -big, -0.05), (big, -big, -0.05)])
    verts = dodecahedron_vertices()
    # one face from each of the six pairs of opposite faces
    axes = [(0, PHI, 1), (0, -PHI, 1), (PHI, 1, 0), (PHI, -1, 0), (1, 0, PHI), (-1, 0, PHI)]
    rings = []
    for a in axes:
        face = dodecahedron_face(verts, a)
        center = mul(add(add(add(add(face[0], face[1]), face[2]), face[3]), face[4]), 0.2)
        rings.append([add(center, mul(sub(v, center), 0.8)) for v in face])   # shrunk apart
    scale = 0.32                  # circumradius sqrt(3) * 0.32 = 0.55
    r_sphere, r_cyl = 0.16 * scale, 0.09 * scale
    spacing, rise = 1.12, 0.95
    levels = 7
    for k in range(levels):
        m = levels - k
        for iy in range(m):
            for ix in range(m):
                c = ((ix - (m - 1) / 2) * spacing, (iy - (m - 1) / 2) * spacing, 0.6 + k * rise)
                color = hsv(hash01(ix, iy, k, 3), 0.9, 1.0)
                s.material(Material(color, 0.55, ks=0.45, shine=25.0, ka=0.1))
                for ring in rings:
                    pts = [add(c, mul(v, scale)) for v in ring]
                    for i in range(5):
                        s.sphere(pts[i], r_sphere)
                    for i in range(5):
                        s.cone(pts[i], r_cyl, pts[(i + 1) % 5], r_cyl)
    return s


# ---------------------------------------------------------------------------
# teapot-like


def catmull_rom(points, t):
    """A point on the Catmull-Rom spline through points, t in [0, 1]."""
    n = len(points) - 1
    x = min(t * n, n - 1e-12)
    i = int(x)
    u = x - i
    p0, p1, p2, p3 = points[max(i - 1, 0)], points[i], points[i + 1], points[min(i + 2, n)]
    return tuple(0.5 * ((2 * p1[k]) + (-p0[k] + p2[k]) * u + (2 * p0[k] - 5 * p1[k] + 4 * p2[k] - p3[k]) * u * u
                        + (-p0[k] + 3 * p1[k] - 3 * p2[k] + p3[k]) * u * u * u) for k in range(len(p1)))


def spline_tangent(points, t, h=1e-4):
    a, b = catmull_rom(points, max(t - h, 0.0)), catmull_rom(points, min(t + h, 1.0))
    return tuple(b[k] - a[k] for k in range(len(a)))


def grid_patches(scene, rows, cols, point, normal, wrap):
    """Triangles `pp 3` over a (rows+1) x cols (wrapping) grid; triangles with two equal corners are left out."""
    P = [[point(i, j) for j in range(cols)] for i in range(rows + 1)]
    N = [[normal(i, j) for j in range(cols)] for i in range(rows + 1)]
    jn = cols if wrap else cols - 1
    for i in range(rows):
        for j in range(jn):
            j1 = (j + 1) % cols
            for tri in (((i, j), (i, j1), (i + 1, j1)), ((i, j), (i + 1, j1), (i + 1, j))):
                vs = [P[a][b] for a, b in tri]
                if vs[0] == vs[1] or vs[1] == vs[2] or vs[0] == vs[2]:
                    continue
                scene.patch(vs, [N[a][b] for a, b in tri])


def revolution(scene, profile, rows, cols):
    """A surface of revolution about z of the (r, z) spline profile (bottom to top)."""
    ts = [i / rows for i in range(rows + 1)]
    prof = [catmull_rom(profile, t) for t in ts]
    prof = [(0.0 if abs(r) < 1e-9 else r, z) for r, z in prof]
    tang = [spline_tangent(profile, t) for t in ts]
    angles = [2 * math.pi * j / cols for j in range(cols)]

    def point(i, j):
        r, z = prof[i]
        return (r * math.cos(angles[j]), r * math.sin(angles[j]), z)

    def normal(i, j):
        dr, dz = tang[i]
        nr, nz = dz, -dr               # the tangent turned outward
        l = math.hypot(nr, nz)
        return (nr / l * math.cos(angles[j]), nr / l * math.sin(angles[j]), nz / l)

    grid_patches(scene, rows, cols, point, normal, True)


def tube(scene, path, radius, rows, cols):
    """A tube of radius(t) around the spline path in the xz plane."""
    b = (0.0, 1.0, 0.0)

    def frame(t):
        c = catmull_rom(path, t)
        tg = normalize(spline_tangent(path, t))
        nrm = normalize(cross(tg, b))
        return c, nrm

    frames = [frame(i / rows) for i in range(rows + 1)]
    angles = [2 * math.pi * j / cols for j in range(cols)]

    def direction(i, j):
        _, nrm = frames[i]
        return add(mul(nrm, math.cos(angles[j])), mul(b, math.sin(angles[j])))

    def point(i, j):
        return add(frames[i][0], mul(direction(i, j), radius(i / rows)))

    grid_patches(scene, rows, cols, point, direction, True)


def make_teapot():
    s = Scene("teapot")
    s.set_view((-4.2, -7.4, 5.6), (0.0, 0.0, 1.1), (0, 0, 1), 40.0)
    s.light((-5.0, -8.0, 12.0))
    s.light((8.0, -3.0, 9.0))
    # checkerboard, 12 x 12 squares
    n, side = 12, 5.2
    cell = 2 * side / n
    white = Material((1.0, 1.0, 1.0), 0.7, ks=0.25, shine=20.0, ka=0.1)
    red = Material((0.9, 0.12, 0.1), 0.7, ks=0.25, shine=20.0, ka=0.1)
    for color in (white, red):
        s.material(color)
        for i in range(n):
            for j in range(n):
                if (i + j) % 2 != (0 if color is white else 1):
                    continue
                x0, y0 = -side + i * cell, -side + j * cell
                s.polygon([(x0, y0, 0.0), (x0 + cell, y0, 0.0), (x0 + cell, y0 + cell, 0.0), (x0, y0 + cell, 0.0)])
    s.material(Material((0.85, 0.55, 0.25), 0.6, ks=0.3, shine=40.0, ka=0.1))
    cols = 56
    body = [(0.0, 0.02), (0.8, 0.0), (1.3, 0.08), (1.6, 0.45), (1.72, 1.0), (1.6, 1.6), (1.3, 2.0), (1.18, 2.2)]
    revolution(s, body, 40, cols)                        # 79 x 56 = 4,424 triangles
    lid = [(1.25, 2.18), (1.05, 2.32), (0.6, 2.48), (0.22, 2.56), (0.16, 2.7), (0.34, 2.86), (0.2, 3.0), (0.0, 3.03)]
    revolution(s, lid, 24, cols)                         # 47 x 56 = 2,632
    handle = [(-1.45, 0.0, 1.85), (-2.15, 0.0, 2.0), (-2.45, 0.0, 1.45), (-2.2, 0.0, 0.8), (-1.55, 0.0, 0.6)]
    tube(s, handle, lambda t: 0.13, 24, 20)              # 960
    spout = [(1.45, 0.0, 0.75), (2.1, 0.0, 0.95), (2.45, 0.0, 1.55), (2.7, 0.0, 2.1), (3.05, 0.0, 2.3)]
    tube(s, spout, lambda t: 0.3 - 0.16 * t, 23, 24)     # 1,104
    return s


# ---------------------------------------------------------------------------
# tree


def make_tree():
    s = Scene("tree")
    s.background = (0.078, 0.361, 0.753)
    s.set_view((3.4, -6.6, 2.5), (0.0, 0.0, 2.0), (0, 0, 1), 45.0)
    for l in ((6, -8, 10), (-7, -6, 9), (-6, 7, 11), (7, 6, 8), (0, -10, 4), (10, 0, 5), (0, 0, 14)):
        s.light(l)
    s.material(Material((0.35, 0.6, 0.25), 0.9, ks=0.0, ka=0.1))
    s.polygon([(6, 6, 0), (-6, 6, 0), (-6, -6, 0), (6, -6, 0)])
    depth = 12
    branches = []   # (level, base, base radius, apex, apex radius)
    # Aono and Kunii's binary tree: each branch ends in two, shorter by the
    # ratios R1 and R2, turned by the angles A1 and A2 from their parent in
    # a plane that rotates by the divergence angle from one level to the next.
    R1, R2, A1, A2, DIVERGENCE, TAPER = 0.86, 0.74, math.radians(24.0), math.radians(40.0), math.radians(137.5), 0.8

    def grow(level, base, direction, side, length, radius):
        apex = add(base, mul(direction, length))
        r_apex = radius * TAPER
        branches.append((level, base, radius, apex, r_apex))
        if level + 1 == depth:
            return
        side = rotate(side, direction, DIVERGENCE)
        axis = normalize(cross(direction, side))
        # a little pull upward keeps the crown from sagging
        for ratio, ang in ((R1, A1), (R2, -A2)):
            d = normalize(add(rotate(direction, axis, ang), (0.0, 0.0, 0.08)))
            grow(level + 1, apex, d, side, length * ratio, r_apex * (0.95 if ratio == R1 else 0.85))

    grow(0, (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), (1.0, 0.0, 0.0), 1.1, 0.14)
    wood = Material((0.55, 0.36, 0.2), 0.85, ks=0.0, ka=0.1)
    leaf = Material((0.25, 0.7, 0.2), 0.85, ks=0.0, ka=0.1)
    for mat, levels in ((wood, range(0, depth - 3)), (leaf, range(depth - 3, depth))):
        s.material(mat)
        for lv, base, br, apex, ar in branches:
            if lv in levels:
                s.cone(base, br, apex, ar)
        for lv, base, br, apex, ar in branches:
            if lv in levels:
                s.sphere(apex, ar if lv < depth - 1 else max(1.6 * ar, 0.045))
    return s


# ---------------------------------------------------------------------------

MAKERS = {"gears": make_gears, "mount": make_mount, "rings": make_rings, "teapot": make_teapot, "tree": make_tree}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog=__doc__.split("\n\n", 2)[2])
    ap.add_argument("outdir", help="folder to write NAME.nff and NAME.pov into (created if missing)")
    ap.add_argument("--scenes", default=",".join(MAKERS), help="comma separated, of %s (default all)" % ", ".join(MAKERS))
    ap.add_argument("--pov-polygons", action="store_true",
                    help="write polygons of more than 3 vertices as one POV-Ray polygon, not triangles")
    args = ap.parse_args()
    names = [n for n in args.scenes.split(",") if n]
    for n in names:
        if n not in MAKERS:
            sys.exit("error: unknown scene %r (expected one of %s)" % (n, ", ".join(MAKERS)))
    os.makedirs(args.outdir, exist_ok=True)
    for n in names:
        scene = MAKERS[n]()
        scene.write_nff(os.path.join(args.outdir, n + ".nff"))
        scene.write_pov(os.path.join(args.outdir, n + ".pov"), args.pov_polygons)
        print(scene.summary())


if __name__ == "__main__":
    main()
