#!/usr/bin/env python3
# python_overhead.py — what a render through the Python module costs against the command line, on one scene:
# alternating runs (CLI, Python, CLI, ...), medians. Two comparisons: the render alone (the CLI's statistics line's
# wall time against the time of Scene.render, load excluded on both sides) and whole processes (the CLI writing
# its PFM against python3 importing glint and NumPy, loading, rendering and writing the same PFM).
# usage: PYTHONPATH=build/python python3 bench/python_overhead.py build/glint [scene] [runs]
# Run it on an idle machine (uptime's load well below the CPU count).
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

glint_binary = sys.argv[1]
scene = sys.argv[2] if len(sys.argv) > 2 else "scenes/cornell-box.json"
runs = int(sys.argv[3]) if len(sys.argv) > 3 else 5
settings = dict(width=200, height=200, spp=16, threads=1)
flags = [a for k, v in settings.items() for a in ("--" + k, str(v))]
out = os.path.join(tempfile.mkdtemp(), "o.pfm")
child = ("import sys, time, glint\n"
         "s = glint.load(sys.argv[1])\n"
         "t = time.perf_counter()\n"
         "image = s.render(%s)\n"
         "print(time.perf_counter() - t)\n"
         "glint.write(sys.argv[2], image)\n") % ", ".join("%s=%d" % kv for kv in settings.items())

cli_render, cli_process, py_render, py_process = [], [], [], []
for _ in range(runs):
    t = time.perf_counter()
    r = subprocess.run([glint_binary, scene, *flags, "-o", out], capture_output=True, text=True, check=True)
    cli_process.append(time.perf_counter() - t)
    cli_render.append(float(re.search(r"([0-9.]+) s wall", r.stderr).group(1)))
    t = time.perf_counter()
    r = subprocess.run([sys.executable, "-c", child, scene, out], capture_output=True, text=True, check=True)
    py_process.append(time.perf_counter() - t)
    py_render.append(float(r.stdout))


def row(name, cli, py):
    c, p = statistics.median(cli), statistics.median(py)
    print("%-14s medians: CLI %.3f s, Python %.3f s, %+.1f %%; minima: %.3f s, %.3f s, %+.1f %%" % (
        name, c, p, 100 * (p - c) / c, min(cli), min(py), 100 * (min(py) - min(cli)) / min(cli)))
    print("%-14s CLI %s; Python %s" % ("", " ".join("%.3f" % x for x in cli), " ".join("%.3f" % x for x in py)))


print("%s, %s, %d runs each, alternating; load %s" % (scene, flags, runs, os.getloadavg()))
row("render", cli_render, py_render)
row("whole process", cli_process, py_process)
