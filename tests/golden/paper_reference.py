#!/usr/bin/env python3
"""paper_reference.py — an independent reference of the paper's OCaml ray tracer, for glint's golden test.

Written from what the paper's program computes (issue 2, "Facts"), not from glint's C code, in pure
Python: Python floats are IEEE doubles and `**` on floats calls the C library's pow(), as OCaml's
`**` does, so every operation below is the OCaml program's operation in the same order.

    python3 tests/golden/paper_reference.py [--distance 0.58] [-o tests/golden/paper.ppm]

Writes a binary P6 image, 768x768. Takes about a minute.
"""
import argparse
import math
import sys

WIDTH = HEIGHT = 768
INF = math.inf

# (centre, radius, colour, specular exponent s, reflectiveness rfl), in the program's list order.
SPHERES = [
    ((0.0, -1.0, 3.0), 1.0, (255, 0, 0), 9900, 0.2),
    ((-2.0, 1.0, 3.0), 1.0, (0, 0, 255), 5, 0.0),
    ((2.0, 1.0, 3.0), 1.0, (0, 255, 0), 50, 0.5),
    ((0.0, -5001.0, 0.0), 5000.0, (255, 255, 0), 1000, 0.01),
]

# (kind, intensity, vector): 'a' ambient, 'p' point (position), 'd' directional (towards the light).
LIGHTS = [
    ("a", 0.2, None),
    ("p", 0.6, (2.0, 1.0, 0.0)),
    ("d", 0.2, (1.0, 4.0, 4.0)),
]


def sub3(p, q):
    return (p[0] - q[0], p[1] - q[1], p[2] - q[2])


def add3(p, q):
    return (p[0] + q[0], p[1] + q[1], p[2] + q[2])


def scale(k, p):
    return (k * p[0], k * p[1], k * p[2])


def sproduct(p, q):
    return p[0] * q[0] + p[1] * q[1] + p[2] * q[2]


def norm(p):
    return math.sqrt(sproduct(p, p))


def intersect_sphere(o, d, sph):
    """Both roots of |o + t d - c|^2 = r^2 as the textbook formula gives them, or None."""
    centre, radius = sph[0], sph[1]
    co = sub3(o, centre)
    a = sproduct(d, d)
    b = 2.0 * sproduct(d, co)
    c = sproduct(co, co) - radius * radius
    disc = b * b - 4.0 * a * c
    if disc >= 0.0:
        return ((-b + math.sqrt(disc)) / (2.0 * a), (-b - math.sqrt(disc)) / (2.0 * a))
    return None


def closest_sphere(o, d, tmin, tmax):
    """Closest sphere with a root in [tmin, tmax]; ties go to the later root and the later sphere."""
    best, best_t = None, INF
    for sph in SPHERES:
        roots = intersect_sphere(o, d, sph)
        if roots is None:
            continue
        for t in roots:
            if tmin <= t <= tmax and t <= best_t:
                best, best_t = sph, t
    return best, best_t


def reflected_ray(ncap, l):
    return sub3(scale(2.0 * sproduct(l, ncap), ncap), l)


def diffuse_i(normal, l, i, acc):
    nl = sproduct(normal, l)
    if nl > 0.0:
        return acc + i * nl / (norm(l) * norm(normal))
    return acc


def specular_i(o, p, ncap, l, i, s, acc):
    refl = reflected_ray(ncap, l)
    view = sub3(o, p)
    rv = sproduct(refl, view)
    if rv > 0.0 and s > 0:
        return acc + i * (rv / (norm(refl) * norm(view))) ** float(s)
    return acc


def total_intensity(normal, p, o, s):
    intensity = 0.0
    for kind, i, v in LIGHTS:
        c = 0.0
        if kind == "a":
            c = i + c
        else:
            if kind == "p":
                l, tmax = sub3(v, p), 1.0
            else:
                l, tmax = v, INF
            blocker, _ = closest_sphere(p, l, 0.0001, tmax)
            if blocker is None:
                ncap = scale(1.0 / norm(normal), normal)
                c = specular_i(o, p, ncap, l, i, s, c)
                c = diffuse_i(normal, l, i, c)
        intensity = intensity + c
    return intensity


def trace(o, d, tmin, tmax, limit):
    """(sphere hit or None, scalar intensity) along o + t d."""
    sph, t = closest_sphere(o, d, tmin, tmax)
    if sph is None:
        return None, 0.0
    p = add3(o, scale(t, d))
    normal = sub3(p, sph[0])
    intensity = total_intensity(normal, p, o, sph[3])
    rfl = sph[4]
    if rfl > 0.0 and limit > 0:
        refl = reflected_ray(scale(1.0 / norm(normal), normal), scale(-1.0, d))
        hit, other = trace(p, refl, 0.001, INF, limit - 1)
        if hit is None:
            other = 0.0
        intensity = intensity * (1.0 - rfl) + rfl * other
    return sph, intensity


def clamp(x):
    if x > 255.0:
        return 255
    if x < 0.0:
        return 0
    return int(x)  # truncation towards zero, as OCaml's truncate


def render(distance):
    origin = (0.0, 0.0, 0.0)
    out = bytearray()
    for row in range(HEIGHT):  # row 0 is the top of the window
        gy = HEIGHT // 2 - 1 - row
        for col in range(WIDTH):
            gx = col - WIDTH // 2
            v = ((gx * 1.0) / WIDTH, (gy * 1.0) / HEIGHT, distance)
            d = sub3(v, origin)
            sph, intensity = trace(origin, d, 1.0, INF, 3)
            if sph is None:
                out += bytes((255, 255, 255))
            else:
                out += bytes(clamp(float(ch) * intensity) for ch in sph[2])
    return bytes(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--distance", type=float, default=0.58, help="viewport distance d (0.58 as in Fig. 8)")
    ap.add_argument("-o", "--output", default="paper.ppm", help="output P6 image")
    args = ap.parse_args()
    pixels = render(args.distance)
    with open(args.output, "wb") as f:
        f.write(b"P6\n%d %d\n255\n" % (WIDTH, HEIGHT))
        f.write(pixels)
    return 0


if __name__ == "__main__":
    sys.exit(main())
