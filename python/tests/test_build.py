# test_build.py — scenes built in Python through the scene API: the same bytes as the scene files they copy, from
# dicts and NumPy arrays; glint.write; what the converters refuse; no memory kept by builds.
import ctypes
import json
import os
import sys

import numpy as np
import pytest

import glint
from conftest import cli_render, scene_path

def same_bits(a, b):
    return a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()


def test_book_one_final_scene_from_dicts_and_arrays_renders_the_file_bytes():
    with open(scene_path("rtiow-final.json")) as f:
        data = json.load(f)
    scene = glint.Scene("rtiow-final.py")
    scene.set_render(**data["render"])
    camera = dict(data["camera"])
    camera["lookfrom"] = np.array(camera["lookfrom"], dtype=np.float64)  # arrays stand for lists
    scene.set_camera(camera)
    centers = np.array([o["center"] for o in data["objects"]])
    radii = np.array([o["radius"] for o in data["objects"]])
    for obj, center, radius in zip(data["objects"], centers, radii):
        scene.add_object(type="sphere", center=center, radius=radius, material=obj["material"])  # NumPy scalars too
    for light in data.get("lights", []):
        scene.add_light(light)
    loaded = glint.load(scene_path("rtiow-final.json"))
    settings = dict(width=60, height=34, spp=3, threads=2)
    assert scene.size == loaded.size == (1200, 675)
    assert same_bits(scene.render(**settings), loaded.render(**settings))


def read_obj(path):
    """The v and f lines of an OBJ file, as float32 positions (rounded exactly as glint's reader rounds: strtof)
    and uint32 triangles (1-based in the file)."""
    libc = ctypes.CDLL(None)
    libc.strtof.restype = ctypes.c_float
    libc.strtof.argtypes = [ctypes.c_char_p, ctypes.c_void_p]
    positions, faces = [], []
    with open(path, "rb") as f:
        for line in f:
            parts = line.split()
            if parts and parts[0] == b"v":
                positions.append([libc.strtof(p, None) for p in parts[1:4]])
            elif parts and parts[0] == b"f":
                assert len(parts) == 4
                faces.append([int(p.split(b"/")[0]) - 1 for p in parts[1:4]])
    return np.array(positions, dtype=np.float32), np.array(faces, dtype=np.int64)


def test_the_bunny_as_arrays_renders_the_obj_bytes():
    with open(scene_path("bunny.json")) as f:
        data = json.load(f)
    positions, indices = read_obj(os.path.join(os.path.dirname(scene_path("bunny.json")), data["objects"][1]["file"]))
    assert positions.shape == (35947, 3) and indices.shape == (69451, 3)
    scene = glint.Scene()
    scene.set_render(data["render"])
    scene.set_camera(data["camera"])
    for name, texture in data["textures"].items():
        scene.add_texture(name, texture)
    for name, material in data["materials"].items():
        scene.add_material(name, material)
    scene.add_object(data["objects"][0])
    scene.add_mesh("bunny", positions, indices)
    placed = dict(data["objects"][1])
    del placed["file"]
    scene.add_object({**placed, "mesh": "bunny"})
    loaded = glint.load(scene_path("bunny.json"))
    settings = dict(width=48, height=36, spp=2, threads=2)
    assert same_bits(scene.render(**settings), loaded.render(**settings))
    # float64 positions and uint32 indices are the same mesh
    again = glint.Scene()
    again.set_render(data["render"])
    again.set_camera(data["camera"])
    for name, texture in data["textures"].items():
        again.add_texture(name, texture)
    for name, material in data["materials"].items():
        again.add_material(name, material)
    again.add_object(data["objects"][0])
    again.add_mesh("bunny", positions.astype(np.float64), indices.astype(np.uint32))
    again.add_object({**placed, "mesh": "bunny"})
    assert same_bits(again.render(**settings), loaded.render(**settings))


def test_a_scene_name_is_the_base_of_relative_paths():
    scene = glint.Scene(scene_path("bunny.json"))
    scene.add_object(type="mesh", file="meshes/stanford-bunny/stanford-bunny.obj",
                     material={"type": "lambertian", "albedo": 0.5})
    with pytest.raises(glint.Error, match=r"^glint_scene_add_object: mesh file .*: cannot open"):
        glint.Scene().add_object(type="mesh", file="meshes/stanford-bunny/stanford-bunny.obj")


def test_overrides_apply_to_one_render_only():
    scene = glint.load(scene_path("cornell-box.json"))
    assert scene.render(width=8, height=6, spp=1).shape == (6, 8, 3)
    assert scene.size == (600, 600)


FORMATS = [(".pfm", None), (".ppm", None), (".png", None), (".exr", None), (".hdr", None),
           (".ppm", "ppm-ascii"), (".exr", "exr-half")]


@pytest.mark.parametrize("suffix, fmt", FORMATS)
def test_write_every_format_as_the_command_line_does(tmp_path, suffix, fmt):
    path = scene_path("cornell-box.json")
    args = ["--width", 20, "--height", 16, "--spp", 2]
    if fmt == "ppm-ascii":
        args.append("--ascii-ppm")
    if fmt == "exr-half":
        args.append("--half")
    cli = cli_render(tmp_path, path, *args, suffix=suffix)
    image = glint.load(path).render(width=20, height=16, spp=2)
    mine = os.path.join(str(tmp_path), "py" + suffix)
    glint.write(mine, image, "gamma2", format=fmt)  # cornell-box.json's "output"
    with open(cli, "rb") as a, open(mine, "rb") as b:
        assert a.read() == b.read()


def test_write_refuses():
    image = np.zeros((4, 4, 3), dtype=np.float32)
    with pytest.raises(ValueError, match=r"^write: unknown format 'jpg'"):
        glint.write("x.jpg", image, format="jpg")
    with pytest.raises(glint.Error):
        glint.write("x.jpg", image)
    with pytest.raises(glint.Error, match="encoding"):
        glint.write("x.png", image, "rec709")
    with pytest.raises(ValueError, match=r"^write: image: expected shape \(H, W, 3\)"):
        glint.write("x.png", np.zeros((4, 4, 4), dtype=np.float32))
    with pytest.raises(TypeError, match=r"^write: image: expected an array of numbers"):
        glint.write("x.png", np.array([[["a"] * 3]]))


def test_dict_values_the_converter_refuses_name_the_key():
    scene = glint.Scene()
    sphere = {"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": {"type": "lambertian", "albedo": 0.5}}
    with pytest.raises(TypeError, match=r"^add_object: key 'center\[2\]': expected a number, str, bool, list, "
                                        r"tuple, dict or NumPy array, got set$"):
        scene.add_object({**sphere, "center": [0, 0, {1}]})
    with pytest.raises(ValueError, match=r"^add_object: key 'radius': expected a finite number, got float$"):
        scene.add_object({**sphere, "radius": float("nan")})
    with pytest.raises(TypeError, match=r"^add_material: key 'albedo': keys must be str, got int$"):
        scene.add_material("m", {"type": "lambertian", "albedo": {1: 2}})
    with pytest.raises(TypeError, match=r"^set_camera: key 'vup': .*got NoneType$"):
        scene.set_camera(type="lookat", vup=None)
    with pytest.raises(TypeError, match=r"^add_object: key 'center': expected numbers, got an array of dtype"):
        scene.add_object({**sphere, "center": np.array(["a", "b", "c"])})
    with pytest.raises(TypeError, match=r"^set_render: give a dict or keywords, not both$"):
        scene.set_render({"spp": 1}, width=3)
    with pytest.raises(TypeError, match=r"^add_light: expected a dict, got list$"):
        scene.add_light([1, 2])
    nested = []
    nested.append(nested)
    with pytest.raises(ValueError, match="nested deeper than 32 levels"):
        scene.add_object({**sphere, "center": nested})
    # the library's own validation: glint.Error with its message, naming the call
    with pytest.raises(glint.Error, match=r"^glint_scene_add_object: .*radius"):
        scene.add_object({**sphere, "radius": 0})
    # nothing refused was added
    assert scene.render(width=4, height=4).max() == 0


def test_numpy_scalars_and_arrays_are_numbers_and_lists():
    a = glint.Scene()
    a.set_render(width=np.int32(16), height=np.uint16(12), spp=np.int64(2), background=np.float32(0.25),
                 integrator="path")
    a.add_object(type="sphere", center=np.array([0, 0, -2], dtype=np.float32), radius=np.float64(0.5),
                 material={"type": "lambertian", "albedo": np.full(3, 0.5)})
    b = glint.Scene()
    b.set_render({"width": 16, "height": 12, "spp": 2, "background": 0.25, "integrator": "path"})
    b.add_object({"type": "sphere", "center": (0, 0, -2), "radius": 0.5,
                  "material": {"type": "lambertian", "albedo": [0.5, 0.5, 0.5]}})
    assert same_bits(a.render(), b.render())


def test_mesh_arrays_the_module_refuses():
    scene = glint.Scene()
    p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=np.float32)
    i = np.array([[0, 1, 2]])
    cases = [
        (dict(positions=p[:, :2]), ValueError, r"^add_mesh: positions: expected shape \(N, 3\), got \(3, 2\)$"),
        (dict(positions=p.ravel()), ValueError, r"^add_mesh: positions: expected a 2-dimensional array"),
        (dict(positions=np.array([["a"] * 3])), TypeError, r"^add_mesh: positions: expected an array of numbers"),
        (dict(indices=i.astype(np.float32)), TypeError, r"^add_mesh: indices: expected an array of integers"),
        (dict(indices=np.array([[0, 1, 3]])), ValueError,
         r"^add_mesh: indices\[0, 2\] = 3 is out of range \[0, 3\): an index of positions$"),
        (dict(indices=np.array([[0, -1, 2]])), ValueError, r"^add_mesh: indices\[0, 1\] = -1 is out of range"),
        (dict(indices=np.array([0, 1, 2])), ValueError, r"^add_mesh: indices: expected shape \(M, 3\)"),
        (dict(normals=p[:2]), ValueError, r"^add_mesh: normals: expected shape \(3, 3\): one row a vertex"),
        (dict(uvs=p), ValueError, r"^add_mesh: uvs: expected shape \(3, 2\)"),
        (dict(face_materials=[0]), TypeError, r"^add_mesh: face_materials needs materials"),
        (dict(face_materials=[1], materials=["a"]), ValueError,
         r"^add_mesh: face_materials\[0\] = 1 is out of range \[0, 1\): an index of materials$"),
        (dict(face_materials=[0, 0], materials=["a"]), ValueError, r"^add_mesh: face_materials: expected shape \(1,\)"),
        (dict(materials=[3]), TypeError, r"^add_mesh: materials\[0\]: expected a material name \(str\), got int$"),
    ]
    for change, exception, message in cases:
        args = {"positions": p, "indices": i, **change}
        with pytest.raises(exception, match=message):
            scene.add_mesh("m", **args)
    scene.add_material("red", type="lambertian", albedo=[0.8, 0.1, 0.1])
    scene.add_mesh("m", p, i, normals=p, uvs=p[:, :2], face_materials=[0], materials=["red"])
    scene.add_mesh("flat", p, i, flat=True)
    with pytest.raises(glint.Error, match=r"^glint_scene_add_mesh: .*normals"):
        scene.add_mesh("flat2", p, i, normals=p, flat=True)
    with pytest.raises(glint.Error, match=r"^glint_scene_add_mesh: duplicate mesh name \"m\""):
        scene.add_mesh("m", p, i)  # the name is taken


def test_image_textures_from_pixels():
    scene = glint.Scene()
    scene.add_image("bytes", np.full((4, 8, 3), 200, dtype=np.uint8), encoding="linear", filter="nearest")
    scene.add_image("grey", np.full((4, 8), 0.5, dtype=np.float32))
    scene.add_image("rgba", np.ones((2, 2, 4), dtype=np.float64))
    with pytest.raises(TypeError, match=r"^add_image: pixels: expected uint8 \(8-bit\) or float32"):
        scene.add_image("bad", np.ones((2, 2, 3), dtype=np.int32))
    with pytest.raises(ValueError, match=r"^add_image: pixels: expected shape \(H, W\) or \(H, W, C\) with C = 1, 3 or 4$"):
        scene.add_image("bad", np.ones((2, 2, 2), dtype=np.uint8))
    scene.set_render(width=8, height=8, integrator="path", background=1)
    scene.set_camera(type="lookat", lookfrom=[0, 0, 1], lookat=[0, 0, 0], vfov=60)
    scene.add_object(type="quad", q=[-1, -1, 0], u=[2, 0, 0], v=[0, 2, 0],
                     material={"type": "lambertian", "albedo": "bytes"})
    image = scene.render(spp=1)
    assert image.shape == (8, 8, 3) and image.max() > 0


def rss_pages():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1])


def build_one():
    s = glint.Scene()
    s.set_render({"width": 8, "height": 8, "spp": 1, "integrator": "path"})
    s.add_material("m", {"type": "lambertian", "albedo": [0.5, 0.5, 0.5]})
    s.add_object({"type": "sphere", "center": [0, 0, -2], "radius": 0.5, "material": "m"})
    s.add_mesh("t", MESH_P, MESH_I)
    s.add_object({"type": "mesh", "mesh": "t", "material": "m"})
    try:
        s.add_object({"type": "sphere", "center": [0, 0, 0], "radius": -1})
    except glint.Error:
        pass


MESH_P = np.array([[0, 0, -3], [1, 0, -3], [0, 1, -3]], dtype=np.float32)
MESH_I = np.array([[0, 1, 2]], dtype=np.uint32)


def test_ten_thousand_scene_builds_keep_no_memory():
    for _ in range(1000):
        build_one()
    before = rss_pages()
    refs = sys.getrefcount(MESH_P), sys.getrefcount(MESH_I)
    for _ in range(10000):
        build_one()
    grown = (rss_pages() - before) * os.sysconf("SC_PAGE_SIZE")
    assert (sys.getrefcount(MESH_P), sys.getrefcount(MESH_I)) == refs
    # AddressSanitizer keeps freed memory in quarantine: the resident size says nothing there
    assert grown < 1 << 20 or os.environ.get("GLINT_SANITIZE"), "%d bytes more after 10,000 scene builds" % grown
