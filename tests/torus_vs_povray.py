#!/usr/bin/env python3
"""glint's torus against POV-Ray's (an independent quartic solver: Sturm
sequences): the same tori, seen by an orthographic and a perspective camera
through the same pixel centers, must cover the same pixels. Exit 77 (skipped) without povray.

usage: torus_vs_povray.py GLINT WORK_DIR
"""
import json
import math
import pathlib
import shutil
import subprocess
import sys

W, H, VIEW, FOV_Y = 160, 120, 6.0, 40.0
# (major, minor, rotation about x in degrees, translation): thin and fat
# tubes, seen edge on (the grazing silhouette) and through the hole.
TORI = [(2.0, 0.5, 0, (0, 0, 0)), (2.0, 0.5, 90, (0, 0, 0)), (2.0, 0.5, 88, (0.3, -0.2, 1)),
        (1.5, 1.2, 35, (0.2, 0.1, 0)), (2.4, 0.05, 60, (-0.1, 0.2, 0.5)), (1.0, 0.3, 5, (1.1, 0.7, -2))]


def read_ppm(path):
    data = path.read_bytes()
    fields, pos = [], 0
    while len(fields) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":  # a comment (POV-Ray writes some), to the end of its line
            pos = data.index(b"\n", pos)
            continue
        start = pos
        while not data[pos:pos + 1].isspace():
            pos += 1
        fields.append(data[start:pos])
    w, h = int(fields[1]), int(fields[2])
    pixels = data[pos + 1:]
    return [pixels[3 * i] > 127 for i in range(w * h)]


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    glint, work = sys.argv[1], pathlib.Path(sys.argv[2])
    if not shutil.which("povray"):
        print("skipped: povray not found")
        sys.exit(77)
    work.mkdir(parents=True, exist_ok=True)
    worst = 1.0
    cases = [(k, torus, cam) for k, torus in enumerate(TORI) for cam in ("orthographic", "perspective")]
    for k, (major, minor, angle, t), cam in cases:
        a = math.radians(angle)
        scene = {
            "render": {"width": W, "height": H, "background": 0},
            "camera": ({"type": "orthographic", "position": [0, 0, 10], "look_at": [0, 0, 0], "view_height": VIEW}
                       if cam == "orthographic" else
                       {"position": [0, 0, 10], "look_at": [0, 0, 0], "fov_y": FOV_Y}),
            "materials": {"white": {"ambient": 1, "diffuse": 0, "specular": 0}},
            "lights": [{"type": "ambient", "ambient": 1}],
            # Rotated about +x by the right-hand rule: the axis (0, cos a, sin a).
            "objects": [{"type": "torus", "center": list(t), "axis": [0, math.cos(a), math.sin(a)],
                         "major_radius": major, "minor_radius": minor, "material": "white"}],
        }
        (work / f"torus{k}.json").write_text(json.dumps(scene))
        subprocess.run([glint, "render", str(work / f"torus{k}.json"), "-o", str(work / f"glint{k}.ppm"), "--quiet"],
                       check=True)
        # POV-Ray is left-handed: glint's (x, y, z) is its (x, y, -z), the
        # camera at -z looks toward +z, and the axis (0, cos a, -sin a) is
        # its y turned by -a about x (same rotation formula, other handedness).
        # POV-Ray's perspective `angle` is the horizontal field of view.
        fov_x = math.degrees(2 * math.atan(W / H * math.tan(math.radians(FOV_Y / 2))))
        pov_camera = (f"orthographic location <0, 0, -10> look_at <0, 0, 0> right <{VIEW * W / H}, 0, 0> up <0, {VIEW}, 0>"
                      if cam == "orthographic" else
                      f"perspective location <0, 0, -10> look_at <0, 0, 0> right <{W / H}, 0, 0> up <0, 1, 0> angle {fov_x}")
        pov = f"""global_settings {{ assumed_gamma 1.0 ambient_light 1 }}
camera {{ {pov_camera} }}
background {{ rgb 0 }}
torus {{ {major}, {minor} pigment {{ rgb 1 }} finish {{ ambient 1 diffuse 0 }}
  rotate <{-angle}, 0, 0> translate <{t[0]}, {t[1]}, {-t[2]}> }}
"""
        (work / f"torus{k}.pov").write_text(pov)
        subprocess.run(["povray", "-D", "-A", "+FP", f"+W{W}", f"+H{H}", f"+O{work / f'pov{k}.ppm'}",
                        str(work / f"torus{k}.pov")], check=True, capture_output=True)
        ours, theirs = read_ppm(work / f"glint{k}.ppm"), read_ppm(work / f"pov{k}.ppm")
        same = sum(1 for x, y in zip(ours, theirs) if x == y) / len(ours)
        covered = sum(ours) / len(ours)
        print(f"torus {k} (R {major}, r {minor}, {angle} deg), {cam}: {covered:.1%} covered, masks agree on {same:.4%}")
        worst = min(worst, same)
        if covered < 0.01:
            sys.exit(f"error: torus {k} covers almost nothing: the test scene is wrong")
    # Only pixels whose centers lie within rounding of the silhouette may differ.
    if worst < 0.999:
        sys.exit(f"error: masks agree on only {worst:.4%} of the pixels")


if __name__ == "__main__":
    main()
