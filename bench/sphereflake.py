#!/usr/bin/python3
"""Write a sphereflake as an NFF scene, at any recursion depth.

    bench/sphereflake.py DEPTH [-o FILE.nff] [--resolution N]

The sphereflake, as Eric Haines described it for the Standard Procedural
Databases: a sphere with nine smaller spheres around it, six spaced evenly
around its equator and three on its upper side, each child a third of its
parent's radius; every child carries its own nine children, recursively.
Depth 0 is the lone sphere; depth d has 1 + 9 + ... + 9^d spheres
(depth 4: 7,381, the size of the SPD's balls; 5: 66,430; 6: 597,871).

This is our own construction from that description (not the SPD program):
each child touches its parent, and its own "equator" is the plane
perpendicular to the line from its parent, its "top" the side away from the
parent, so no sphere overlaps its parent. The spheres are reflective (Ks
0.5), on a large matte floor square under the root sphere, lit by three
point lights, seen from above at a slant like the SPD's balls.
"""

import argparse
import math
import sys

ROOT_RADIUS = 0.5
CHILD_SCALE = 1.0 / 3.0
# Three on the top side, this far above the child's equator (degrees), set
# between the equator ring's azimuths so that they clear the six below.
TOP_ELEVATION = math.radians(50.0)


def normalize(v):
    n = math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    return (v[0] / n, v[1] / n, v[2] / n)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def frame(axis):
    """Two unit vectors perpendicular to the unit vector axis and to each other."""
    helper = (1.0, 0.0, 0.0) if abs(axis[0]) < 0.9 else (0.0, 1.0, 0.0)
    u = normalize(cross(helper, axis))
    return u, cross(axis, u)


def child_directions(axis):
    """Unit directions from a sphere's center to its nine children's centers.

    axis: the sphere's "up" (away from its parent). Six at the equator, every
    60 degrees; three above it, every 120 degrees, halfway between the six.
    """
    u, v = frame(axis)
    dirs = []
    for k in range(6):
        a = math.radians(60.0 * k)
        dirs.append(tuple(math.cos(a) * u[i] + math.sin(a) * v[i] for i in range(3)))
    ce, se = math.cos(TOP_ELEVATION), math.sin(TOP_ELEVATION)
    for k in range(3):
        a = math.radians(30.0 + 120.0 * k)
        dirs.append(tuple(ce * (math.cos(a) * u[i] + math.sin(a) * v[i]) + se * axis[i]
                          for i in range(3)))
    return dirs


def flake(center, radius, axis, depth, out):
    """Appends (x, y, z, r) for the sphere and all its descendants to out."""
    out.append((center[0], center[1], center[2], radius))
    if depth == 0:
        return
    r = radius * CHILD_SCALE
    for d in child_directions(axis):
        c = tuple(center[i] + (radius + r) * d[i] for i in range(3))
        flake(c, r, d, depth - 1, out)


def sphere_count(depth):
    return sum(9 ** k for k in range(depth + 1))


def write_nff(f, depth, resolution):
    spheres = []
    flake((0.0, 0.0, 0.0), ROOT_RADIUS, (0.0, 0.0, 1.0), depth, spheres)
    w = f.write
    w("# sphereflake, depth %d: %d spheres (bench/sphereflake.py)\n" % (depth, len(spheres)))
    w("b 0.078 0.361 0.753\n")
    w("v\nfrom 2.1 1.3 1.7\nat 0 0 0\nup 0 0 1\nangle 45\nhither 0.01\n")
    w("resolution %d %d\n" % (resolution, resolution))
    for light in ((4, 3, 2), (1, -4, 4), (-3, 1, 5)):
        w("l %g %g %g\n" % light)
    # The floor: a matte square just under the root sphere.
    w("f 1 0.75 0.33 0.8 0 100000 0 1\n")
    w("p 4\n12 12 -0.5\n-12 12 -0.5\n-12 -12 -0.5\n12 -12 -0.5\n")
    w("f 1 0.9 0.7 0.5 0.5 3.0827 0 1\n")
    w("".join("s %.7g %.7g %.7g %.7g\n" % s for s in spheres))
    return len(spheres)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("depth", type=int, help="recursion depth, 0-7 (6: 597,871 spheres)")
    p.add_argument("-o", "--output", help="output .nff (default: standard output)")
    p.add_argument("--resolution", type=int, default=512, help="the view's resolution (default 512)")
    a = p.parse_args()
    if not 0 <= a.depth <= 7:
        p.error("depth must be from 0 to 7")
    if a.output:
        with open(a.output, "w", encoding="ascii") as f:
            n = write_nff(f, a.depth, a.resolution)
    else:
        n = write_nff(sys.stdout, a.depth, a.resolution)
    assert n == sphere_count(a.depth)
    print("sphereflake depth %d: %d spheres" % (a.depth, n), file=sys.stderr)


if __name__ == "__main__":
    main()
