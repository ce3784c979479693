#!/usr/bin/env python3
"""Writes the small glTF and PLY files of tests/cli/models.sh (run from this directory; the outputs are committed).
Every file here is made by this script: no third-party data."""
import base64, json, struct, zlib

QUAD = [(-0.5, 0.0, -0.5), (0.5, 0.0, -0.5), (0.5, 0.0, 0.5), (-0.5, 0.0, 0.5)]
QUAD_TRIS = [0, 2, 1, 0, 3, 2]  # facing +y


def buffer_of(positions, indices):
    pb = b''.join(struct.pack('<3f', *p) for p in positions)
    ib = b''.join(struct.pack('<I', i) for i in indices)
    return pb, ib


def gltf(positions=QUAD, indices=QUAD_TRIS, nodes=None, scene_nodes=None, count=None, uri=None, extra=None):
    pb, ib = buffer_of(positions, indices)
    data = pb + ib
    g = {
        "asset": {"version": "2.0", "generator": "glint tests/data/models/make.py"},
        "scene": 0,
        "scenes": [{"nodes": scene_nodes if scene_nodes is not None else [0]}],
        "nodes": nodes if nodes is not None else [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
        "materials": [{"name": "clay", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.3, 0.2, 1.0],
                                                                "metallicFactor": 0.0, "roughnessFactor": 1.0}}],
        "buffers": [{"byteLength": len(data),
                     "uri": uri if uri else "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(pb)},
                        {"buffer": 0, "byteOffset": len(pb), "byteLength": len(ib)}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": count if count else len(positions), "type": "VEC3"},
                      {"bufferView": 1, "componentType": 5125, "count": len(indices), "type": "SCALAR"}],
    }
    if extra:
        g.update(extra)
    return json.dumps(g, indent=1) + '\n'


def write(name, text):
    with open(name, 'w') as f:
        f.write(text)


# The quad as PLY (the same vertices and, after assimp's fan, the same triangles): reused.gltf's JSON twin uses it.
write('quad.ply', 'ply\nformat ascii 1.0\ncomment written by glint tests/data/models/make.py\nelement vertex 4\n'
      'property float x\nproperty float y\nproperty float z\nelement face 2\nproperty list uchar int vertex_indices\n'
      'end_header\n' + ''.join('%g %g %g\n' % p for p in QUAD) + '3 0 2 1\n3 0 3 2\n')

# One mesh placed by three nodes, one of them inside a parent: three instances.
write('reused.gltf', gltf(nodes=[{"mesh": 0, "translation": [-1.5, 0.0, 0.0]},
                                 {"translation": [1.5, 0.0, 0.0], "children": [2]},
                                 {"mesh": 0, "scale": [0.5, 0.5, 0.5]},
                                 {"mesh": 0, "translation": [0.0, 0.0, -1.5]}], scene_nodes=[0, 1, 3]))

# Cameras: one moved only, one turned a quarter about y; the quad in front of both.
write('cameras.gltf', gltf(nodes=[{"mesh": 0},
                                  {"camera": 0, "name": "front", "translation": [0.25, 1.0, 4.0]},
                                  {"camera": 1, "name": "side", "translation": [4.0, 1.0, 0.0],
                                   "rotation": [0.0, 0.7071067811865476, 0.0, 0.7071067811865476]}],
                           scene_nodes=[0, 1, 2],
                           extra={"cameras": [{"type": "perspective", "perspective": {"yfov": 0.6, "znear": 0.01}},
                                              {"type": "perspective",
                                               "perspective": {"yfov": 0.5, "aspectRatio": 1.5, "znear": 0.01}}]}))

# Lights: a spot light pointing down at the quad (and a point light is the scene's own).
write('spot.gltf', gltf(nodes=[{"mesh": 0, "scale": [4.0, 1.0, 4.0]},
                               {"name": "spot", "translation": [0.0, 2.0, 0.0],
                                "rotation": [-0.7071067811865476, 0.0, 0.0, 0.7071067811865476],
                                "extensions": {"KHR_lights_punctual": {"light": 0}}}],
                        scene_nodes=[0, 1],
                        extra={"extensionsUsed": ["KHR_lights_punctual"],
                               "extensions": {"KHR_lights_punctual": {"lights": [
                                   {"type": "spot", "color": [1.0, 0.9, 0.8], "intensity": 8.0,
                                    "spot": {"innerConeAngle": 0.3, "outerConeAngle": 0.6}}]}}}))

# An emissive material with KHR_materials_emissive_strength (read by glint: assimp 5.2 does not) and a metallic one.
write('emissive.gltf', gltf(extra={"extensionsUsed": ["KHR_materials_emissive_strength"],
                                   "materials": [{"name": "lamp", "emissiveFactor": [1.0, 0.5, 0.25],
                                                  "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4.0}},
                                                  "pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.2, 0.3, 1.0],
                                                                           "metallicFactor": 0.25, "roughnessFactor": 0.75}}]}))

# alphaMode MASK with baseColorFactor's alpha below the cutoff: every fragment is cut away.
write('masked.gltf', gltf(extra={"materials": [{"name": "cut", "alphaMode": "MASK", "alphaCutoff": 0.5,
                                                "pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 0.25]}}]}))

# alphaMode MASK with the base colour texture's alpha: a 4x4 checker of opaque and clear cells (an RGBA PNG, embedded
# as a data URI), over the quad with texture coordinates; checker-rgba.png (the same bytes) and quad-uv.ply (the
# quad with the coordinates glint reads from the glTF: assimp flips v) make its JSON twin.
def png_rgba(width, height, pixel):
    raw = b''.join(b'\0' + b''.join(bytes(pixel(x, y)) for x in range(width)) for y in range(height))
    def chunk(kind, data):
        return struct.pack('>I', len(data)) + kind + data + struct.pack('>I', zlib.crc32(kind + data) & 0xffffffff)
    return (b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', width, height, 8, 6, 0, 0, 0)) +
            chunk(b'IDAT', zlib.compress(raw, 9)) + chunk(b'IEND', b''))


CHECKER = png_rgba(4, 4, lambda x, y: (200, 60, 40, 255 if (x + y) % 2 == 0 else 0))
with open('checker-rgba.png', 'wb') as f:
    f.write(CHECKER)
QUAD_UV = [(p[0] + 0.5, p[2] + 0.5) for p in QUAD]  # glTF's: v = 0 at the image's top row
pb, ib = buffer_of(QUAD, QUAD_TRIS)
tb = b''.join(struct.pack('<2f', *t) for t in QUAD_UV)
uv_data = pb + ib + tb
masked_texture = json.loads(gltf())
masked_texture["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = 2
masked_texture["buffers"][0] = {"byteLength": len(uv_data), "uri": "data:application/octet-stream;base64," +
                                base64.b64encode(uv_data).decode()}
masked_texture["bufferViews"].append({"buffer": 0, "byteOffset": len(pb) + len(ib), "byteLength": len(tb)})
masked_texture["accessors"].append({"bufferView": 2, "componentType": 5126, "count": len(QUAD_UV), "type": "VEC2"})
masked_texture["materials"] = [{"name": "leaf", "alphaMode": "MASK",
                                "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0,
                                                         "roughnessFactor": 1.0}}]
masked_texture["images"] = [{"uri": "data:image/png;base64," + base64.b64encode(CHECKER).decode()}]
masked_texture["textures"] = [{"source": 0}]
write('masked-texture.gltf', json.dumps(masked_texture, indent=1) + '\n')
# An opaque white base colour texture times a baseColorFactor: the colour (and the albedo AOV) is the factor.
WHITE = png_rgba(2, 2, lambda x, y: (255, 255, 255, 255))
tinted = json.loads(json.dumps(masked_texture))
tinted["materials"] = [{"name": "tinted", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0},
                                                                   "baseColorFactor": [0.5, 0.25, 0.75, 1.0],
                                                                   "metallicFactor": 0.0, "roughnessFactor": 1.0}}]
tinted["images"] = [{"uri": "data:image/png;base64," + base64.b64encode(WHITE).decode()}]
write('tinted-texture.gltf', json.dumps(tinted, indent=1) + '\n')
with open('quad-uv.ply', 'wb') as f:
    f.write(b'ply\nformat binary_little_endian 1.0\ncomment written by glint tests/data/models/make.py\n'
            b'element vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty float u\n'
            b'property float v\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n')
    for p, t in zip(QUAD, QUAD_UV):
        f.write(struct.pack('<5f', p[0], p[1], p[2], t[0], 1.0 - t[1]))
    for k in range(0, len(QUAD_TRIS), 3):
        f.write(struct.pack('<B3i', 3, *QUAD_TRIS[k:k + 3]))

# A point light moved by its node, a directional light turned by its node to shine along -y.
write('lights.gltf', gltf(nodes=[{"mesh": 0},
                                 {"name": "bulb", "translation": [1.0, 2.0, 3.0], "extensions": {"KHR_lights_punctual": {"light": 0}}},
                                 {"name": "sun", "rotation": [-0.7071067811865476, 0.0, 0.0, 0.7071067811865476],
                                  "extensions": {"KHR_lights_punctual": {"light": 1}}}],
                          scene_nodes=[0, 1, 2],
                          extra={"extensionsUsed": ["KHR_lights_punctual"],
                                 "extensions": {"KHR_lights_punctual": {"lights": [
                                     {"type": "point", "color": [1.0, 0.5, 0.25], "intensity": 2.0},
                                     {"type": "directional", "intensity": 3.0}]}}}))

# ---- malformed files: each must be refused with a message naming it, exit 2 ----
write('index-out-of-range.gltf', gltf(indices=[0, 2, 1, 0, 3, 9]))
pb, ib = buffer_of([(0, 0, 0), (float('inf'), 0, 0), (0, 0, 1)], [0, 1, 2])
write('infinite-vertex.gltf', gltf(positions=[(0, 0, 0), (float('inf'), 0, 0), (0, 0, 1)], indices=[0, 1, 2]))
write('missing-bin.gltf', gltf(uri='missing.bin'))
write('recursive-nodes.gltf', gltf(nodes=[{"mesh": 0, "children": [0]}]))
write('cyclic-nodes.gltf', gltf(nodes=[{"mesh": 0, "children": [1]}, {"children": [0]}]))
write('huge-count.gltf', gltf(count=1000000000))
deep = [{"children": [i + 1]} for i in range(400)] + [{"mesh": 0}]
write('deep-nodes.gltf', gltf(nodes=deep))
write('huge-count.ply', 'ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n'
      'property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n')
write('nan-vertex.ply', 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n'
      'element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\nnan 0 0\n0 0 1\n3 0 1 2\n')
write('index-out-of-range.ply', 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n'
      'property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 0 1\n'
      '3 0 1 7\n')
with open('truncated.ply', 'wb') as f:
    f.write(b'ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n'
            b'property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n' + struct.pack('<4f', 0, 0, 0, 1))
