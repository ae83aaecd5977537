"""The conformance suite of every registered law, and the law registered by the tests only.

Each test runs on every law of the registry: the built-in ones and the Stribeck law of
``tests/laws_for_tests.py``, which no module of the package knows. Expected values come
from the law's formula read by sympy on its own (``sympy.sympify``), from the map
formulas likewise, from ``tests/reference/one_block.py`` (an independent SciPy integration) and
from closed forms; never from the code under test.
"""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest
import sympy as sp
from click.testing import CliRunner
from laws_for_tests import STRIBECK, PhysicalStribeckLaw, StribeckLaw
from reference.one_block import reference_cycle

import stickslip as ss
from stickslip.bifurcation.regimes import regimes
from stickslip.cli import main
from stickslip.core.laws import N_LAW_PARAMS
from stickslip.dynamics.sweep import sweep, sweepable
from stickslip.laws import BUILTIN_LAWS, registry
from stickslip.laws.docs import laws_markdown

NAMES = registry.names()
W = np.concatenate([np.linspace(1e-6, 0.5, 40), np.geomspace(0.5, 20.0, 20)])


def _example(name: str) -> ss.DimensionlessLaw:
    e = registry.get(name)
    return e.dimensionless(**e.spec.example)


def _sympy_f(name: str) -> tuple[sp.Expr, sp.Symbol, dict[str, float]]:
    """The law's formula read by sympy itself, with the example's values substituted."""
    spec = registry.get(name).spec
    w = sp.Symbol("w")
    names = {p.name: sp.Symbol(p.name) for p in spec.parameters}
    expr = sp.sympify(spec.f, locals={"w": w, **names})
    values = {p.name: spec.example.get(p.name, p.default) for p in spec.parameters}
    return expr.subs({names[k]: v for k, v in values.items()}), w, values


def test_the_test_law_is_registered_and_only_by_the_tests() -> None:
    assert "stribeck" in NAMES
    assert "stribeck" not in BUILTIN_LAWS
    assert registry.get("stribeck").spec is STRIBECK


@pytest.mark.parametrize("name", NAMES)
def test_kernel_matches_the_formula(name: str) -> None:
    """The compiled kernel (hand-written or generated) against the formula, values and slope."""
    law = _example(name)
    expr, w, _ = _sympy_f(name)
    f = sp.lambdify(w, expr, "math")
    df = sp.lambdify(w, sp.diff(expr, w), "math")
    k = law.kernel
    lp = np.zeros(N_LAW_PARAMS)
    lp[: law.core_params().size] = law.core_params()
    P = tuple(lp)
    for x in W:
        assert k.engine.f_plus(k.law_id, P, x) == pytest.approx(f(x), rel=1e-13, abs=1e-15)
        assert k.engine.df_plus(k.law_id, P, x) == pytest.approx(df(x), rel=1e-11, abs=1e-13)
    # just below w = 0 (samples before a stop): the continuation agrees with the Taylor polynomial
    taylor = sp.lambdify(w, sp.series(expr, w, 0, 6).removeO(), "math")
    for x in (-1e-4, -1e-3):
        assert k.engine.f_plus(k.law_id, P, x) == pytest.approx(taylor(x), rel=1e-12, abs=1e-15)


@pytest.mark.parametrize("name", NAMES)
def test_numpy_derivatives_match_the_formula(name: str) -> None:
    law = _example(name)
    expr, w, _ = _sympy_f(name)
    for order in (0, 1, 2, 3):
        ref = sp.lambdify(w, sp.diff(expr, w, order), "numpy")
        np.testing.assert_allclose(
            law.forward(W, order), np.broadcast_to(ref(W), W.shape), rtol=1e-12, atol=1e-14
        )
    # odd in w, set-valued (0) at rest
    np.testing.assert_allclose(law.value(-W), -law.value(W))
    assert law.value(0.0) == 0.0


@pytest.mark.parametrize("name", NAMES)
def test_physical_form_is_mu_s_times_f_of_beta_v(name: str) -> None:
    """``mu(v) = mu_s f(beta v)``, with the dimensionless values from the map formulas (read by sympy)."""
    spec = registry.get(name).spec
    law = _example(name)
    beta, mu_s = 87.0, 0.41
    plaw = law.to_physical(ss.Q_(beta, "s/m"), mu_s)
    assert isinstance(plaw, registry.get(name).physical_class)
    # the map read by sympy: physical values back to the dimensionless ones
    env = {**plaw.si_parameters(), "beta": beta, "mu_s": mu_s}
    symbols = {k: sp.Symbol(k) for k in env}
    for k, text in spec.to_dimensionless.items():
        value = sp.sympify(text, locals=symbols).subs({symbols[n]: x for n, x in env.items()})
        assert float(value) == pytest.approx(law.params[k], rel=1e-13)
    expr, w, _ = _sympy_f(name)
    v = np.linspace(1e-5, 0.05, 30)
    mu = np.array([float(expr.subs(w, beta * x)) for x in v]) * mu_s
    np.testing.assert_allclose(plaw.coefficient(ss.Q_(v, "m/s")), mu, rtol=1e-12)
    back = plaw.nondimensionalize(ss.Q_(beta, "s/m"))
    assert back == law or all(back.params[k] == pytest.approx(x, rel=1e-13) for k, x in law.params.items())


@pytest.mark.fast
@pytest.mark.parametrize("name", NAMES)
def test_validation_names_the_parameter(name: str) -> None:
    e = registry.get(name)
    for p in e.spec.parameters:
        bad = [math.nan, math.inf, "abc"]
        if p.lower > -math.inf:
            bad.append(p.lower - 1.0 if p.lower_inclusive else p.lower)
        if p.upper < math.inf:
            bad.append(p.upper + (0.0 if not p.upper_inclusive else 1.0))
        for value in bad:
            with pytest.raises(ValueError, match=f"^{p.name}="):
                e.dimensionless(**{**e.spec.example, p.name: value})
        # the vectorised path (sweeps) gives the same message, with the point
        values = {q.name: np.full(3, e.spec.example.get(q.name, q.default or 0.0)) for q in e.spec.parameters}
        values[p.name] = np.array([values[p.name][0], values[p.name][0], math.nan])
        with pytest.raises(ValueError, match=rf"^{p.name}=nan is NaN \(point 2\)"):
            e.spec.validate(values)
    with pytest.raises(TypeError, match="unknown parameter"):
        e.dimensionless(**e.spec.example, nonsense=1.0)


@pytest.mark.parametrize("name", NAMES)
def test_stick_slip_cycle_against_the_reference(name: str) -> None:
    """Engine vs the independent SciPy reference (its own copy of the formula), and the energy balance."""
    law = _example(name)
    nu = 0.01
    r = ss.cycle(ss.DimensionlessParameters(nu=nu, law=law), probe=False)
    assert r.regime == "stick-slip" and r.status == "ok"
    ref = reference_cycle(name, {k: float(v) for k, v in law.params.items()}, nu)
    assert r.amplitude == pytest.approx(ref.amplitude, rel=1e-8)
    assert r.period == pytest.approx(ref.period, rel=1e-8)
    assert r.drive_work == pytest.approx(r.friction_work, rel=1e-8)


@pytest.mark.fast
@pytest.mark.parametrize("name", NAMES)
def test_laws_pickle_by_value(name: str) -> None:
    law = _example(name)
    plaw = law.to_physical(ss.Q_(42.0, "s/m"), 0.5)
    assert pickle.loads(pickle.dumps(law)) == law
    assert pickle.loads(pickle.dumps(plaw)) == plaw


@pytest.mark.fast
@pytest.mark.parametrize("name", NAMES)
def test_command_line_options_come_from_the_registry(name: str) -> None:
    help_text = CliRunner().invoke(main, ["cycle", "--help"]).output
    spec = registry.get(name).spec
    for p in (*spec.parameters, *spec.physical):
        assert f"--{p.name.replace('_', '-')}" in help_text
    assert name in help_text  # a --law choice


@pytest.mark.parametrize("name", NAMES)
def test_sweeps_know_the_parameters(name: str) -> None:
    law = _example(name)
    spec = law.spec
    assert sweepable(ss.DimensionlessParameters(nu=0.1, law=law)) == [
        "nu",
        *(p.name for p in spec.parameters),
    ]
    plaw = law.to_physical(ss.Q_(42.0, "s/m"), 0.5)
    phys = ss.PhysicalParameters(mass="1 kg", stiffness="62 N/m", load="196 mN", v0="5 um/s", law=plaw)
    assert set(sweepable(phys)) == {
        "v0",
        "mass",
        "stiffness",
        "load",
        "beta",
        "mu_s",
        *(p.name for p in spec.physical),
    }


def test_docs_table_is_current() -> None:
    """docs/laws.md's table is the registry's (python tools/gen_laws_doc.py rewrites it)."""
    from pathlib import Path

    doc = (Path(__file__).resolve().parent.parent / "docs" / "laws.md").read_text(encoding="utf-8")
    assert laws_markdown(BUILTIN_LAWS).strip() in doc


# --------------------------------------------------------------------------- the test-only law everywhere


LAW = StribeckLaw(kin=0.5, ws=0.2, eta=0.05)
# f'(nu) = -(1 - kin)/ws exp(-nu/ws) + eta = 0
NU_HOPF = 0.2 * math.log((1 - 0.5) / (0.2 * 0.05))


def test_test_law_in_cycle_dimensionless_and_physical() -> None:
    r = ss.cycle(ss.DimensionlessParameters(nu=0.05, law=LAW))
    ref = reference_cycle("stribeck", {"kin": 0.5, "ws": 0.2, "eta": 0.05}, 0.05)
    assert r.regime == "stick-slip"
    assert r.amplitude == pytest.approx(ref.amplitude, rel=1e-8)
    # physical: mu_k = kin mu_s, v_s = ws / beta, visc = eta mu_s beta (typed here, from the formulas)
    beta, mu_s = 42.0, 0.5
    plaw = PhysicalStribeckLaw(
        mu_s=mu_s, mu_k=0.25, v_s=f"{0.2 / beta} m/s", visc=f"{0.05 * mu_s * beta} s/m"
    )
    mass = (beta * mu_s * 0.196) ** 2 / 62.0
    p = ss.PhysicalParameters(
        mass=f"{mass} kg", stiffness="62 N/m", load="196 mN", v0=f"{0.05 / beta} m/s", law=plaw
    )
    rp = ss.cycle(p, probe=False)
    assert rp.amplitude == pytest.approx(ref.amplitude * mu_s * 0.196, rel=1e-8)


def test_test_law_in_a_sweep() -> None:
    ds = sweep(
        ss.DimensionlessParameters(nu=0.05, law=LAW), {"nu": [0.02, 0.05], "ws": [0.1, 0.2]}, progress=False
    )
    assert dict(ds.sizes) == {"nu": 2, "ws": 2}
    ref = reference_cycle("stribeck", {"kin": 0.5, "ws": 0.1, "eta": 0.05}, 0.02)
    assert float(ds.amplitude.sel(nu=0.02, ws=0.1)) == pytest.approx(ref.amplitude, rel=1e-8)
    assert ds.attrs["law"] == "stribeck"


def test_test_law_in_regimes() -> None:
    d = regimes(LAW, 0.2, 3.0, n_grid=41)
    (h,) = d.hopf
    assert h.nu == pytest.approx(NU_HOPF, rel=1e-9)
    # f''' = -(1 - kin)/ws^3 exp(-nu/ws) < 0: subcritical (PHYSICS.md §3): above the Hopf point
    # steady sliding is stable but stick-slip persists (bistable) until the unstable cycle grazes
    assert h.criticality == "subcritical"
    assert [iv.regime for iv in d.intervals] == ["stick-slip", "bistable", "steady-sliding"]
    assert d.intervals[0].nu_max == pytest.approx(NU_HOPF, rel=1e-9)


def test_test_law_on_the_command_line() -> None:
    res = CliRunner().invoke(
        main,
        [
            "cycle",
            "--law",
            "stribeck",
            "--kin",
            "0.5",
            "--ws",
            "0.2",
            "--eta",
            "0.05",
            "--nu",
            "0.05",
            "--json",
        ],
    )
    assert res.exit_code == 0, res.output
    ref = reference_cycle("stribeck", {"kin": 0.5, "ws": 0.2, "eta": 0.05}, 0.05)
    import json

    d = json.loads(res.output)
    assert d["amplitude"] == pytest.approx(ref.amplitude, rel=1e-8)
    assert d["parameters"]["law"] == "stribeck"
    bad = CliRunner().invoke(
        main, ["cycle", "--law", "stribeck", "--kin", "1.5", "--ws", "0.2", "--nu", "0.05"]
    )
    assert bad.exit_code == 2 and "kin=1.5 is too large" in bad.output
    other = CliRunner().invoke(
        main, ["cycle", "--law", "weakening", "--c", "3", "--ws", "0.2", "--nu", "0.05"]
    )
    assert other.exit_code == 2 and "--ws belongs to --law stribeck" in other.output
