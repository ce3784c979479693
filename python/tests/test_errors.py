# test_errors.py — what the library refuses raises glint.Error with its message; what Python cannot pass raises
# TypeError or ValueError naming the argument.
import pytest

import glint
from conftest import scene_path


def test_error_is_an_exception_with_the_library_message():
    assert issubclass(glint.Error, Exception)
    with pytest.raises(glint.Error, match=r"^missing\.json: cannot open: No such file or directory$"):
        glint.load("missing.json")
    with pytest.raises(glint.Error, match=r"^<scene>:1:12: render must be a JSON object, got 5$"):
        glint.parse('{"render": 5}')


@pytest.mark.parametrize("keyword, value, exception, message", [
    ("spp", 0, glint.Error, r"^--spp: 0 is out of range, expected an integer in \[1, 1000000\]$"),
    ("width", 16385, glint.Error, r"^--width: 16385 is out of range"),
    ("max_depth", 10001, glint.Error, r"^--depth: 10001 is out of range"),
    ("accel", "kd", glint.Error, r"^--accel: unknown structure 'kd', expected bvh, bvh2 or none$"),
    ("output_encoding", "rec709", glint.Error, r"^--output-encoding: unknown encoding 'rec709'"),
    ("region", (0, 0, 99999, 4), glint.Error, r"--region"),
    ("spp", 1.5, TypeError, r"^render: spp must be an int, got float$"),
    ("spp", True, TypeError, r"^render: spp must be an int, got bool$"),
    ("spp", "4", TypeError, r"^render: spp must be an int, got str$"),
    ("spp", -1, ValueError, r"^render: spp is out of range"),
    ("seed", 2**53 + 1, ValueError, r"^render: seed is out of range, expected an integer in \[0, 9007199254740992\]$"),
    ("threads", 257, ValueError, r"^render: threads is out of range, expected an integer in \[0, 256\]$"),
    ("width", 2**70, ValueError, r"^render: width is out of range"),
    ("region", (0, 0, 4), TypeError, r"^render: region must be a sequence of four ints"),
    ("region", (0, 0, 4, "4"), TypeError, r"^render: region y1 must be an int, got str$"),
    ("accel", 2, TypeError, r"^render: accel must be a str, got int$"),
    ("aov", ["albedo", "z"], ValueError, r"^render: unknown AOV 'z', expected albedo, normal or depth$"),
    ("aov", [1], TypeError, r"^render: aov\[0\] must be a str, got int$"),
    ("aov", 3, TypeError, r"^render: aov must be a list"),
    ("progress", 3, TypeError, r"^render: progress must be callable"),
    ("time_limit", 0, ValueError, r"^render: time_limit is out of range"),
    ("time_limit", "1", TypeError, r"^render: time_limit must be a number of seconds, got str$"),
    ("checkpoint", 5, TypeError, r"^render: checkpoint must be a path"),
    ("trace", "/nonexistent/dir/t.json", glint.Error, r"^/nonexistent/dir/t\.json: cannot write"),
])
def test_bad_render_arguments(keyword, value, exception, message):
    scene = glint.load(scene_path("cornell-box.json"))
    with pytest.raises(exception, match=message):
        scene.render(**{"width": 8, "height": 8, **{keyword: value}})


def test_render_takes_keywords_only():
    scene = glint.Scene()
    with pytest.raises(TypeError):
        scene.render(4)
    with pytest.raises(TypeError, match="sp"):
        scene.render(sp=4)


def test_bad_load_arguments():
    with pytest.raises(TypeError):
        glint.load(5)
    with pytest.raises(ValueError):
        glint.load("a\0b")
    with pytest.raises(ValueError, match=r"^load: threads=-1 is out of range"):
        glint.load(scene_path("paper.json"), threads=-1)
    with pytest.raises(TypeError):
        glint.parse(b"{}", name=3)
