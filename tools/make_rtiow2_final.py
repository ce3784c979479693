#!/usr/bin/env python3
"""Writes scenes/rtiow2-final.json, book 2's final scene, from the layout that book 2's program builds.

The layout (tools/layouts/rtiow-book2-final-scene.json, with its source and licence) was dumped from an instrumented
copy of "Ray Tracing: The Next Week"'s program. Its source note: RayTracing/raytracing.github.io @
94b510c2201e58464964b828328de0f5c52896c6 (branch release, 2024-03-16), src/TheNextWeek/main.cc, function
final_scene(), built with g++ 12.2 -O3 -march=native against glibc 2.36, random_double() =
rand()/(RAND_MAX+1.0) with glibc rand() at its default seed. Every number is written as the layout holds it
(the shortest text that reads back to the program's double); the cluster's centres are rotated and moved
here, in double precision, as the program's rotate_y and translate do. What glint is told so that it does
what the program does (the layout's notes state the program's rules):
  - the earth texture is used as bytes / 255 with the nearest texel ("encoding": "linear", "filter": "nearest");
  - the noise sphere is the program's marble, turbulence of the scaled point, with the Perlin tables it drew;
  - the light emits from both sides ("two_sided");
  - the blue sphere is a glass sphere plus a medium bounded by the same sphere; the fog is a medium whose
    boundary sphere (radius 5000) holds the camera and everything else;
  - 8-bit output as gamma 2 (the program writes int(256 clamp(sqrt(v), 0, 0.999))).
Usage: make_rtiow2_final.py LAYOUT.json > scenes/rtiow2-final.json
"""
import json
import math
import sys


def num(x):
    return json.dumps(x)


def vec(v):
    return "[" + ", ".join(num(x) for x in v) + "]"


def main():
    layout = json.load(open(sys.argv[1]))
    cam = layout["camera"]
    out = ["{"]
    out.append('  "render": {"width": 400, "height": 400, "spp": 100, "max_depth": 40, "integrator": "path", '
               '"background": %s, "output": "gamma2"},' % vec(cam["background"]))
    out.append('  "camera": {"type": "lookat", "lookfrom": %s, "lookat": %s, "vup": %s, "vfov": %s, '
               '"defocus_angle": %s, "focus_distance": %s, "shutter": %s},' %
               (vec(cam["lookfrom"]), vec(cam["lookat"]), vec(cam["vup"]), num(cam["vfov_degrees"]),
                num(cam["defocus_angle_degrees"]), num(cam["focus_dist"]), vec(cam["shutter"])))
    noise = layout["noise_sphere"]["material"]["texture"]
    tables = noise["perlin"]
    earth = layout["earth_sphere"]["material"]["texture"]
    out.append('  "textures": {')
    out.append('    "earth": {"type": "image", "file": "textures/%s", "encoding": "linear", "filter": "nearest"},'
               % earth["file"])
    out.append('    "marble": {"type": "marble", "scale": %s, "depth": 7, "scaled_turbulence": true, "perlin": {' %
               num(noise["scale"]))
    out.append('      "gradients": [%s],' % ", ".join(vec(g) for g in tables["ranvec"]))
    for axis in ("perm_x", "perm_y", "perm_z"):
        out.append('      "%s": [%s]%s' % (axis, ", ".join(str(int(p)) for p in tables[axis]),
                                          "," if axis != "perm_z" else ""))
    out.append("    }}")
    out.append("  },")
    ground = layout["ground_boxes"]["material"]["albedo"]
    light = layout["light"]
    moving = layout["moving_sphere"]
    metal = layout["metal_sphere"]["material"]
    cluster = layout["sphere_cluster"]
    out.append('  "materials": {')
    out.append('    "ground": {"type": "lambertian", "albedo": %s},' % vec(ground))
    out.append('    "light": {"type": "diffuse_light", "emission": %s, "two_sided": true},' %
               vec(light["material"]["emit"]))
    out.append('    "orange": {"type": "lambertian", "albedo": %s},' % vec(moving["material"]["albedo"]))
    out.append('    "glass": {"type": "dielectric", "ior": %s},' % num(layout["glass_sphere"]["material"]["ior"]))
    out.append('    "metal": {"type": "metal", "albedo": %s, "fuzz": %s},' % (vec(metal["albedo"]), num(metal["fuzz"])))
    out.append('    "earth": {"type": "lambertian", "albedo": "earth"},')
    out.append('    "marble": {"type": "lambertian", "albedo": "marble"},')
    out.append('    "white": {"type": "lambertian", "albedo": %s}' % vec(cluster["material"]["albedo"]))
    out.append("  },")
    objs = []
    for b in layout["ground_boxes"]["boxes"]:
        objs.append('    {"type": "box", "min": %s, "max": %s, "material": "ground"}' % (vec(b["min"]), vec(b["max"])))
    objs.append('    {"type": "quad", "q": %s, "u": %s, "v": %s, "material": "light"}' %
                (vec(light["Q"]), vec(light["u"]), vec(light["v"])))
    objs.append('    {"type": "sphere", "center": %s, "center2": %s, "radius": %s, "material": "orange"}' %
                (vec(moving["center1"]), vec(moving["center2"]), num(moving["radius"])))
    g = layout["glass_sphere"]
    objs.append('    {"type": "sphere", "center": %s, "radius": %s, "material": "glass"}' % (vec(g["center"]), num(g["radius"])))
    m = layout["metal_sphere"]
    objs.append('    {"type": "sphere", "center": %s, "radius": %s, "material": "metal"}' % (vec(m["center"]), num(m["radius"])))
    sub = layout["subsurface_sphere"]
    sb = sub["boundary"]
    objs.append('    {"type": "sphere", "center": %s, "radius": %s, "material": "glass"}' % (vec(sb["center"]), num(sb["radius"])))
    objs.append('    {"type": "constant_medium", "density": %s, "albedo": %s, "boundary": {"type": "sphere", "center": %s, '
                '"radius": %s}}' % (num(sub["medium"]["density"]), vec(sub["medium"]["albedo"]), vec(sb["center"]),
                                   num(sb["radius"])))
    fog = layout["fog"]
    objs.append('    {"type": "constant_medium", "density": %s, "albedo": %s, "boundary": {"type": "sphere", "center": %s, '
                '"radius": %s}}' % (num(fog["medium"]["density"]), vec(fog["medium"]["albedo"]),
                                   vec(fog["boundary"]["center"]), num(fog["boundary"]["radius"])))
    e = layout["earth_sphere"]
    objs.append('    {"type": "sphere", "center": %s, "radius": %s, "material": "earth"}' % (vec(e["center"]), num(e["radius"])))
    n = layout["noise_sphere"]
    objs.append('    {"type": "sphere", "center": %s, "radius": %s, "material": "marble"}' % (vec(n["center"]), num(n["radius"])))
    s, c = cluster["sin_theta"], cluster["cos_theta"]
    t = cluster["translate"]
    for p in cluster["centers_before_transform"]:
        w = [c * p[0] + s * p[2] + t[0], p[1] + t[1], -s * p[0] + c * p[2] + t[2]]
        objs.append('    {"type": "sphere", "center": %s, "radius": %s, "material": "white"}' % (vec(w), num(cluster["radius"])))
    out.append('  "objects": [')
    out.append(",\n".join(objs))
    out.append("  ]")
    out.append("}")
    print("\n".join(out))


if __name__ == "__main__":
    main()
