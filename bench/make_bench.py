#!/usr/bin/env python3
"""Write the glint benchmark scenes, each with an equivalent POV-Ray 3.7 scene.

    python3 bench/make_bench.py [-o OUT] [--terrain-tris N] [--only spheres,bunny,terrain,terrain-normals]

Writes into OUT (default bench-scenes/ beside this script, git-ignored):
    spheres.json  spheres.pov    1000 spheres (r=0.4, 40x25 grid) on a reflective plane, 1920x1080
    bunny.json    bunny.pov      Stanford bunny (3674 tris, bunny.obj) on the plane, 1920x1080
    bunny.obj                    copy of the repository's scenes/meshes/bunny.obj (read by bunny.json)
    terrain.json  terrain.pov    sum-of-sines height field (~1M tris) + plane, 1280x720
    terrain.obj                  the height field mesh (read by terrain.json)
  only when asked for (--only terrain-normals), not by default:
    terrain-normals.json .pov    the same height field with a vertex normal per vertex (smooth), 1280x720
    terrain-normals.obj          its mesh with `vn` lines and `f a//a b//b c//c` faces (~76 MB at 1M
                                 triangles): the OBJ load benchmark of issue #16

Python 3 standard library only.  Both files of a pair are written from the same
data, so they describe the same scene; the POV-Ray mapping is:
  * world coordinates identical.  POV-Ray is left-handed, so the camera uses
    `right -x*W/H`: POV then renders the same right-handed view as glint
    (the mirror image of a classic `right x` POV camera; same work).
  * POV `angle` is horizontal: angle = 2 atan(tan(fov_y/2) * W/H), computed in
    the .pov from image_width/image_height so any +W/+H keeps matching glint's
    --width/--height.
  * material from the POV finish (no brilliance/metallic/conserve_energy):
      pigment p, finish { ambient a diffuse d phong s phong_size n reflection r }
      with ambient_light 1  ->  glint ambient p*a (point light "ambient": 1),
      diffuse p*d, specular s (POV phong is not tinted by the pigment),
      shininess n, reflectivity r.
  * max_depth D -> max_trace_level D (both count the camera ray as level 1);
    adc_bailout 0 so POV never drops weak reflection rays.
  * meshes: POV mesh2 (vertex_vectors + face_indices, no normals = flat
    shading) with the very same vertex numbers as the .obj; glint "smooth": false.
  * single ray through each pixel centre: glint spp 1 = POV -A.
"""
import argparse
import json
import math
import os
import shutil
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
# The Stanford bunny of the mesh example scene: one copy in the repository.
BUNNY = os.path.join(HERE, os.pardir, "scenes", "meshes", "bunny.obj")

BACKGROUND = [0.16, 0.24, 0.35]
MAX_DEPTH = 5

# POV finishes of the reference scenes (texture T_Obj and T_Plane).
FINISH_OBJ = {"pigment": 0.8, "ambient": 0.1, "diffuse": 0.7, "phong": 0.5, "phong_size": 40, "reflection": 0.0}
FINISH_PLANE = {"pigment": 0.7, "ambient": 0.1, "diffuse": 0.7, "phong": 0.5, "phong_size": 40, "reflection": 0.3}
AMBIENT_LIGHT = 1       # POV global ambient_light == L_a of glint's point light


def num(x):
    """Shortest text for a float (integers without '.0')."""
    x = float(x)
    if x == int(x) and abs(x) < 1e15:
        return str(int(x))
    return repr(x)


def vec(v):
    return "<%s>" % ", ".join(num(c) for c in v)


def glint_material(f):
    """glint material computing exactly what POV computes for finish f."""
    r = lambda x: round(x, 12)      # 0.8*0.7 -> 0.56, not 0.5599999999999999
    m = {"ambient": r(f["pigment"] * f["ambient"]),      # times L_a = AMBIENT_LIGHT
         "diffuse": r(f["pigment"] * f["diffuse"]),
         "specular": f["phong"],
         "shininess": f["phong_size"]}
    if f["reflection"]:
        m["reflectivity"] = f["reflection"]
    return m


def pov_texture(f):
    fin = "ambient %s diffuse %s phong %s phong_size %s" % (
        num(f["ambient"]), num(f["diffuse"]), num(f["phong"]), num(f["phong_size"]))
    if f["reflection"]:
        fin += " reflection { rgb %s }" % num(f["reflection"])
    return "texture { pigment { rgb %s } finish { %s } }" % (num(f["pigment"]), fin)


def fov_y_from_hfov(hfov, w, h):
    return math.degrees(2 * math.atan(math.tan(math.radians(hfov) / 2) * h / w))


# ------------------------------------------------------------------ meshes
class Mesh:
    """Vertices kept as text so that the .obj and the mesh2 carry identical numbers."""

    def __init__(self):
        self.v = []      # (xs, ys, zs) strings
        self.f = []      # (a, b, c) 0-based


def read_obj(path):
    m = Mesh()
    with open(path) as fh:
        for line in fh:
            t = line.split()
            if not t:
                continue
            if t[0] == "v":
                m.v.append(tuple(t[1:4]))
            elif t[0] == "f":
                idx = []
                for w in t[1:]:
                    i = int(w.split("/")[0])
                    idx.append(i - 1 if i > 0 else len(m.v) + i)
                for k in range(1, len(idx) - 1):
                    m.f.append((idx[0], idx[k], idx[k + 1]))
    return m


def terrain_h(x, z):
    s, c = math.sin, math.cos
    return (3.0 * s(0.15 * x) * c(0.12 * z) + 1.5 * s(0.37 * x + 1.0) * s(0.29 * z + 2.0)
            + 0.6 * s(1.1 * x + 0.5 * z) + 0.3 * s(2.3 * x) * c(2.7 * z)
            + 0.1 * s(7.0 * x) * s(6.0 * z) + 4.0)


def terrain_mesh(target_tris):
    """Height field over [0,100]^2 (x/z, y up): q x q cells, 2*q^2 triangles."""
    q = max(1, int(math.floor(math.sqrt(target_tris / 2.0) + 0.5)))
    n = q + 1
    S = 100.0
    m = Mesh()
    g = lambda x: "%.6g" % x
    for j in range(n):
        z = S * j / q
        zs = g(z)
        for i in range(n):
            x = S * i / q
            m.v.append((g(x), g(terrain_h(x, z)), zs))
    for j in range(q):
        for i in range(q):
            a = j * n + i
            b, c = a + 1, a + n
            d = c + 1
            m.f.append((a, c, b))
            m.f.append((b, c, d))
    return m


def terrain_normal(x, z):
    """Unit normal (-dh/dx, 1, -dh/dz) of the height field, by central differences."""
    e = 1e-4
    dx = (terrain_h(x + e, z) - terrain_h(x - e, z)) / (2 * e)
    dz = (terrain_h(x, z + e) - terrain_h(x, z - e)) / (2 * e)
    s = math.sqrt(dx * dx + 1 + dz * dz)
    return (-dx / s, 1 / s, -dz / s)


def terrain_normals(m, target_tris):
    """Per-vertex normal texts of terrain_mesh(target_tris), in its vertex order."""
    q = max(1, int(math.floor(math.sqrt(target_tris / 2.0) + 0.5)))
    n = q + 1
    S = 100.0
    g = lambda x: "%.6g" % x
    return [tuple(g(c) for c in terrain_normal(S * i / q, S * j / q)) for j in range(n) for i in range(n)]


def write_obj_normals(m, vn, path, comment):
    """The mesh with a normal per vertex: `vn` lines and `f a//a b//b c//c` (normal k for vertex k)."""
    with open(path, "w") as fh:
        fh.write("# %s\n# %d vertices, %d normals, %d triangles\n" % (comment, len(m.v), len(vn), len(m.f)))
        fh.write("".join("v %s %s %s\n" % v for v in m.v))
        fh.write("".join("vn %s %s %s\n" % n for n in vn))
        fh.write("".join("f %d//%d %d//%d %d//%d\n" % (a + 1, a + 1, b + 1, b + 1, c + 1, c + 1) for a, b, c in m.f))


def write_obj(m, path, comment):
    with open(path, "w") as fh:
        fh.write("# %s\n# %d vertices, %d triangles\n" % (comment, len(m.v), len(m.f)))
        fh.write("".join("v %s %s %s\n" % v for v in m.v))
        fh.write("".join("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in m.f))


def pov_mesh2(m, texture):
    out = ["mesh2 {", " vertex_vectors { %d," % len(m.v)]
    out.append(",\n".join("<%s,%s,%s>" % v for v in m.v))
    out.append(" }")
    out.append(" face_indices { %d," % len(m.f))
    out.append(",\n".join("<%d,%d,%d>" % f for f in m.f))
    out.append(" }")
    out.append(" " + texture)
    out.append("}")
    return "\n".join(out)


# ------------------------------------------------------------------ scenes
def base_scene(name, w, h, cam_pos, cam_look, hfov, light_pos):
    """The glint dict shared by all scenes; hfov is the reference POV scene's horizontal angle."""
    return {
        "render": {"width": w, "height": h, "samples_per_pixel": 1, "max_depth": MAX_DEPTH,
                   "shading_model": "phong", "background": BACKGROUND},
        "camera": {"type": "perspective", "position": cam_pos, "look_at": cam_look, "up": [0, 1, 0],
                   "fov_y": fov_y_from_hfov(hfov, w, h)},
        "materials": {"object": glint_material(FINISH_OBJ), "plane": glint_material(FINISH_PLANE)},
        "lights": [{"type": "point", "position": light_pos, "color": 1, "ambient": AMBIENT_LIGHT}],
        "objects": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "plane"}],
    }


def pov_header(name, sc, what):
    r, c = sc["render"], sc["camera"]
    L = sc["lights"][0]
    return "\n".join([
        "// %s.pov -- GENERATED by make_bench.py together with %s.json (the same scene for glint). Do not edit." % (name, name),
        "// %s" % what,
        "// povray -D -A +WT2 +W%d +H%d +O%s.png %s.pov" % (r["width"], r["height"], name, name),
        "#version 3.7;",
        "global_settings { assumed_gamma 1.0 ambient_light rgb %s max_trace_level %d adc_bailout 0 }"
        % (num(L["ambient"]), r["max_depth"]),
        "background { rgb %s }" % vec(r["background"]),
        "// glint's right-handed camera: right -x; POV's angle is horizontal, derived from glint's fov_y",
        "#declare FovY = %r;" % c["fov_y"],
        "camera { perspective location %s sky %s up y right -x*image_width/image_height" % (vec(c["position"]), vec(c["up"])),
        "  angle degrees(2*atan(tan(radians(FovY)/2)*image_width/image_height)) look_at %s }" % vec(c["look_at"]),
        "light_source { %s color rgb %s }" % (vec(L["position"]), num(L["color"])),
        "#declare T_Obj = %s" % pov_texture(FINISH_OBJ),
        "#declare T_Plane = %s" % pov_texture(FINISH_PLANE),
        "plane { <0, 1, 0>, 0 texture { T_Plane } }",
    ]) + "\n"


def _fmt(x, ind):
    """JSON with dicts indented, lists of numbers and scene objects on one line."""
    if isinstance(x, dict) and ind < 4:
        pad = " " * (ind + 2)
        items = ['%s%s: %s' % (pad, json.dumps(k), _fmt(v, ind + 2)) for k, v in x.items()]
        return "{\n" + ",\n".join(items) + "\n" + " " * ind + "}"
    if isinstance(x, list) and x and isinstance(x[0], dict):
        pad = " " * (ind + 2)
        return "[\n" + ",\n".join(pad + json.dumps(o) for o in x) + "\n" + " " * ind + "]"
    return json.dumps(x)


def write_json(sc, path):
    txt = _fmt(sc, 0) + "\n"
    assert json.loads(txt) == sc
    with open(path, "w") as fh:
        fh.write(txt)


def make_spheres(out):
    name = "spheres"
    sc = base_scene(name, 1920, 1080, [20, 9, -12], [20, 0, 12], 60, [10, 30, -10])
    lines = []
    for j in range(25):
        for i in range(40):
            c = [i + 0.5, 0.4, j + 0.5]
            sc["objects"].append({"type": "sphere", "center": c, "radius": 0.4, "material": "object"})
            lines.append("sphere { %s, 0.4 texture { T_Obj } }" % vec(c))
    write_json(sc, os.path.join(out, name + ".json"))
    with open(os.path.join(out, name + ".pov"), "w") as fh:
        fh.write(pov_header(name, sc, "1000 spheres (40 x 25 grid, r=0.4) on a reflective plane"))
        fh.write("\n".join(lines) + "\n")
    return "%s: 1000 spheres + plane" % name


def make_mesh_scene(out, name, m, obj_name, sc, what):
    sc["objects"].append({"type": "mesh", "file": obj_name, "smooth": False, "material": "object"})
    write_json(sc, os.path.join(out, name + ".json"))
    with open(os.path.join(out, name + ".pov"), "w") as fh:
        fh.write(pov_header(name, sc, what))
        fh.write("// the mesh of %s, flat shaded (glint: \"smooth\": false)\n" % obj_name)
        fh.write(pov_mesh2(m, "texture { T_Obj }") + "\n")


def make_bunny(out):
    src = BUNNY
    dst = os.path.join(out, "bunny.obj")
    if os.path.abspath(src) != os.path.abspath(dst):
        shutil.copyfile(src, dst)
    m = read_obj(src)
    sc = base_scene("bunny", 1920, 1080, [0, 7, -26], [0, 5, 0], 45, [-20, 40, -30])
    make_mesh_scene(out, "bunny", m, "bunny.obj", sc,
                    "Stanford bunny (%d triangles, bunny.obj) on a reflective plane" % len(m.f))
    return "bunny: %d triangles + plane" % len(m.f)


def make_terrain(out, tris):
    m = terrain_mesh(tris)
    write_obj(m, os.path.join(out, "terrain.obj"),
              "sum-of-sines height field over [0,100]^2, generated by make_bench.py")
    sc = base_scene("terrain", 1280, 720, [50, 25, -20], [50, 0, 45], 60, [30, 100, -30])
    make_mesh_scene(out, "terrain", m, "terrain.obj", sc,
                    "height field mesh (%d triangles, terrain.obj) + reflective plane y=0 (small lakes)" % len(m.f))
    return "terrain: %d triangles + plane" % len(m.f)


def make_terrain_normals(out, tris):
    name = "terrain-normals"
    m = terrain_mesh(tris)
    vn = terrain_normals(m, tris)
    write_obj_normals(m, vn, os.path.join(out, name + ".obj"),
                      "sum-of-sines height field over [0,100]^2 with vertex normals, generated by make_bench.py")
    sc = base_scene(name, 1280, 720, [50, 25, -20], [50, 0, 45], 60, [30, 100, -30])
    sc["objects"].append({"type": "mesh", "file": name + ".obj", "smooth": True, "material": "object"})
    write_json(sc, os.path.join(out, name + ".json"))
    with open(os.path.join(out, name + ".pov"), "w") as fh:
        fh.write(pov_header(name, sc, "height field mesh with vertex normals (%d triangles, %s.obj) + reflective plane"
                            % (len(m.f), name)))
        fh.write("// the mesh of %s.obj, smooth shaded with the file's normals (glint: \"smooth\": true)\n" % name)
        body = pov_mesh2(m, "texture { T_Obj }").split("\n")
        normals = [" normal_vectors { %d," % len(vn), ",\n".join("<%s,%s,%s>" % n for n in vn), " }"]
        at = body.index(" face_indices { %d," % len(m.f))
        fh.write("\n".join(body[:at] + normals + body[at:]) + "\n")
    return "%s: %d triangles with vertex normals + plane" % (name, len(m.f))


def main(argv):
    ap = argparse.ArgumentParser(description="Write glint benchmark scenes + equivalent POV-Ray scenes.")
    ap.add_argument("-o", "--out", default=os.path.join(HERE, "bench-scenes"),
                    help="output folder (default: bench-scenes/ beside this script)")
    ap.add_argument("--terrain-tris", type=int, default=1000000,
                    help="target triangle count of the terrain (default 1000000 -> 999,698)")
    ap.add_argument("--only", default="spheres,bunny,terrain",
                    help="comma list of scenes (also: terrain-normals, not made by default)")
    a = ap.parse_args(argv)
    if a.terrain_tris < 2:
        ap.error("--terrain-tris must be >= 2")
    only = [s for s in a.only.split(",") if s]
    for s in only:
        if s not in ("spheres", "bunny", "terrain", "terrain-normals"):
            ap.error("unknown scene %r (spheres, bunny, terrain, terrain-normals)" % s)
    os.makedirs(a.out, exist_ok=True)
    for s in only:
        if s == "spheres":
            msg = make_spheres(a.out)
        elif s == "bunny":
            msg = make_bunny(a.out)
        elif s == "terrain-normals":
            msg = make_terrain_normals(a.out, a.terrain_tris)
        else:
            msg = make_terrain(a.out, a.terrain_tris)
        print("wrote %s  (%s)" % (os.path.join(a.out, s + ".{json,pov}"), msg))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
