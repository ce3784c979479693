#!/usr/bin/env python3
"""bench/yard_meshes.py — writes a mesh of the mesh yardstick as an OBJ file in the bunny's place, so that the
yardstick's bunny scene (bench/scenes/bunny-yardstick.json, and the embree-mesh renderer's arguments for it)
renders it with nothing changed but the file: scaled uniformly to the bunny's largest extent, centred on the
bunny's centre in x and z, standing on the bunny's lowest point. Both renderers then read the same OBJ file.

usage: python3 bench/yard_meshes.py SOURCE BUNNY.obj OUT.obj
  SOURCE: a PLY file (ASCII or binary little-endian; gzip-compressed when it ends in .gz), such as the Stanford
          dragon, or a binary glTF (.glb) whose nodes place its meshes (their triangles, transforms applied)
The first line of OUT.obj says how many triangles it holds (bench/run.sh's mesh_triangles reads it).
"""
import gzip
import json
import os
import struct
import sys


def read_ply(path):
    """Vertices (x, y, z) and triangles (fanned polygons) of a PLY file with float x y z and a face list."""
    opener = gzip.open if path.endswith(".gz") else open
    with opener(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    fmt, elements = None, []
    for line in header:
        w = line.split()
        if not w:
            continue
        if w[0] == "format":
            fmt = w[1]
        elif w[0] == "element":
            elements.append([w[1], int(w[2]), []])
        elif w[0] == "property":
            elements[-1][2].append(w[1:])
    sizes = {"char": "b", "uchar": "B", "int8": "b", "uint8": "B", "short": "h", "ushort": "H", "int16": "h",
             "uint16": "H", "int": "i", "uint": "I", "int32": "i", "uint32": "I", "float": "f", "float32": "f",
             "double": "d", "float64": "d"}
    verts, tris = [], []
    if fmt == "ascii":
        tokens = data[end:].split()
        pos = 0
        for name, count, props in elements:
            for _ in range(count):
                row = {}
                for p in props:
                    if p[0] == "list":
                        n = int(tokens[pos])
                        row[p[-1]] = [int(t) for t in tokens[pos + 1:pos + 1 + n]]
                        pos += 1 + n
                    else:
                        row[p[-1]] = float(tokens[pos])
                        pos += 1
                if name == "vertex":
                    verts.append((row["x"], row["y"], row["z"]))
                elif name == "face":
                    idx = row.get("vertex_indices", row.get("vertex_index"))
                    tris.extend((idx[0], idx[i], idx[i + 1]) for i in range(1, len(idx) - 1))
    elif fmt == "binary_little_endian":
        pos = end
        for name, count, props in elements:
            for _ in range(count):
                row = {}
                for p in props:
                    if p[0] == "list":
                        (n,) = struct.unpack_from("<" + sizes[p[1]], data, pos)
                        pos += struct.calcsize(sizes[p[1]])
                        f = "<%d%s" % (n, sizes[p[2]])
                        row[p[-1]] = struct.unpack_from(f, data, pos)
                        pos += struct.calcsize(f)
                    else:
                        f = "<" + sizes[p[0]]
                        (row[p[-1]],) = struct.unpack_from(f, data, pos)
                        pos += struct.calcsize(f)
                if name == "vertex":
                    verts.append((row["x"], row["y"], row["z"]))
                elif name == "face":
                    idx = row.get("vertex_indices", row.get("vertex_index"))
                    tris.extend((idx[0], idx[i], idx[i + 1]) for i in range(1, len(idx) - 1))
    else:
        raise SystemExit("yard_meshes.py: %s: PLY format %s is not read here" % (path, fmt))
    return verts, tris


def mat_mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def node_matrix(node):
    """A glTF node's local matrix (row-major), from `matrix` (column-major) or translation, rotation, scale."""
    if "matrix" in node:
        m = node["matrix"]
        return [[m[c * 4 + r] for c in range(4)] for r in range(4)]
    tx, ty, tz = node.get("translation", [0, 0, 0])
    qx, qy, qz, qw = node.get("rotation", [0, 0, 0, 1])
    sx, sy, sz = node.get("scale", [1, 1, 1])
    r = [[1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
         [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)],
         [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)]]
    t = [tx, ty, tz]
    s = [sx, sy, sz]
    return [[r[i][0] * s[0], r[i][1] * s[1], r[i][2] * s[2], t[i]] for i in range(3)] + [[0, 0, 0, 1]]


def read_glb(path):
    """Vertices and triangles of every triangle primitive a binary glTF's default scene places, in world space."""
    with open(path, "rb") as f:
        data = f.read()
    magic, _, _ = struct.unpack_from("<III", data, 0)
    if magic != 0x46546C67:
        raise SystemExit("yard_meshes.py: %s is not a binary glTF" % path)
    jlen, _ = struct.unpack_from("<II", data, 12)
    gltf = json.loads(data[20:20 + jlen])
    blen, _ = struct.unpack_from("<II", data, 20 + jlen)
    binary = data[28 + jlen:28 + jlen + blen]
    comp = {5120: "b", 5121: "B", 5122: "h", 5123: "H", 5125: "I", 5126: "f"}
    width = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}

    def accessor(i):
        a = gltf["accessors"][i]
        view = gltf["bufferViews"][a["bufferView"]]
        n, c = width[a["type"]], comp[a["componentType"]]
        size = struct.calcsize("<" + c)
        stride = view.get("byteStride", n * size)
        base = view.get("byteOffset", 0) + a.get("byteOffset", 0)
        return [struct.unpack_from("<%d%s" % (n, c), binary, base + k * stride) for k in range(a["count"])]

    verts, tris = [], []

    def place(n, parent):
        node = gltf["nodes"][n]
        m = mat_mul(parent, node_matrix(node))
        if "mesh" in node:
            for prim in gltf["meshes"][node["mesh"]]["primitives"]:
                if prim.get("mode", 4) != 4:
                    continue
                first = len(verts)
                for (x, y, z) in accessor(prim["attributes"]["POSITION"]):
                    verts.append(tuple(m[i][0] * x + m[i][1] * y + m[i][2] * z + m[i][3] for i in range(3)))
                idx = [k[0] for k in accessor(prim["indices"])] if "indices" in prim else \
                    list(range(len(verts) - first))
                tris.extend((first + idx[k], first + idx[k + 1], first + idx[k + 2]) for k in range(0, len(idx) - 2, 3))
        for c in node.get("children", []):
            place(c, m)

    identity = [[float(i == j) for j in range(4)] for i in range(4)]
    for n in gltf["scenes"][gltf.get("scene", 0)]["nodes"]:
        place(n, identity)
    return verts, tris


def bounds(verts):
    return [min(v[k] for v in verts) for k in range(3)], [max(v[k] for v in verts) for k in range(3)]


def read_obj_vertices(path):
    with open(path) as f:
        return [tuple(float(x) for x in line.split()[1:4]) for line in f if line.startswith("v ")]


def main():
    if len(sys.argv) != 4:
        raise SystemExit(__doc__)
    src, bunny, out = sys.argv[1:]
    if not src.endswith((".glb", ".ply", ".ply.gz")):
        raise SystemExit("yard_meshes.py: %s: expected a .ply, .ply.gz or .glb file" % src)
    verts, tris = read_glb(src) if src.endswith(".glb") else read_ply(src)
    if not verts or not tris:
        raise SystemExit("yard_meshes.py: %s holds no triangles" % src)
    lo, hi = bounds(verts)
    blo, bhi = bounds(read_obj_vertices(bunny))
    s = max(bhi[k] - blo[k] for k in range(3)) / max(hi[k] - lo[k] for k in range(3))
    shift = [(blo[0] + bhi[0]) / 2 - s * (lo[0] + hi[0]) / 2, blo[1] - s * lo[1],
             (blo[2] + bhi[2]) / 2 - s * (lo[2] + hi[2]) / 2]
    tmp = out + ".part"
    with open(tmp, "w") as f:
        f.write("# %s in the bunny's place (bench/yard_meshes.py): %d triangles\n" % (os.path.basename(src), len(tris)))
        f.writelines("v %.7g %.7g %.7g\n" % tuple(s * v[k] + shift[k] for k in range(3)) for v in verts)
        f.writelines("f %d %d %d\n" % (a + 1, b + 1, c + 1) for (a, b, c) in tris)
    os.replace(tmp, out)  # no partial file under the final name


if __name__ == "__main__":
    main()
