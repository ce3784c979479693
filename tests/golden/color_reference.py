#!/usr/bin/env python3
"""color_reference.py — an independent reference of glint's colour Whitted mode on the paper's scene.

The colour ray tracer of "Computer Graphics from Scratch" (the model of issue 2, item 4), written
plainly in double precision: RGB colour = sphere colour * (ambient + diffuse + specular intensity),
local * (1 - rfl) + rfl * reflected colour, a white background for rays that escape, shadow and
reflected rays from the hit point with t > 0.001, clamped and rounded to nearest only at the end.
The paper's spheres and lights, viewed through the paper's viewport camera (d = 0.58).

    python3 tests/golden/color_reference.py [--size 256] [-o tests/golden/paper-color-256.ppm]
"""
import argparse
import math
import sys

INF = math.inf
# (centre, radius, colour 0..1, specular exponent, reflectiveness)
SPHERES = [
    ((0.0, -1.0, 3.0), 1.0, (1.0, 0.0, 0.0), 9900, 0.2),
    ((-2.0, 1.0, 3.0), 1.0, (0.0, 0.0, 1.0), 5, 0.0),
    ((2.0, 1.0, 3.0), 1.0, (0.0, 1.0, 0.0), 50, 0.5),
    ((0.0, -5001.0, 0.0), 5000.0, (1.0, 1.0, 0.0), 1000, 0.01),
]
LIGHTS = [("ambient", 0.2, None), ("point", 0.6, (2.0, 1.0, 0.0)), ("directional", 0.2, (1.0, 4.0, 4.0))]
BACKGROUND = (1.0, 1.0, 1.0)
DEPTH = 3


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def scale(k, a):
    return (k * a[0], k * a[1], k * a[2])


def length(a):
    return math.sqrt(dot(a, a))


def intersect(o, d, sphere):
    co = sub(o, sphere[0])
    a, b, c = dot(d, d), 2.0 * dot(co, d), dot(co, co) - sphere[1] * sphere[1]
    disc = b * b - 4.0 * a * c
    if disc < 0.0:
        return ()
    s = math.sqrt(disc)
    return ((-b + s) / (2.0 * a), (-b - s) / (2.0 * a))


def closest(o, d, tmin, tmax):
    best, best_t = None, INF
    for sphere in SPHERES:
        for t in intersect(o, d, sphere):
            if tmin < t < tmax and t < best_t:
                best, best_t = sphere, t
    return best, best_t


def lighting(p, n, v, shininess):
    """Summed light intensity at p (unit normal n, towards-viewer vector v)."""
    total = 0.0
    for kind, intensity, vec in LIGHTS:
        if kind == "ambient":
            total += intensity
            continue
        l, tmax = (sub(vec, p), 1.0) if kind == "point" else (vec, INF)
        if closest(p, l, 0.001, tmax)[0] is not None:
            continue
        nl = dot(n, l)
        if nl > 0.0:
            total += intensity * nl / length(l)
        if shininess > 0:
            r = sub(scale(2.0 * nl, n), l)
            rv = dot(r, v)
            if rv > 0.0:
                total += intensity * (rv / (length(r) * length(v))) ** shininess
    return total


def trace(o, d, tmin, depth):
    sphere, t = closest(o, d, tmin, INF)
    if sphere is None:
        return BACKGROUND
    p = add(o, scale(t, d))
    n = sub(p, sphere[0])
    n = scale(1.0 / length(n), n)
    v = scale(-1.0, d)
    local = scale(lighting(p, n, v, sphere[3]), sphere[2])
    rfl = sphere[4]
    if depth <= 0 or rfl <= 0.0:
        return local
    reflected = sub(scale(2.0 * dot(n, v), n), v)
    return add(scale(1.0 - rfl, local), scale(rfl, trace(p, reflected, 0.001, depth - 1)))


def encode(x):
    return max(0, min(255, round(x * 255.0)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=256, help="image width and height")
    ap.add_argument("--distance", type=float, default=0.58, help="viewport distance")
    ap.add_argument("-o", "--output", default="paper-color-256.ppm", help="output P6 image")
    args = ap.parse_args()
    size = args.size
    out = bytearray()
    for row in range(size):
        gy = size // 2 - 1 - row  # the paper's canvas: no half-pixel offset
        for col in range(size):
            gx = col - size // 2
            colour = trace((0.0, 0.0, 0.0), (gx / size, gy / size, args.distance), 1.0, DEPTH)
            out += bytes(encode(c) for c in colour)
    with open(args.output, "wb") as f:
        f.write(b"P6\n%d %d\n255\n" % (size, size))
        f.write(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
