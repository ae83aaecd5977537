"""The README's Python example runs as written."""

import math
import re
from pathlib import Path

import pytest
from reference.one_block import cubic_orbit_reference, stick_slip_border

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
    # the borders computed without stickslip: the Hopf point of 1/(1 + c w) + p w, where
    # f'(nu) = 0, is (sqrt(c/p) - 1)/c; the stick-slip cycle ends where the slip phase from
    # breakaway no longer stops (SciPy, bisected to 1e-8): 0.46232 and 0.66962 for c = 3.8, p = 0.5
    c, p = 3.8, 0.5
    hopf = (math.sqrt(c / p) - 1.0) / c
    border = stick_slip_border("weakening", {"c": c, "p": p}, 0.47, 1.0)
    assert [iv.nu_max for iv in diagram.intervals[:2]] == pytest.approx([hopf, border], abs=1e-6)
    assert f"('bistable', {hopf:.4f}, {border:.4f})" in README.read_text()  # the README's printed line
    assert r.regime == "stick-slip"
    # the pure-slip orbit's multiplier by plain SciPy shooting (Liouville's formula): 0.82411
    multiplier = cubic_orbit_reference(0.97, 0.5, 0.5 / 3).multiplier
    assert spaces[0]["ss"].cycle(spaces[0]["d"]).multiplier == pytest.approx(multiplier, abs=1e-6)
    assert f"Floquet multiplier {multiplier:.3f}" in README.read_text()
    assert (tmp_path / "trajectory.csv").exists()


def readme_commands() -> list[str]:
    """Return every command of the README's shell blocks, as written (continued lines joined)."""
    commands = []
    for block in re.findall(r"```bash\n(.*?)```", README.read_text(), flags=re.S):
        text = re.sub(r"\\\n\s*", " ", block)
        commands += [ln.strip() for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    return commands


#: commands this test does not run, and why (each is run elsewhere)
NOT_HERE = {
    "bash .ci/run": "the test suite itself",
    "bash .ci/docs": "built by .ci/run after the tests",
    "stickslip explore": "a server: tests/test_explore.py serves it to chromium",
}


def _snapshot(root: Path) -> dict[str, tuple[int, int]]:
    return {
        str(p.relative_to(root)): (p.stat().st_mtime_ns, p.stat().st_size)
        for p in root.rglob("*")
        if p.is_file()
    }


@pytest.mark.slow
def test_readme_shell_blocks_run_as_written_and_write_apart(tmp_path: Path) -> None:
    """Every shell command of the README, in order, in an empty folder: each ends with status 0,
    and no file is written by two commands (each writes into its own folder)."""
    import os
    import shutil
    import subprocess
    import sys
    import time

    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}")
    env.pop("STICKSLIP_PROGRESS", None)
    assert shutil.which("stickslip", path=env["PATH"])
    commands = readme_commands()
    assert commands[0].startswith("pip install . && stickslip reproduce")
    writer: dict[str, str] = {}
    failed, twice, took = [], [], []
    for cmd in commands:
        if cmd in NOT_HERE:
            continue
        if cmd.startswith("pip install . && "):  # installed already: what follows runs as written
            cmd = cmd.removeprefix("pip install . && ")
        if "--backend cuda" in cmd:
            from numba import cuda

            if not cuda.is_available():
                continue
        before = _snapshot(tmp_path)
        start = time.perf_counter()
        res = subprocess.run(
            cmd, shell=True, cwd=tmp_path, env=env, capture_output=True, text=True, timeout=1800
        )
        took.append((time.perf_counter() - start, cmd[:60]))
        if res.returncode != 0:
            failed.append(f"{cmd}\n  -> {res.returncode}: {(res.stderr or res.stdout).strip()[-400:]}")
        for name, stamp in _snapshot(tmp_path).items():
            if before.get(name) != stamp:
                if name in writer and not name.endswith("stickslip-manifest.json"):
                    twice.append(f"{name}: {writer[name]!r} then {cmd!r}")
                writer[name] = cmd
    print("\n".join(f"{t:7.1f} s  {c}" for t, c in took))
    print(f"{sum(t for t, _ in took):7.1f} s  in all")
    assert not failed, "\n".join(failed)
    assert not twice, "\n".join(twice)
