#!/usr/bin/env python3
"""Writes scenes/rtiow2-bouncing-spheres.json from the layout that book 2's program generates.

The layout (tools/layouts/rtiow-book2-bouncing-spheres.json, with its source and licence) was dumped from an
instrumented copy of "Ray Tracing: The Next Week"'s program. Its source note: RayTracing/raytracing.github.io
@ 94b510c2201e58464964b828328de0f5c52896c6 (branch release, 2024-03-16), src/TheNextWeek/main.cc, function
random_spheres() (bouncing_spheres() in later versions), built with g++ 12.2 -O3 -march=native against glibc
2.36, random_double() = rand()/(RAND_MAX+1.0) with glibc rand() at its default seed. Scene files hold no
comments, so docs/scene-format.md repeats this. Every number is written as the layout holds it (the shortest text that reads
back to the program's double). Usage: make_rtiow2_bouncing_spheres.py LAYOUT.json > scenes/rtiow2-bouncing-spheres.json
"""
import json
import sys


def num(x):
    return json.dumps(x)


def vec(v):
    return "[" + ", ".join(num(x) for x in v) + "]"


def material(m):
    kind = m["type"]
    if kind == "lambertian":
        if "texture" in m:
            return '"ground"'
        return '{"type": "lambertian", "albedo": %s}' % vec(m["albedo"])
    if kind == "metal":
        return '{"type": "metal", "albedo": %s, "fuzz": %s}' % (vec(m["albedo"]), num(m["fuzz"]))
    if kind == "dielectric":
        return '{"type": "dielectric", "ior": %s}' % num(m["ior"])
    raise SystemExit("unknown material type %r" % kind)


def main():
    layout = json.load(open(sys.argv[1]))
    cam = layout["camera"]
    ref = layout["main_cc_settings"]
    width = ref["image_width"]
    height = int(width / cam["aspect_ratio"])
    ground = layout["spheres"][0]["material"]["texture"]
    out = []
    out.append("{")
    out.append('  "render": {"width": %d, "height": %d, "spp": %d, "max_depth": %d, "integrator": "path", '
               '"background": %s, "output": "gamma2"},' % (width, height, ref["samples_per_pixel"], ref["max_depth"],
                                                          vec(cam["background"])))
    out.append('  "camera": {"type": "lookat", "lookfrom": %s, "lookat": %s, "vup": %s, "vfov": %s, '
               '"defocus_angle": %s, "focus_distance": %s, "shutter": %s},' %
               (vec(cam["lookfrom"]), vec(cam["lookat"]), vec(cam["vup"]), num(cam["vfov_degrees"]),
                num(cam["defocus_angle_degrees"]), num(cam["focus_dist"]), vec(cam["shutter"])))
    out.append('  "textures": {"checker": {"type": "checker", "scale": %s, "even": %s, "odd": %s}},' %
               (num(ground["scale"]), vec(ground["even"]), vec(ground["odd"])))
    out.append('  "materials": {"ground": {"type": "lambertian", "albedo": "checker"}},')
    out.append('  "objects": [')
    objs = []
    for s in layout["spheres"]:
        move = ', "center2": %s' % vec(s["center2"]) if s["moving"] else ""
        objs.append('    {"type": "sphere", "center": %s%s, "radius": %s, "material": %s}' %
                    (vec(s["center"]), move, num(s["radius"]), material(s["material"])))
    out.append(",\n".join(objs))
    out.append("  ]")
    out.append("}")
    print("\n".join(out))


if __name__ == "__main__":
    main()
