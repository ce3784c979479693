# test_docs.py — every example of docs/python.md runs, in order, as one program (in a temporary directory that
# sees the repository's scenes/).
import os
import re

from conftest import SOURCE_DIR


def test_examples_of_docs_python_md_run(tmp_path, monkeypatch, capsys):
    with open(os.path.join(SOURCE_DIR, "docs", "python.md")) as f:
        blocks = re.findall(r"```python\n(.*?)```", f.read(), re.S)
    assert len(blocks) >= 12
    os.symlink(os.path.join(SOURCE_DIR, "scenes"), tmp_path / "scenes")
    monkeypatch.chdir(tmp_path)
    namespace = {}
    for block in blocks:
        exec(compile(block, "docs/python.md", "exec"), namespace)
        if "scenes/missing.json" in block:  # its comment shows what it prints
            assert capsys.readouterr().out.endswith("scenes/missing.json: cannot open: No such file or directory\n")
    assert os.path.getsize("box.png") > 0 and os.path.getsize("box.exr") > 0
