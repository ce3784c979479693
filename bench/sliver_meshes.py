#!/usr/bin/env python3
"""bench/sliver_meshes.py — writes two meshes whose triangles are long and slanted, where a BVH over whole
triangles is weak and pre-splitting (src/accel/tri_split.h) or spatial splits pay: `slivers.obj`, a sphere of
6 bands from pole to pole cut into 20,000 thin segments (240,000 triangles), and `needles.obj`, 100,000 thin
needles of random direction in a box (a haystack). Both fit the bunny's place in the mesh yardstick's scene.

usage: python3 bench/sliver_meshes.py OUT_DIR
"""
import math
import os
import random
import sys


def slivers(path, bands=6, segments=20000, radius=0.07, centre=(-0.02, 0.11, 0.0)):
    cx, cy, cz = centre
    with open(path, "w") as f:
        for i in range(bands + 1):
            th = math.pi * i / bands
            for j in range(segments):
                ph = 2 * math.pi * j / segments
                f.write("v %.7f %.7f %.7f\n" % (cx + radius * math.sin(th) * math.cos(ph), cy + radius * math.cos(th),
                                                cz + radius * math.sin(th) * math.sin(ph)))
        for i in range(bands):
            for j in range(segments):
                a = i * segments + j + 1
                b = i * segments + (j + 1) % segments + 1
                f.write("f %d %d %d\nf %d %d %d\n" % (a, a + segments, b, b, a + segments, b + segments))


def unit(v, length):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n * length for x in v]


def needles(path, count=100000, seed=7):
    rnd = random.Random(seed)
    with open(path, "w") as f:
        for _ in range(count):
            c = [rnd.uniform(-0.09, 0.05), rnd.uniform(0.04, 0.18), rnd.uniform(-0.05, 0.05)]
            d = unit([rnd.gauss(0, 1) for _ in range(3)], 0.03)
            w = unit([rnd.gauss(0, 1) for _ in range(3)], 0.0015)
            ends = ([c[k] - d[k] for k in range(3)], [c[k] + d[k] for k in range(3)], [c[k] + w[k] for k in range(3)])
            for p in ends:
                f.write("v %.6f %.6f %.6f\n" % tuple(p))
        for i in range(count):
            f.write("f %d %d %d\n" % (3 * i + 1, 3 * i + 2, 3 * i + 3))


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: python3 bench/sliver_meshes.py OUT_DIR")
    os.makedirs(sys.argv[1], exist_ok=True)
    slivers(os.path.join(sys.argv[1], "slivers.obj"))
    needles(os.path.join(sys.argv[1], "needles.obj"))


if __name__ == "__main__":
    main()
