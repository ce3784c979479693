# conftest.py — what the Python module's tests share: the glint program and source tree (from CTest's
# environment), a PFM reader, renders by the command line to compare with.
import os
import subprocess

import numpy as np
import pytest

SOURCE_DIR = os.environ.get("GLINT_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
BINARY = os.environ.get("GLINT_BINARY", "glint")


def scene_path(name):
    return os.path.join(SOURCE_DIR, "scenes", name)


def read_pfm(path):
    """A PFM file as an (H, W, 3) float32 array, row 0 at the top (the file stores rows bottom-up)."""
    with open(path, "rb") as f:
        data = f.read()
    header = data.split(b"\n", 3)
    assert header[0] == b"PF"
    width, height = map(int, header[1].split())
    scale = float(header[2])
    dtype = "<f4" if scale < 0 else ">f4"
    pixels = np.frombuffer(header[3], dtype=dtype, count=width * height * 3)
    return pixels.reshape(height, width, 3)[::-1].astype(np.float32)


def cli_render(tmp_path, scene, *args, suffix=".pfm"):
    """Renders a scene file with the glint program; the output file's path."""
    out = os.path.join(str(tmp_path), "cli" + suffix)
    subprocess.run([BINARY, scene, "-q", "-o", out, *map(str, args)], check=True)
    return out


@pytest.fixture
def tmp(tmp_path):
    return tmp_path
