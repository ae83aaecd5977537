"""The docs' transcripts are what the commands print today.

A fenced block in ``docs/*.md`` whose lines start with ``$ stickslip`` is a transcript:
each command is run (in process) and its output compared line by line with the lines
after it. The averaging table of docs/regimes.md is compared number by number with
``tools/averaging_table.py`` to 1e-8: a hand-copied table drifts in its last digits
(l1 0.3563 for 0.3562), which a reader cannot see.
"""

from __future__ import annotations

import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

from stickslip.cli import main

ROOT = Path(__file__).resolve().parents[1]
DOCS = sorted(p for p in (ROOT / "docs").glob("*.md") if p.name not in ("benchmarks.md", "robustness.md"))


def _transcripts() -> list[tuple[str, str, list[str]]]:
    """Return ``(doc, command, expected lines)`` for every ``$ stickslip`` line in a fenced block."""
    out = []
    for doc in DOCS:
        for block in re.findall(r"^```[^\n]*\n(.*?)^```", doc.read_text(), flags=re.M | re.S):
            lines = block.rstrip("\n").split("\n")
            if not lines or not lines[0].startswith("$ stickslip"):
                continue
            cmd: str | None = None
            expected: list[str] = []
            for line in [*lines, "$ "]:
                if line.startswith("$ "):
                    if cmd is not None:
                        out.append((doc.name, cmd, [e for e in expected if e.strip()]))
                    cmd, expected = line[2:], []
                else:
                    expected.append(line.rstrip())
    return out


TRANSCRIPTS = _transcripts()


def test_the_docs_have_transcripts() -> None:
    assert len(TRANSCRIPTS) >= 2, TRANSCRIPTS  # docs/regimes.md's two examples at least


@pytest.mark.parametrize(("doc", "command", "expected"), TRANSCRIPTS, ids=[t[1][:60] for t in TRANSCRIPTS])
def test_a_transcript_is_what_the_command_prints(doc: str, command: str, expected: list[str]) -> None:
    args = shlex.split(command)
    assert args[0] == "stickslip"
    res = CliRunner().invoke(main, args[1:])
    assert res.exit_code == 0, res.output
    got = [line.rstrip() for line in res.output.splitlines() if line.strip()]
    assert got == expected, f"{doc}: `{command}` prints\n" + "\n".join(got)


def _numbers(line: str) -> list[float]:
    return [float(x) for x in re.findall(r"-?\d+\.?\d*(?:e[-+]?\d+)?", line)]


def test_the_averaging_table_is_what_the_tool_prints() -> None:
    text = (ROOT / "docs" / "regimes.md").read_text()
    doc_rows = [line for line in text.splitlines() if re.match(r"^\| (1|0\.\d+) \| ", line)]
    tool = ROOT / "tools" / "averaging_table.py"
    run = subprocess.run([sys.executable, str(tool)], capture_output=True, text=True, check=True)
    tool_rows = [line for line in run.stdout.splitlines() if re.match(r"^\| (1|0\.\d+) \| ", line)]
    assert len(doc_rows) == len(tool_rows) == 6
    for d, t in zip(doc_rows, tool_rows, strict=True):
        assert _numbers(d) == pytest.approx(_numbers(t), rel=1e-8), (d, t)
