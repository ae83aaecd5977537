"""Two-parameter diagrams: curves against closed forms, codimension-2 points, sweeps, brute force, outputs.

Closed forms used:

- the weakening law ``f = 1/(1 + c w) + p w`` has ``f'(nu) = 0`` at ``nu_H = (sqrt(c/p) - 1)/c``;
- the law ``f = 1 + w + g w^3 + 0.25 w^5`` has its Hopf curve where ``1 + 3 g nu^2 + 1.25 nu^4 = 0``,
  i.e. ``g = -(1 + 1.25 nu^4)/(3 nu^2)``, whose largest ``g`` (a turning point of the curve in
  ``(nu, g)``) is at ``nu^4 = 0.8``; ``f''' = 6 g + 15 nu^2`` vanishes on it at ``nu^2 = 0.4``,
  ``g = -1``: the Bautin point (``f^(5) = 30 > 0``: the subcritical cycles fold into a stable one).
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

from stickslip import WeakeningLaw
from stickslip.bifurcation.arclength import trace
from stickslip.bifurcation.diagram import two_parameter_diagram
from stickslip.bifurcation.diagram_check import check_diagram, decode, encode
from stickslip.bifurcation.diagram_io import diagram_dataset
from stickslip.bifurcation.planes import Plane
from stickslip.core.api import run_attractors
from stickslip.core.results import Regime
from stickslip.laws.expression import ExpressionLaw

COLAS = Path(__file__).resolve().parents[2] / "shared" / "data" / "colas2019"
BAUTIN_LAW = "1 + w + g*w**3 + 0.25*w**5"


@pytest.fixture(scope="module")
def weakening():
    pl = Plane.dimensionless(WeakeningLaw(c=5, p=0.5), ("nu", (0.05, 2.0)), ("c", (2.0, 20.0)))
    return two_parameter_diagram(pl, raster=150)


@pytest.fixture(scope="module")
def bautin():
    """The plane reaches g = -1.3, where f < 0 above w = 1.6 (the law says so; no orbit goes there)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        law = ExpressionLaw(BAUTIN_LAW, g=-1.0)
        pl = Plane.dimensionless(law, ("nu", (0.2, 2.0)), ("g", (-1.3, -0.7)))
        return two_parameter_diagram(pl, raster=150)


def test_arclength_closes_a_circle_and_locates_its_events():
    c = trace(
        lambda x: np.array([x[0] ** 2 + x[1] ** 2 - 1]),
        np.array([1.0, 0.0]),
        tests={"x": lambda z: z[0]},
        h_max=0.2,
    )
    assert c.end == ("closed", "closed")
    assert np.allclose(np.hypot(c.x[:, 0], c.x[:, 1]), 1.0, atol=1e-12)
    ev = sorted(float(e.x[1]) for e in c.events)
    assert ev == pytest.approx([-1.0, 1.0], abs=1e-12)
    assert all(abs(e.x[0]) < 1e-12 for e in c.events)


def test_weakening_hopf_curve_equals_its_closed_form(weakening):
    (h,) = weakening.curves_of("hopf")
    c, nu = h.y, h.x
    assert np.max(np.abs(nu - (np.sqrt(c / 0.5) - 1) / c)) < 1e-10
    assert c.min() == pytest.approx(2.0, abs=1e-12) and c.max() == pytest.approx(20.0, abs=1e-12)
    assert h.ends == ("edge", "edge")
    # the weakening law's f''' < 0 everywhere: subcritical along the whole curve, no Bautin point
    assert np.all(h.data["f3"] < 0) and not weakening.points_of("bautin")


def test_bautin_point_located_to_1e8_and_curve_through_its_turning_point(bautin):
    (b,) = bautin.points_of("bautin")
    assert b.x == pytest.approx(math.sqrt(0.4), abs=1e-8)
    assert b.y == pytest.approx(-1.0, abs=1e-8)
    assert b.value == pytest.approx(-30 / 384, rel=1e-9)  # -f^(5)/384
    (h,) = bautin.curves_of("hopf")
    assert np.max(np.abs(h.y + (1 + 1.25 * h.x**4) / (3 * h.x**2))) < 1e-10
    # the curve turns back in g at nu = 0.8**0.25 (g = -2/(3 sqrt(0.8))) and is followed through it
    i = int(np.argmax(h.y))
    assert 0 < i < len(h.y) - 1
    assert h.x[i] == pytest.approx(0.8**0.25, abs=0.02)
    assert h.y[i] == pytest.approx(-2 / (3 * math.sqrt(0.8)), abs=1e-3)
    assert h.y[i] < -2 / (3 * math.sqrt(0.8)) + 1e-15
    assert h.ends == ("edge", "edge")
    # sub- below the Bautin point (f''' < 0), super- above
    f3 = h.data["f3"]
    assert np.all(f3[h.x < b.x - 1e-6] < 0) and np.all(f3[h.x > b.x + 1e-6] > 0)


def test_fold_curve_runs_from_the_bautin_point_to_the_fold_grazing_point(bautin):
    folds = bautin.curves_of("fold")
    assert len(folds) == 1
    (f,) = folds
    (b,) = bautin.points_of("bautin")
    ends = {p.kind: p for p in bautin.points if p.kind in ("end", "fold-grazing")}
    assert "end" in ends and "fold-grazing" in ends
    # the fold orbit shrinks into the Bautin point (to the smallest amplitude followed)
    assert ends["end"].x == pytest.approx(b.x, abs=1e-4) and ends["end"].y == pytest.approx(b.y, abs=1e-4)
    # both ways to the fold-grazing point agree: the fold curve's end, the grazing orbit's multiplier 1
    fg = bautin.points_of("fold-grazing")
    assert len(fg) >= 2
    assert max(p.x for p in fg) - min(p.x for p in fg) < 1e-9
    assert max(p.y for p in fg) - min(p.y for p in fg) < 1e-9
    assert np.all(f.data["min_velocity"] >= -1e-12)


def _sweep(law, nus, push):
    """The engine along ``nus``, each run from the last one's spring-force maximum: oscillating or not.

    The first run starts ``push`` above steady sliding; after steady sliding the next run starts
    ``1e-5`` above it (a small disturbance, as a slow ramp leaves).
    """
    kernel, lp = law.arrays()
    out = []
    s0 = law.at(nus[0]) + push
    for nu in nus:
        r = run_attractors(
            kernel,
            lp,
            [nu],
            [s0],
            [nu],
            from_breakaway=False,
            rtol=1e-10,
            atol=1e-12,
            max_slip_time=2e4,
            conv_tol=1e-7,
        )
        moving = not bool(r.is_regime(Regime.STEADY_SLIDING)[0])
        out.append(moving)
        s0 = float(r.s_max[0]) if moving else law.at(nu) + 1e-5
    return np.array(out)


#: ``f - 1`` odd in ``w - 1``: the model at ``nu`` is the model at ``2 - nu`` under
#: ``(s, w) -> (2 - s, 2 - w)``, so its diagram is symmetric about ``nu = 1``. The coefficients
#: put a triple root of the averaged amplitude equation (cubic in the squared amplitude) at
#: amplitude 0.25 when ``nu = 1`` and ``g = 0.05``: near there two folds of cycles meet.
CUSP_LAW = "1 - 0.003125*(w-1) + g*(w-1)**3 - 0.24*(w-1)**5 + (64*0.2/35)*(w-1)**7"


def test_cusp_of_the_fold_curve_is_located_where_two_folds_meet():
    law = ExpressionLaw(CUSP_LAW, g=0.05, static=1.0)
    d = two_parameter_diagram(Plane.dimensionless(law, ("nu", (0.6, 1.4)), ("g", (0.02, 0.08))), label=False)
    cusps = sorted(d.points_of("cusp"), key=lambda p: p.x)
    assert len(cusps) == 2, [(p.x, p.y) for p in cusps]
    left, right = cusps
    assert abs(left.x + right.x - 2.0) < 1e-8 and abs(left.y - right.y) < 1e-9
    assert all(abs(p.value) < 1e-6 for p in cusps)  # P''(A) there
    # the one-parameter continuation, a code of its own: two folds of cycles just below the
    # cusp's g, within 2.5e-3 of its nu, and none just above
    from stickslip.bifurcation.regimes import regimes

    def folds(g: float) -> list[float]:
        r = regimes(law.replace(g=g), 0.83, 0.86, n_grid=11)
        return sorted({round(p.nu, 9) for p in r.points if p.kind == "fold"})

    below = folds(left.y - 1e-4)
    assert len(below) == 2 and all(abs(nu - left.x) < 2.5e-3 for nu in below), below
    assert folds(left.y + 1e-4) == []


def test_hopf_and_grazing_meet_only_as_nu_goes_to_zero_and_no_fold_grazing_is_made_of_noise():
    """The weakening law with c near p: the grazing orbit's ln m is about 0.6 nu^2 > 0 (SciPy
    reference: 5.9e-8 at nu = 3.2e-4), below the noise of ln m at the continuation's tolerance."""
    law = WeakeningLaw(c=1, p=0.5)
    d = two_parameter_diagram(Plane.dimensionless(law, ("nu", (1e-5, 1.0)), ("c", (0.3, 3.0))), label=False)
    assert d.points_of("fold-grazing") == []
    (end,) = d.points_of("end")
    assert "run into each other" in end.detail and end.x == pytest.approx(1e-5, rel=1e-9)
    c = 0.5
    for _ in range(50):  # nu_H(c) = (sqrt(c/p) - 1)/c = 1e-5, by fixed point
        c = 0.5 * (1 + c * 1e-5) ** 2
    assert abs(end.y - c) < 1e-9


@pytest.mark.slow
def test_a_seed_that_converges_onto_a_traced_grazing_curve_adds_no_second_copy():
    """f = 1 + w + g w^3 + b w^5 + e w^7 (three cycles merge near nu = 1): the engine's onset
    scan seeds the grazing curve again far from where the Hopf-born branch met it."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # f < 0 at large w
        law = ExpressionLaw("1 + w + g*w**3 + 0.049123031687776944*w**5 - 0.0023275542140619256*w**7", g=-0.4)
        plane = Plane.dimensionless(law, ("nu", (0.7, 1.3)), ("g", (-0.43, -0.39)))
        d = two_parameter_diagram(plane, label=False)
    assert len(d.curves_of("grazing")) == 1
    # the fold-grazing point is found on the fold curve and on the grazing curve
    assert len(d.points_of("cusp")) == 1 and len(d.points_of("fold-grazing")) == 2


@pytest.mark.parametrize("g", [-1.045, -1.03, -1.015])
def test_fold_curve_matches_the_hysteresis_loop_of_simulated_sweeps(bautin, g):
    """Down from the oscillation it holds until the fold; up from steady sliding, until the Hopf point."""
    (f,) = bautin.curves_of("fold")
    (h,) = bautin.curves_of("hopf")
    nu_f = float(np.interp(g, f.y[np.argsort(f.y)], f.x[np.argsort(f.y)]))
    left = h.x < 0.8
    nu_h = float(np.interp(g, h.y[left][np.argsort(h.y[left])], h.x[left][np.argsort(h.y[left])]))
    assert nu_f < nu_h
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        law = ExpressionLaw(BAUTIN_LAW, g=g)
    d = 1e-4
    nus = np.arange(nu_f - 20 * d, nu_h + 20 * d, d)
    up = _sweep(law, nus, 1e-5)
    down = _sweep(law, nus[::-1], 0.5)[::-1]
    loop = nus[down & ~up]
    assert loop.size, "no hysteresis between the sweeps"
    # below the fold the orbit drifts off slowly (a ghost of the two cycles): within 3 steps of it
    assert np.all(down[nus > nu_f + d]) and not np.any(down[nus < nu_f - 3 * d])
    assert loop.min() == pytest.approx(nu_f, abs=3 * d)  # the fold of cycles
    assert loop.max() == pytest.approx(nu_h, abs=3 * d)  # the subcritical Hopf point


@pytest.mark.parametrize("which", ["weakening", "bautin"])
def test_brute_force_agrees_away_from_the_curves(which, request):
    d = request.getfixturevalue(which)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the Bautin law's plane: f < 0 far above any orbit's velocity
        chk = check_diagram(d, (30, 30), progress=False)
    assert chk.scored > 500
    assert chk.agree >= 0.99, chk.report()
    assert "agree with the diagram" in chk.report()


def test_regions_are_named_by_their_attractors(weakening):
    regimes = set(weakening.region_regime)
    assert {"stick-slip", "steady-sliding"} <= regimes
    assert "stick-slip + steady-sliding" in weakening.region_names  # bistable between Hopf and grazing
    assert weakening.regime_at(0.1, 10.0) == "stick-slip"
    assert weakening.regime_at(1.8, 10.0) == "steady-sliding"


def test_codes_round_trip():
    for names in ("stick-slip", "stick-slip + steady-sliding", "pure-slip + pure-slip + steady-sliding"):
        assert decode(encode(names)) == names


def test_netcdf_and_json(weakening, tmp_path):
    import xarray as xr

    ds = diagram_dataset(weakening)
    ds.to_netcdf(tmp_path / "d.nc")
    back = xr.load_dataset(tmp_path / "d.nc")
    kinds = [str(k) for k in back["curve_kind"].values]
    assert sorted(kinds) == ["grazing", "hopf"]
    hopf = back["curve_id"].values == kinds.index("hopf")
    c, nu = back["curve_y"].values[hopf], back["curve_x"].values[hopf]
    assert np.max(np.abs(nu - (np.sqrt(c / 0.5) - 1) / c)) < 1e-10
    assert back["curve_x"].attrs["units"] == "1" and back.attrs["x_name"] == "nu"
    d = json.loads(weakening.to_json())
    assert {c["kind"] for c in d["curves"]} == {"hopf", "grazing"}


def test_physical_plane_hopf_is_where_dF_dV_vanishes():
    """In (V, k) the Hopf set of the paper's F2 is the line F'(V) = 0: V = (sqrt(a/b) - 1)/a."""
    from stickslip.laws import PhysicalWeakeningLaw
    from stickslip.models.parameters import PhysicalParameters

    law = PhysicalWeakeningLaw(mu_s=0.35, a="30 s/m", b="20 s/m")
    params = PhysicalParameters(mass="30.7 g", stiffness="168 N/m", load="0.301 N", v0="1 mm/s", law=law)
    pl = Plane.physical(params, ("v0", (1e3, 3e4)), ("stiffness", (50.0, 500.0)))
    d = two_parameter_diagram(pl, label=False, raster=20)
    (h,) = d.curves_of("hopf")
    v_h = (math.sqrt(30 / 20) - 1) / 30 * 1e6  # um/s
    assert np.max(np.abs(h.x / v_h - 1)) < 1e-9
    assert h.y.min() == pytest.approx(50.0) and h.y.max() == pytest.approx(500.0)


def test_bad_planes_say_which_argument():
    law = WeakeningLaw(c=5, p=0.5)
    with pytest.raises(ValueError, match="axis 'q'"):
        Plane.dimensionless(law, ("nu", (0.1, 1)), ("q", (1, 2)))
    with pytest.raises(ValueError, match="c=\\(3, 2\\)"):
        Plane.dimensionless(law, ("nu", (0.1, 1)), ("c", (3, 2)))
    with pytest.raises(ValueError, match="give nu="):
        Plane.dimensionless(law, ("c", (1, 2)), ("p", (0.1, 0.2)))


def test_command_writes_the_diagram_and_refuses_a_bad_axis(tmp_path):
    out = tmp_path / "d"
    r = subprocess.run(
        [
            sys.executable,
            "-m",
            "stickslip",
            "diagram",
            "--x",
            "nu=0.05..2",
            "--y",
            "c=2..20",
            "--p",
            "0.5",
            "--raster",
            "60",
            "--out",
            str(out),
        ],
        capture_output=True,
        text=True,
        check=False,
    )
    assert r.returncode == 0, r.stderr
    assert "hopf     curve" in r.stdout and "region" in r.stdout
    assert {"diagram.nc", "diagram.json", "diagram.png", "diagram.svg"} <= {p.name for p in out.iterdir()}
    bad = subprocess.run(
        [sys.executable, "-m", "stickslip", "diagram", "--x", "nu=2", "--y", "c=2..20", "--p", "0.5"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert bad.returncode == 2
    assert bad.stderr == "Error: --x='nu=2': expected NAME=A..B, e.g. 'nu=0.05..2' or 'v0=10..1e4'\n"
    from click.testing import CliRunner

    from stickslip.cli import main

    for args, message in (
        (["--y", "zeta=2..20"], "--y='zeta=2..20': 'zeta' is no parameter of the set-up"),
        (["--x", "nu=2..0.1", "--y", "c=2..20"], "--x='nu=2..0.1': expected A < B"),
    ):
        res = CliRunner().invoke(main, ["diagram", "--p", "0.5", *args])
        assert res.exit_code == 2 and res.output.startswith("Error: " + message), res.output
        assert res.output.count("\n") == 1


@pytest.mark.slow
def test_an_expressions_name_on_an_axis_needs_no_param():
    from click.testing import CliRunner

    from stickslip.cli import main

    law = ["--law", "expr", "--f", "1 + w + g*w**3 + 0.25*w**5"]
    res = CliRunner().invoke(main, ["diagram", *law, "--y", "g=-1.3..-0.7", "--raster", "20"])
    assert res.exit_code == 0 and "bautin" in res.output, res.output


@pytest.mark.skipif(not COLAS.is_dir(), reason="the Colas et al. 2019 records are not beside the repository")
def test_the_real_records_plane(tmp_path):
    """Colas et al., Phys. Rev. E (2019): three records at k = 168 N/m, V = 42, 1100, 4300 um/s."""
    r = subprocess.run(
        [
            sys.executable,
            "-m",
            "stickslip",
            "diagram",
            "--records",
            str(COLAS),
            "--name-pattern",
            "k{stiffness}Nm_v{v0}",
            "--mass",
            "30.7 g",
            "--load",
            "weight",
            "--model",
            "mu_s=0.35, a=30 s/m, b=20 s/m",
            "--raster",
            "60",
            "--json",
        ],
        capture_output=True,
        text=True,
        check=False,
    )
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert sorted(m["v0_um_per_s"] for m in d["measured"]) == pytest.approx([42.0, 1100.0, 4300.0])
    assert all(m["stiffness_N_per_m"] > 0 for m in d["measured"])
    hopf = [c for c in d["curves"] if c["kind"] == "hopf"]
    assert hopf and np.allclose(hopf[0]["x"], (math.sqrt(1.5) - 1) / 30 * 1e6, rtol=1e-9)


def test_slip_reversal_curve_of_the_papers_f1():
    """F1 (p = 0): stick-slip, and above a curve an oscillation that slips backward and never
    sticks. On the curve the backward slip ends at breakaway: the engine on either side of three
    of its points (1e-6 of nu away) finds stick-slip below and slip reversal above."""
    from stickslip.bifurcation.probes import _engine

    pl = Plane.dimensionless(WeakeningLaw(c=5, p=0.0), ("nu", (0.05, 5.0)), ("c", (1.0, 20.0)))
    d = two_parameter_diagram(pl, raster=60)
    (r,) = d.curves_of("reversal")
    assert r.ends == ("edge", "edge")
    assert sorted(d.region_regime) == ["slip-reversal", "stick-slip"]
    for i in (1, len(r.x) // 2, len(r.x) - 2):
        law = WeakeningLaw(c=float(r.y[i]), p=0.0)
        rows = _engine(law, np.array([r.x[i] * (1 - 1e-6), r.x[i] * (1 + 1e-6)]))
        assert [str(x) for x in rows.regimes()] == ["stick-slip", "pure-slip"]
        assert rows.n_backward[1] > 0  # pure slip with backward slip: slip reversal
    chk = check_diagram(d, (20, 20), progress=False)
    assert chk.agree >= 0.99, chk.report()


def test_a_region_whose_cells_disagree_is_left_unscored(weakening):
    import dataclasses

    names = ["undetermined: stick-slip | steady-sliding"] * len(weakening.region_names)
    d = dataclasses.replace(weakening, region_names=names)
    chk = check_diagram(d, (10, 10), progress=False)
    assert chk.scored == 0 and math.isnan(chk.agree)
    assert "lie in regions the diagram leaves undetermined" in chk.report()


def test_stick_slip_onset_is_found_by_the_engine_where_no_hopf_branch_leads(weakening):
    """A plane that holds the grazing curve but not the Hopf curve (nu > 0.55 > nu_H for c in 2..3):
    the engine's onset on the seed lines seeds it, and it is the curve the full plane traces."""
    pl = Plane.dimensionless(WeakeningLaw(c=5, p=0.5), ("nu", (0.55, 2.0)), ("c", (2.0, 3.0)))
    d = two_parameter_diagram(pl, raster=40, label=False)
    assert d.curves_of("hopf") == []
    (g,) = d.curves_of("grazing")
    (full,) = weakening.curves_of("grazing")
    order = np.argsort(full.y)
    near = np.interp(g.y, full.y[order], full.x[order])
    assert np.max(np.abs(g.x - near)) < 2e-3  # the full curve's chords: its points are exact
    on = [float(np.interp(c, g.y, g.x)) for c in full.y[(full.y > 2.05) & (full.y < 2.95)]]
    assert np.allclose(on, full.x[(full.y > 2.05) & (full.y < 2.95)], atol=2e-3)


def test_grazing_curve_is_the_engines_stick_slip_onset():
    """At three points of the grazing curve, the one-parameter onset (bisected on the engine to 1e-9)."""
    from stickslip.bifurcation.probes import stick_slip_branch

    pl = Plane.dimensionless(WeakeningLaw(c=5, p=0.5), ("nu", (0.55, 2.0)), ("c", (2.0, 3.0)))
    (g,) = two_parameter_diagram(pl, raster=20, label=False).curves_of("grazing")
    for i in (1, len(g.x) // 2, len(g.x) - 2):
        _, pts = stick_slip_branch(WeakeningLaw(c=float(g.y[i]), p=0.5), np.linspace(0.55, 0.8, 26))
        (onset,) = [p.nu for p in pts if p.kind == "stick-slip-onset"]
        assert onset == pytest.approx(g.x[i], rel=1e-8)
