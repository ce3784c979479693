# test_render.py — Scene.render against the command line: the same float values as its PFM, every override,
# AOVs, regions, progress.
import os

import numpy as np
import pytest

import glint
from conftest import cli_render, read_pfm, scene_path


def same_bits(a, b):
    return a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()


def test_version():
    assert glint.version == glint.__version__
    assert glint.version.count(".") == 2


@pytest.mark.parametrize("scene", ["cornell-box.json", "rtiow-final.json", "paper.json", "textures.json"])
def test_render_is_the_pfm_bit_for_bit(tmp_path, scene):
    path = scene_path(scene)
    expected = read_pfm(cli_render(tmp_path, path, "--width", 40, "--height", 30, "--spp", 3, "--seed", 7))
    image = glint.load(path).render(width=40, height=30, spp=3, seed=7, threads=2)
    assert image.dtype == np.float32 and image.shape == (30, 40, 3)
    assert image.flags["C_CONTIGUOUS"]
    assert same_bits(image, expected)


def test_every_override_as_the_command_line(tmp_path):
    path = scene_path("cornell-box.json")
    expected = read_pfm(cli_render(tmp_path, path, "--width", 24, "--height", 20, "--spp", 2, "--depth", 3,
                                   "--seed", 11, "--threads", 1, "--accel", "bvh2", "--output-encoding", "linear",
                                   "--region", "4,2,20,18"))
    image = glint.load(path).render(width=24, height=20, spp=2, max_depth=3, seed=11, threads=1, accel="bvh2",
                                    output_encoding="linear", region=(4, 2, 20, 18))
    assert image.shape == (16, 16, 3)
    assert same_bits(image, expected)


def test_aovs_are_the_pfm_planes(tmp_path):
    path = scene_path("cornell-box.json")
    cli = cli_render(tmp_path, path, "--width", 20, "--height", 16, "--spp", 2, "--aov", "albedo,normal,depth")
    image, aovs = glint.load(path).render(width=20, height=16, spp=2, aov=["albedo", "normal", "depth"])
    assert same_bits(image, read_pfm(cli))
    assert sorted(aovs) == ["albedo", "depth", "normal"]
    stem = cli[:-len(".pfm")]
    assert same_bits(aovs["albedo"], read_pfm(stem + ".albedo.pfm"))
    assert same_bits(aovs["normal"], read_pfm(stem + ".normal.pfm"))
    with open(stem + ".depth.pfm", "rb") as f:
        header = f.read().split(b"\n", 3)
    assert header[0] == b"Pf"
    depth = np.frombuffer(header[3], dtype="<f4", count=20 * 16).reshape(16, 20)[::-1]
    assert aovs["depth"].shape == (16, 20) and aovs["depth"].tobytes() == np.ascontiguousarray(depth).tobytes()
    # aov= given, even empty or as one comma-separated str: always the pair
    image2, none = glint.load(path).render(width=20, height=16, spp=2, aov=[])
    assert none == {} and same_bits(image2, image)
    _, one = glint.load(path).render(width=20, height=16, spp=2, aov="depth,albedo")
    assert sorted(one) == ["albedo", "depth"]


def test_progress_is_called_on_the_calling_thread_up_to_one():
    import threading
    seen = []
    scene = glint.load(scene_path("cornell-box.json"))
    scene.render(width=48, height=48, spp=64, threads=1,
                 progress=lambda f: seen.append((f, threading.get_ident())))
    assert seen and seen[-1][0] == 1.0
    fractions = [f for f, _ in seen]
    assert fractions == sorted(fractions)
    assert {t for _, t in seen} == {threading.get_ident()}


def test_an_exception_in_progress_cancels_the_render_and_is_raised():
    class Stop(Exception):
        pass

    calls = []

    def progress(fraction):
        calls.append(fraction)
        raise Stop("enough")

    scene = glint.load(scene_path("cornell-box.json"))
    with pytest.raises(Stop, match="enough"):
        scene.render(width=64, height=64, spp=100000, threads=2, progress=progress)
    assert len(calls) == 1
    # the scene renders again afterwards
    assert scene.render(width=8, height=8, spp=1).shape == (8, 8, 3)


def test_time_limit_stops_at_a_pass():
    scene = glint.load(scene_path("cornell-box.json"))
    image = scene.render(width=32, height=32, spp=1000000, threads=2, time_limit=0.3)
    assert image.shape == (32, 32, 3) and np.isfinite(image).all()


def test_checkpoint_resume_and_trace(tmp_path):
    path = scene_path("cornell-box.json")
    ckp = os.path.join(str(tmp_path), "r.ckp")
    trace = os.path.join(str(tmp_path), "t.json")
    scene = glint.load(path)
    first = scene.render(width=16, height=16, spp=2, checkpoint=ckp, trace=trace)
    assert os.path.getsize(ckp) > 0
    with open(trace) as f:
        assert '"traceEvents"' in f.read()
    resumed = scene.render(width=16, height=16, spp=4, resume=ckp)
    assert same_bits(resumed, scene.render(width=16, height=16, spp=4))
    assert not same_bits(first, resumed)


def test_size_and_warnings(tmp_path):
    scene = glint.load(scene_path("bunny.json"))
    assert scene.size == (640, 480)
    assert scene.warnings == []
    assert repr(scene) == "<glint.Scene 640x480>"
    empty = glint.Scene()
    assert empty.size == (400, 225)
    assert empty.render(width=3, height=2).tolist() == [[[0.0] * 3] * 3] * 2


def test_parse_names_the_scene_in_messages():
    scene = glint.parse('{"render": {"width": 8, "height": 6}}', name="mine.json")
    assert scene.size == (8, 6)
    with pytest.raises(glint.Error, match=r"^mine\.json:1:"):
        glint.parse('{"render": {"widht": 8}}', name="mine.json")
    with pytest.raises(glint.Error, match=r"^<scene>:1:"):
        glint.parse("{")
