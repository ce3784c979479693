# test_install.py — cmake --install puts the module where GLINT_PYTHON_INSTALL_DIR says under the prefix given,
# and the installed module imports and renders on its own (no libglint.so needed, nothing but PyInit exported).
import os
import subprocess
import sys

import pytest


@pytest.mark.skipif("GLINT_BUILD_DIR" not in os.environ, reason="run by CTest, which names the build")
def test_installed_module_imports_and_renders(tmp_path):
    prefix = tmp_path / "prefix"
    # cmake itself without the sanitizers' runtimes, which a sanitized build's tests preload (it hangs under them)
    plain = {k: v for k, v in os.environ.items() if k != "LD_PRELOAD"}
    subprocess.run([os.environ["GLINT_CMAKE"], "--install", os.environ["GLINT_BUILD_DIR"], "--prefix", str(prefix)],
                   check=True, stdout=subprocess.DEVNULL, env=plain, timeout=120)
    where = os.path.join(str(prefix), os.environ["GLINT_PYTHON_INSTALL_DIR"])
    modules = [f for f in os.listdir(where) if f.startswith("glint.") and f.endswith(".so")]
    assert len(modules) == 1, os.listdir(where)
    code = ("import glint; s = glint.parse('{\"render\": {\"width\": 4, \"height\": 2, \"background\": 1}}'); "
            "print(glint.__file__); print(s.render().sum())")
    env = dict(os.environ, PYTHONPATH=where)
    out = subprocess.run([sys.executable, "-c", code], env=env, cwd=str(tmp_path), check=True, capture_output=True,
                         text=True, timeout=60).stdout
    assert out == "%s\n24.0\n" % os.path.join(where, modules[0])
    exported = subprocess.run(["nm", "-D", "--defined-only", os.path.join(where, modules[0])], check=True,
                              capture_output=True, text=True).stdout.split()
    assert [name for name in exported if not name.startswith("_") and name.isidentifier()
            and name not in ("T", "D", "B", "R", "W")] == ["PyInit_glint"]
