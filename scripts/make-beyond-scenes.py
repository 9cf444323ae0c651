#!/usr/bin/env python3
"""Writes the generated parts of scenes/beyond/: the procedural sky
(sky.hdr, a small Radiance RGBE latitude-longitude map: a blue gradient, a
warm horizon, a sun and a gray ground) and the torus knot of tori
(torus-knot.json: a chain of interlocking tori along a (2, 3) torus knot). Standard library only.

    python3 scripts/make-beyond-scenes.py
"""
import json
import math
import pathlib
import struct

OUT = pathlib.Path(__file__).resolve().parent.parent / "scenes" / "beyond"


def sky_texel(d):
    """Linear RGB of the sky in unit direction d (y up)."""
    x, y, z = d
    if y < 0:  # the ground: gray, a little lighter toward the horizon
        k = 0.25 + 0.1 * math.exp(8 * y)
        return (k, k * 0.95, k * 0.9)
    zenith, horizon = (0.15, 0.35, 0.9), (0.95, 0.85, 0.7)
    t = math.exp(-6 * y)
    c = [zenith[i] * (1 - t) + horizon[i] * t for i in range(3)]
    sun = (0.45, 0.6, -0.66)  # toward the upper left behind the scene
    n = math.sqrt(sum(s * s for s in sun))
    cos = (x * sun[0] + y * sun[1] + z * sun[2]) / n
    glow = 40.0 if cos > math.cos(math.radians(2.0)) else 0.0
    glow += 1.5 * max(0.0, cos) ** 64
    return tuple(ci + glow * w for ci, w in zip(c, (1.0, 0.9, 0.75)))


def rgbe(c):
    m = max(c)
    if m < 1e-32:
        return bytes(4)
    e = math.frexp(m)[1]
    s = 256.0 / 2 ** e
    return bytes([min(255, int(c[0] * s)), min(255, int(c[1] * s)), min(255, int(c[2] * s)), e + 128])


def write_sky(path, w=256, h=128):
    rows = []
    for j in range(h):
        v = (j + 0.5) / h
        theta = v * math.pi  # v = acos(d.y) / pi: row 0 straight up
        for i in range(w):
            u = (i + 0.5) / w
            phi = (u - 0.5) * 2 * math.pi  # u = 0.5 + atan2(d.x, -d.z) / 2pi
            d = (math.sin(theta) * math.sin(phi), math.cos(theta), -math.sin(theta) * math.cos(phi))
            rows.append(rgbe(sky_texel(d)))
    header = f"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {h} +X {w}\n".encode()
    path.write_bytes(header + b"".join(rows))  # flat (not run-length) scanlines


def torus_knot(p=2, q=3):
    """A chain of interlocking tori along the knot: each link's plane holds
    the curve's tangent, turned a quarter about it from the last link's."""
    objects = [{"type": "plane", "point": [0, -2.2, 0], "normal": [0, 1, 0], "material": "floor"}]
    def at(t):
        r = 2 + math.cos(q * t)
        return (r * math.cos(p * t), math.sin(q * t), r * math.sin(p * t))
    def sub(a, b):
        return [a[i] - b[i] for i in range(3)]
    def unit(v):
        n = math.sqrt(sum(x * x for x in v))
        return [x / n for x in v]
    def cross(a, b):
        return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    steps = 20000
    length = sum(math.dist(at(2 * math.pi * i / steps), at(2 * math.pi * (i + 1) / steps)) for i in range(steps))
    major, minor = 0.2, 0.055
    n = 2 * round(length / (2 * (2 * major - 1.6 * minor)))  # even: the links alternate all the way round
    for k in range(n):
        t = 2 * math.pi * k / n
        tangent = unit(sub(at(t + 1e-4), at(t - 1e-4)))
        side = unit(cross(tangent, [0, 1, 0]))
        axis = side if k % 2 == 0 else cross(tangent, side)
        objects.append({"type": "torus", "center": [round(x, 6) for x in at(t)], "axis": [round(x, 6) for x in axis],
                        "major_radius": major, "minor_radius": minor,
                        "material": "gold" if k % 2 == 0 else "steel"})
    return {
        "render": {"width": 480, "height": 360, "samples_per_pixel": 4, "max_depth": 4,
                   "background": [0.04, 0.05, 0.08]},
        "camera": {"position": [0, 6.5, 8.5], "look_at": [0, -0.3, 0], "fov_y": 38},
        "materials": {
            "gold": {"ambient": [0.08, 0.06, 0.01], "diffuse": [0.75, 0.55, 0.15], "specular": [0.9, 0.8, 0.5],
                     "shininess": 120, "reflectivity": [0.25, 0.2, 0.08]},
            "steel": {"ambient": 0.04, "diffuse": 0.35, "specular": 0.9, "shininess": 200, "reflectivity": 0.35},
            "floor": {"ambient": 0.05, "diffuse": 0.5, "specular": 0.1, "reflectivity": 0.2},
        },
        "lights": [{"type": "ambient", "ambient": 0.5},
                   {"type": "point", "position": [-5, 9, 6], "color": 0.9},
                   {"type": "directional", "direction": [0.4, -1, -0.3], "color": 0.3}],
        "objects": objects,
    }


def main():
    OUT.mkdir(parents=True, exist_ok=True)
    write_sky(OUT / "sky.hdr")
    (OUT / "torus-knot.json").write_text(json.dumps(torus_knot(), indent=1) + "\n", encoding="utf-8")
    print(f"wrote {OUT / 'sky.hdr'} and {OUT / 'torus-knot.json'}")


if __name__ == "__main__":
    main()
