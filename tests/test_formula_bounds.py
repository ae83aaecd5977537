"""A formula's preparation is bounded: nesting, Taylor coefficients by series, code by parts.

The continuation of a formula law to ``w < 0`` is its Taylor polynomial of degree 10
at 0. Built from ten successive sympy derivatives, a 49-character formula took
minutes (82 000 operations in the eighth derivative alone); here its coefficients
come from series arithmetic (:mod:`stickslip.laws.series`) and are checked against
sympy's derivatives, and every case answers within its time limit, compiled or
refused in one line.
"""

from __future__ import annotations

import math
import os
import subprocess
import sys
import time

import numpy as np
import pytest
import sympy as sp

from stickslip import ExpressionLaw
from stickslip.laws.codegen import INLINE_CHARS, law_module_source
from stickslip.laws.formula import MAX_DEPTH, FormulaError, parse_formula
from stickslip.laws.series import Unsupported, derivatives, node_count, taylor
from stickslip.laws.spec import CONTINUATION_NODES

W = sp.Symbol("w", real=True)
#: the 49-character formula whose derivatives hung `cycle` and the explorer
SHORT = "1/(1+w) + 0.001*w*exp(sin(exp(sin(exp(sin(w))))))"


def _nested(levels: int, inner: str = "w") -> str:
    """``cos(sinh(erf(...)))`` ``levels`` deep around ``inner``, added to a weakening law."""
    text = inner
    for i in range(levels):
        text = f"{('cos', 'sinh', 'erf')[i % 3]}({text})"
    return f"1/(1+w) + 0.001*w*{text}"


def _run(code: str, timeout: float) -> tuple[subprocess.CompletedProcess[str], float]:
    """Run Python ``code`` in a fresh process (a hang cannot outlive ``timeout``); return it and its time."""
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=timeout)
    return proc, time.perf_counter() - t0


@pytest.mark.parametrize(
    "text",
    [
        pytest.param(SHORT, marks=pytest.mark.slow),  # 10 s of sympy; its own test below stays
        "1/(1 + c*w) + p*w",
        "exp(-a*w)*cos(w) + atan(w) + asinh(2*w) + erf(w)/3 + tanh(w) + tan(w)",
        "sqrt(1 + w) + (1 + c*w)**q + abs(w - 2) + log(2 + w) + w**3 + 2**w + pi*w",
        "1/(1 + w)**2.5 + (2 + w)**a",
    ],
)
def test_taylor_coefficients_equal_sympys_derivatives(text):
    """Series arithmetic gives f^(k)(0)/k! as sympy's k-th derivative does, to 1e-15 (a double)."""
    expr = parse_formula(text, "f", ("w",))
    coefficients = taylor(expr, W, 10)
    values = {s: sp.Rational(37, 100) for s in expr.free_symbols - {W}}
    d = expr
    for k in range(6):
        exact = sp.N(d.subs(W, 0).subs(values), 40) / math.factorial(k)
        got = sp.N(coefficients[k].subs(values), 40)
        assert abs(got - exact) <= 1e-15 * max(1, abs(exact)), (k, got, exact)
        d = sp.diff(d, W)


def test_numeric_derivatives_equal_sympys():
    """Derivatives of order 2 to 4 by series at many velocities and parameters, to 1e-13."""
    text = "exp(-a*w)*cos(w) + atan(a*w) + asinh(2*w) + erf(w)/3 + tanh(w) + (1 + w)**a + log(3 + w)"
    expr = parse_formula(text, "f", ("w",))
    a = sp.Symbol("a", real=True)
    w = np.array([0.1, 0.7, 1.3, 5.0])[:, None]
    values = np.array([0.3, 1.7, 2.5])[None, :]
    for order in (2, 3, 4):
        exact = sp.lambdify((W, a), sp.diff(expr, W, order), modules=["scipy", "numpy"])(w, values)
        got = derivatives(expr, W, [a], w, [values], order)
        np.testing.assert_allclose(got, exact, rtol=1e-13, atol=1e-13)


def test_a_node_without_a_series_rule_falls_back_to_derivatives():
    """sign() and sqrt(w) at 0 have no series: derivatives and limits give the continuation."""
    with pytest.raises(Unsupported):
        taylor(sp.sign(W - sp.Rational(1, 2)) * W, W, 3)
    law = ExpressionLaw("1/(1 + 3*w) + 0.01*sqrt(w) + 0.1*w*abs(w - 2)")
    assert law.spec.continuation_coefficients == (1,)  # sqrt's slope is infinite at 0: a constant
    # the second derivative by series at w = 0.5 (sympy's holds a DiracDelta of abs's kink)
    exact = 18 / 2.5**3 - 0.01 * 0.25 * 0.5**-1.5 - 0.2
    assert law.forward(np.array([0.5]), 2)[0] == pytest.approx(exact, rel=1e-13)


def test_the_short_formula_prepares_in_a_second_and_its_continuation_is_right():
    """SHORT (sympy: minutes) prepares in well under 30 s; its polynomial is f's Taylor's."""
    code = (
        "import time; t = time.perf_counter()\n"
        "from stickslip import ExpressionLaw\n"
        f"law = ExpressionLaw({SHORT!r}); src = law.spec.kernel_source()\n"
        "print(time.perf_counter() - t, len(law.spec.continuation_coefficients))"
    )
    proc, _ = _run(code, timeout=30)
    assert proc.returncode == 0, proc.stderr
    seconds, degree = proc.stdout.split()
    assert float(seconds) < 30.0 and int(degree) == 11
    law = ExpressionLaw(SHORT)
    poly = sum(float(c) * W**k for k, c in enumerate(law.spec.continuation_coefficients))
    for w in (-1e-3, -1e-2):  # the formula is analytic at 0: its value is the polynomial's to w**11
        exact = sp.N(law.spec.expr.subs(W, w), 30)
        assert float(poly.subs(W, w)) == pytest.approx(float(exact), rel=1e-15)


def test_a_deep_formula_is_refused_in_one_line_naming_its_part():
    """150 levels (a RecursionError before): refused by the parser, the nested part named."""
    with pytest.raises(
        FormulaError, match=r"f: the formula nests 153 levels deep, at most 60, in its part 'erf\("
    ):
        ExpressionLaw(_nested(150))
    assert MAX_DEPTH == 60
    ExpressionLaw(_nested(MAX_DEPTH - 3))  # the deepest accepted


def test_a_parameter_deep_inside_keeps_its_continuation_within_bounds():
    """Coefficients in a parameter 40 levels deep: series in a second, the polynomial's parts bounded."""
    law = ExpressionLaw(_nested(40, "c*w"), c=0.7)
    t0 = time.perf_counter()
    coefficients = law.spec.continuation_coefficients
    assert time.perf_counter() - t0 < 10.0
    assert 4 <= len(coefficients) <= 11
    assert sum(node_count(c) for c in coefficients) <= CONTINUATION_NODES
    # the printed code holds each shared part once: a tree would be exponentially larger
    src = law.spec.kernel_source()
    assert len(src) < 400_000 and "_t0 = " in src


def test_code_printed_by_parts_evaluates_as_the_formula():
    """A formula printed longer than INLINE_CHARS is printed part by part, with the same values."""
    text = "*".join(f"cosh(sin({i}*w)/{i * i})" for i in range(1, 60))
    expr = parse_formula(f"1/(1 + w) + 0.001*w*{text}", "f", ("w",))
    slope = sp.diff(expr, W)
    src = law_module_source(expr, slope, taylor(expr, W, 10), (), "parts")
    namespace: dict = {}
    plain = src.replace("from numba import njit", "def njit(*args, **kwargs):\n    return lambda f: f")
    exec(plain, namespace)  # the generated module, run as Python
    assert len(sp.pycode(slope)) > INLINE_CHARS  # the slope is printed by parts
    reference = sp.lambdify(W, slope, modules="math")
    for w in (0.0, 0.3, 2.0):
        assert namespace["df_plus"](0, (), w) == pytest.approx(reference(w), rel=1e-13)
    assert namespace["f_plus"](0, (), -1e-3) == pytest.approx(float(expr.subs(W, -1e-3)), rel=1e-14)


@pytest.mark.parametrize(
    ("formula", "expect"),
    [
        pytest.param(
            SHORT, "stick-slip from rest", marks=pytest.mark.slow
        ),  # a compile of its own; 40 levels stays
        (_nested(40), "stick-slip from rest"),
        (_nested(150), "Error: invalid value: f: the formula nests 153 levels deep"),
    ],
    ids=["49-characters", "40-levels", "150-levels"],
)
def test_cycle_answers_each_hostile_formula(formula, expect, tmp_path):
    """`stickslip cycle` answers: compiled (the engine's first compile counted) or one line."""
    env = dict(os.environ, STICKSLIP_CACHE_DIR=str(tmp_path / "kernels"))
    t0 = time.perf_counter()
    proc = subprocess.run(
        [sys.executable, "-m", "stickslip", "cycle", "--law", "expr", "--f", formula, "--nu", "0.5"],
        capture_output=True,
        text=True,
        timeout=180,
        env=env,
    )
    seconds = time.perf_counter() - t0
    out = proc.stdout + proc.stderr
    assert expect in out, out
    assert "Traceback" not in out and "recursion" not in out
    # refused: at once; compiled: the engine's first compile for the law (10 to 30 s on two
    # cores, 60 with a second test beside it) is the most of it
    assert seconds < (10.0 if "Error" in expect else 90.0), seconds
    print(f"{formula[:30]}...: {seconds:.1f} s")
