# test_memory.py — renders and scene reads keep no memory and no references.
import os
import sys

import glint

SCENE = '{"render": {"width": 4, "height": 3, "spp": 1, "integrator": "path", "background": "sky"}}'


def rss_pages():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1])


def render_one(progress):
    scene = glint.parse(SCENE)
    image, aovs = scene.render(aov=["albedo", "depth"], progress=progress, spp=2)
    try:
        scene.render(spp=0)
    except glint.Error:
        pass
    return image


def test_renders_keep_no_memory():
    calls = []

    def progress(fraction):
        calls.append(fraction)

    for _ in range(200):
        render_one(progress)
    before = rss_pages()
    refs = sys.getrefcount(progress)
    for _ in range(1000):
        render_one(progress)
    grown = (rss_pages() - before) * os.sysconf("SC_PAGE_SIZE")
    # AddressSanitizer keeps freed memory in quarantine: the resident size says nothing there
    assert grown < 1 << 20 or os.environ.get("GLINT_SANITIZE"), "%d bytes more after 1,000 renders" % grown
    assert sys.getrefcount(progress) == refs
    assert calls and calls[-1] == 1.0
