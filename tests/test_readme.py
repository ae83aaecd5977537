"""The README's Python example runs as written."""

import re
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[1] / "README.md"


def test_readme_python_blocks_run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)
    assert blocks
    monkeypatch.chdir(tmp_path)
    spaces = []
    for block in blocks:
        namespace: dict = {}
        exec(compile(block, "README.md", "exec"), namespace)
        spaces.append(namespace)
    r = spaces[0]["r"]
    diagram = spaces[1]["diagram"]
    assert [iv.regime for iv in diagram.intervals] == ["stick-slip", "bistable", "steady-sliding"]
    assert [round(iv.nu_max, 4) for iv in diagram.intervals[:2]] == [0.4623, 0.6696]  # as the README says
    assert r.regime == "stick-slip"
    assert round(spaces[0]["ss"].cycle(spaces[0]["d"]).multiplier, 3) == 0.824  # as the README says
    assert (tmp_path / "trajectory.csv").exists()
