#!/usr/bin/env python3
# make_sky.py — writes sky.hdr, the environment map of scenes/envmap-spheres.json: an equirectangular
# (latitude-longitude) Radiance RGBE image, 256x128, of a clear sky (deep blue at the zenith, pale at the
# horizon), a brown ground below the horizon, and a small sun 35 degrees up towards +x (three quarters of the
# way across, as src/light/envmap.h orients maps). Made for glint; public domain (CC0).
import math
import struct

W, H = 256, 128
SUN_ELEVATION, SUN_RADIUS = math.radians(35.0), math.radians(2.5)
SUN = (math.cos(SUN_ELEVATION), math.sin(SUN_ELEVATION), 0.0)  # towards +x, up


def radiance(d):
    x, y, z = d
    cos_sun = x * SUN[0] + y * SUN[1] + z * SUN[2]
    if cos_sun > math.cos(SUN_RADIUS):
        return (300.0, 270.0, 220.0)
    if y < 0.0:  # the ground: dim, warm, darker towards the nadir
        g = 0.12 + 0.08 * (1.0 + y)
        return (g * 1.0, g * 0.8, g * 0.6)
    t = math.sqrt(y)  # from the horizon (0) to the zenith (1)
    glow = 0.6 * math.exp(-8.0 * (1.0 - cos_sun))  # brighter sky around the sun
    return ((0.9 - 0.7 * t) + glow, (0.95 - 0.55 * t) + glow * 0.9, 1.1 - 0.2 * t + glow * 0.7)


def rgbe(r, g, b):
    m = max(r, g, b)
    if m < 1e-32:
        return bytes((0, 0, 0, 0))
    mant, exp = math.frexp(m)
    scale = mant * 256.0 / m
    return bytes((int(r * scale), int(g * scale), int(b * scale), exp + 128))


with open("sky.hdr", "wb") as f:
    f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n")
    f.write(("-Y %d +X %d\n" % (H, W)).encode())
    for row in range(H):
        theta = math.pi * (row + 0.5) / H
        for col in range(W):
            phi = 2.0 * math.pi * ((col + 0.5) / W - 0.5)
            d = (math.sin(theta) * math.sin(phi), math.cos(theta), -math.sin(theta) * math.cos(phi))
            f.write(rgbe(*radiance(d)))
