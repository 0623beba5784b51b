"""docs/python.md's session runs: its ```python blocks, in order and in one namespace, in a
temporary folder holding links to the two CMU golf clips of the shared data (never copies)."""
import os
import re

import pytest

import conftest

DOC = os.path.join(os.path.dirname(__file__), "..", "..", "docs", "python.md")


def test_python_md_code_blocks_run(tmp_path, monkeypatch, capsys):
    pytest.importorskip("sklearn")
    for rel in (conftest.GOLF, conftest.GOLF2):
        os.symlink(conftest.data_path(rel), tmp_path / os.path.basename(rel))
    blocks = re.findall(r"```python\n(.*?)```", open(DOC).read(), re.S)
    assert len(blocks) >= 5
    monkeypatch.chdir(tmp_path)
    namespace = {}
    for i, block in enumerate(blocks):
        exec(compile(block, f"docs/python.md block {i + 1}", "exec"), namespace)
    out = capsys.readouterr().out
    # What the comments say is printed.
    assert "<motionmap.Clip '64_08.bvh': 365 frames at 120 fps, 31 joints>" in out
    assert "['Hips', 'LHipJoint', 'LeftUpLeg'] [-1  0  1]" in out
    assert "features: unknown name 'quaternions' (expected one of quat, positions)" in out
    assert (tmp_path / "golf.csv").exists() and (tmp_path / "golf.mmap.h5").exists()
