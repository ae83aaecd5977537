"""What makes the first run compile in less time changes no number.

- Each built-in law runs on an engine compiled with that law alone
  (:func:`stickslip.laws.compiler.builtin_kernel`): its cycles equal, bit for bit,
  those of the engine that switches over the four laws (:mod:`stickslip.core.engine`).
- numba's typing of operators is remembered per argument types
  (:mod:`stickslip.core._typing_memo`): the LLVM IR numba emits is the same with
  and without it (compiled in fresh processes).
- A built-in law's formulas, no longer checked at import, pass the checks.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from stickslip.core.api import Kernel, builtin_kernel, run_attractors
from stickslip.laws import registry
from stickslip.laws.compiler import builtin_module_source

CASES = [  # (law id, parameters, driving velocities): stick-slip, pure slip and steady sliding
    (0, [3.8, 0.0], [1e-3, 0.05, 0.4]),  # F1
    (0, [5.0, 0.05], [1e-3, 0.2, 2.0]),  # F2 (p > 0: the branch that adds p w)
    (1, [0.5, 0.2], [0.05, 0.3, 0.8]),  # cubic
    (2, [0.6], [1e-3, 0.1]),  # Coulomb
    (3, [2.5, 0.01], [0.01, 0.1]),  # Carlson-Langer
]


def _rows(kernel: Kernel | int, lp: list[float], nu: list[float]) -> np.ndarray:
    opts = {"rtol": 1e-9, "atol": 1e-12, "max_slip_time": 1e4, "conv_tol": 1e-8}
    return run_attractors(kernel, lp, nu, from_breakaway=True, diag=True, **opts).raw


@pytest.mark.parametrize(
    ("law_id", "lp", "nu"),
    # the cubic and Coulomb laws' own packages (a compile each, 21-27 s of CI's two cores): slow
    [pytest.param(*case, marks=pytest.mark.slow) if case[0] in (1, 2) else case for case in CASES],
)
def test_a_law_alone_gives_the_builtin_engine_bit_for_bit(
    law_id: int, lp: list[float], nu: list[float]
) -> None:
    name = builtin_kernel(law_id).name
    own = registry.get(name).spec.kernel()
    assert own.engine is not builtin_kernel(law_id).engine  # the law's own package
    assert own.law_id == law_id
    mine, generic = _rows(own, lp, nu), _rows(law_id, lp, nu)
    assert np.isfinite(mine[:, :4]).all()
    np.testing.assert_array_equal(mine, generic)


def test_a_law_alone_holds_only_that_law() -> None:
    src = builtin_module_source(1)
    assert "cubic_f as f_plus" in src and "weakening" not in src
    assert "weakening_accel as slip_accel" in builtin_module_source(0)


def test_builtin_law_formulas_pass_the_checks() -> None:
    builtins = [e.spec for e in registry.entries() if e.spec.core_id is not None]
    assert sorted(s.core_id for s in builtins) == [0, 1, 2, 3]
    for spec in builtins:
        spec.check_formulas()  # raises on a bad formula or map
        assert spec.physical and spec._inverse  # the physical map inverted


_CHILD = r"""
import json, sys
from stickslip.core import _typing_memo
from stickslip.core._dop853_unrolled import step_sw
from stickslip.core.laws import params
import numpy as np
P = params(np.array([3.8, 0.0, 0, 0, 0, 0, 0, 0]))
step_sw(0, P, 0.01, 1, 0.9, 0.1, 0.0, 0.8, 0.01, 1e-9, 1e-12)
sig = step_sw.signatures[0]
print(json.dumps({"memo": _typing_memo.installed(), "ir": step_sw.inspect_llvm(sig)}))
"""


def _ir(memo: str, cache: Path) -> dict:
    # one hash seed for both: numba mangles the compile flags into symbol names, and the
    # flags hold a set (fastmath's) whose printed order follows the seed
    env = dict(os.environ, STICKSLIP_NUMBA_MEMO=memo, NUMBA_CACHE_DIR=str(cache), PYTHONHASHSEED="0")
    out = subprocess.run([sys.executable, "-c", _CHILD], env=env, capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


@pytest.mark.slow
def test_typing_memo_leaves_the_code_unchanged(tmp_path: Path) -> None:
    with_memo, without = _ir("1", tmp_path / "a"), _ir("0", tmp_path / "b")
    assert with_memo["memo"] and not without["memo"]
    assert len(with_memo["ir"]) > 10_000  # the unrolled step: a real amount of code
    assert with_memo["ir"] == without["ir"]


def test_blocks_cover_every_row_once_and_stop_at_an_error(monkeypatch: pytest.MonkeyPatch) -> None:
    """The thread pool of the row kernels (which replaced a prange kernel that compiled seconds longer)."""
    import threading
    import time

    from stickslip.core import kernel as api  # the module whose threads() in_blocks reads

    monkeypatch.setattr(api, "threads", lambda: 3)
    seen: list[int] = []
    lock = threading.Lock()

    def record(lo: int, hi: int) -> None:
        with lock:
            seen.extend(range(lo, hi))

    api.in_blocks(record, 1000)
    assert sorted(seen) == list(range(1000))
    started: list[int] = []

    def fails_first(lo: int, hi: int) -> None:
        started.append(lo)
        if lo == 0:
            raise ValueError("first block")
        time.sleep(0.02)

    with pytest.raises(ValueError, match="first block"):
        api.in_blocks(fails_first, 1000)  # 48 blocks of 21 rows
    assert 1 <= len(started) < 12  # the blocks not started were cancelled


def test_a_few_rows_run_alone_equal_the_batch_kernel_bit_for_bit() -> None:
    """Up to SERIAL_ROWS rows go to the per-row kernel from Python, more to the batch kernel."""
    from stickslip.core import api

    for law_id, lp, nu in CASES:
        many = np.tile(np.array(nu), 5)  # more rows than SERIAL_ROWS: attractor_rows
        assert many.size > api.SERIAL_ROWS
        batch = _rows(law_id, lp, list(many))
        alone = np.vstack([_rows(law_id, lp, [v]) for v in nu])  # one row: attractor_ws
        np.testing.assert_array_equal(batch[: len(nu)], alone)


_CYCLE_CHILD = r"""
import json
from stickslip import cycle, DimensionlessParameters, WeakeningLaw
from stickslip.laws import law_arrays
law = WeakeningLaw(c=3.8)
r = cycle(DimensionlessParameters(nu=1e-3, law=law))
eng = law_arrays(law)[0].engine  # the law's own compiled package
print(json.dumps({"regime": str(r.regime), "rows": len(eng.attractor_rows.signatures),
                  "one": len(eng.attractor_ws.signatures)}))
"""


def test_a_cycle_needs_no_batch_kernel() -> None:
    """`stickslip cycle` runs two rows: it neither compiles nor loads attractor_rows (1-2 s cold)."""
    out = subprocess.run([sys.executable, "-c", _CYCLE_CHILD], capture_output=True, text=True, check=True)
    got = json.loads(out.stdout.strip().splitlines()[-1])
    assert got == {"regime": "stick-slip", "rows": 0, "one": 1}
