"""The README's Python example runs as printed (from the source directory, writing to a
temporary directory) and its comments hold."""
import os
import re

import pytest

from conftest import SOURCE_DIR


def test_readme_example_runs(tmp_path, monkeypatch):
    text = (SOURCE_DIR / "README.md").read_text()
    code = re.search(r"```python\n(.*?)```", text, re.S).group(1)
    assert len(code.strip().split("\n")) == 10
    code = code.replace('"sphere.vtk"', repr(str(tmp_path / "sphere.vtk")))
    monkeypatch.chdir(SOURCE_DIR)
    scope = {}
    exec(compile(code, "README.md", "exec"), scope)
    assert scope["pd"].compare(scope["ref"], scope["fast"])["bitwise"]
    # phi at (0, 0, 1.2) of the unit icosphere: 0.2 up to the chord error of its faces (1.2e-3)
    assert scope["phi"][0] == pytest.approx(0.2, abs=2e-3) and scope["grad"][0][2] == pytest.approx(1.0, abs=1e-3)
    assert (tmp_path / "sphere.vtk").exists()
