"""One line that names the cause: a noise-free record fits, a pole is a pole, a table names itself.

* ``ratestate-fit`` weighs a run it cannot simulate above every run it can, so a
  noise-free record (weighted by the noise floor) fits instead of ending at a runaway
  with advice about units and inertia.
* A formula law whose pole lies beyond the checked range ``w <= 100`` stops ``cycle``
  and ``simulate`` with the documented "divides by zero at a velocity the motion
  reached", also where the step size collapses short of the pole.
* A table of absurd coefficients, or of more rows than the engine compiles, is refused
  in one line naming the file and the row (not the mass, stiffness, load and v0).
"""

from __future__ import annotations

import re
import time
import warnings

import numpy as np
import pytest
from click.testing import CliRunner

import stickslip as ss
from stickslip.cli import main
from stickslip.io.errors import DataError
from stickslip.io.lab import read_lab_record
from stickslip.laws import TabulatedLaw
from stickslip.laws.table import MAX_ROWS, MU_RANGE
from stickslip.ratestate.fitting import fit_rate_state
from stickslip.ratestate.model import RateStateParameters
from stickslip.ratestate.protocols import velocity_steps

# --------------------------------------------------------------------------- ratestate-fit

#: a slider 1.2 times its critical stiffness ((b - a)/Dc = 0.5 1/mm): a fit's restart from
#: Dc / 3 runs away, as trial steps near the truth can
SLIDER = {"a": 0.01, "b": 0.015, "dc": "10 um", "v_ref": "1 um/s", "mu0": 0.6}


def _resampled_record(path, *, noise: float, factor: int = 10) -> None:
    """Write the model's own velocity-step record, resampled ``factor`` times denser (linear)."""
    p = RateStateParameters(**SLIDER, stiffness_per_load="0.6 1/mm")
    ds = velocity_steps(p, ["1 um/s", "10 um/s", "1 um/s"], n_points=400)
    t = ds.time.values
    tt = np.linspace(t[0], t[-1], (t.size - 1) * factor + 1)
    mu = np.interp(tt, t, ds.friction.values)
    v = ds.load_point_velocity.values[np.clip(np.searchsorted(t, tt, side="right") - 1, 0, t.size - 1)]
    mu = mu + np.random.default_rng(7).normal(0.0, noise, mu.size) if noise else mu
    head = "# mu0 = 0.6\n# v_ref = 1 um/s\n# stiffness_per_load = 0.6 1/mm\n# law = aging\n"
    rows = "".join(
        f"{float(a)!r},{float(b) * 1e6!r},{float(c)!r}\n" for a, b, c in zip(tt, v, mu, strict=True)
    )
    path.write_text(head + "time [s],load-point velocity [um/s],friction [1]\n" + rows)


@pytest.mark.parametrize("noise", [0.0, 1e-4])
def test_a_noise_free_densely_resampled_record_fits(tmp_path, noise: float) -> None:
    """Weighted by the noise floor (6e-11), the resampled record's misfit is more than 1e3 noise
    units a sample: a failed run must weigh more than any misfit, or the fit keeps the runaway of
    its restart from Dc / 3 and says 'cannot be simulated ... check the units'. The noisy record
    (1e-4) fits either way."""
    path = tmp_path / "record.csv"
    _resampled_record(path, noise=noise)
    started = time.perf_counter()
    fit = fit_rate_state(read_lab_record(path, need_friction=True), max_seconds=60)
    assert time.perf_counter() - started < 30
    truth = {"a": 0.01, "b": 0.015, "dc": 1e-5}
    for name, true in truth.items():
        assert fit.values[name] == pytest.approx(true, rel=0.05 if noise else 1e-3), name
    if not noise:  # the resampling's own error is the misfit: it says so, not units or inertia
        assert any("noise floor" in w for w in fit.warnings)


# --------------------------------------------------------------------------- poles

#: a pole at w = 150.37, beyond the checked range w <= 100: friction falls to minus infinity on
#: both sides, and a stick-slip cycle at nu = 120 reaches it
POLE = "1/(1+0.05*w) - 0.001/(w - P)**2 + 0.001/P**2"
PROMISED = "the friction law divides by zero at a velocity the motion reached"


@pytest.mark.slow
def test_a_pole_the_motion_reaches_is_named_by_cycle_simulate_and_the_command_line() -> None:
    """The step collapses 1.4e-6 short of the pole (step-size-too-small, or too-many-steps): the law
    there is -5e8 against -0.04 at 0.1 % to either side, a pole, said in the documented words."""
    params = ss.DimensionlessParameters(nu=120.0, law=ss.ExpressionLaw(POLE, P=150.37))
    started = time.perf_counter()
    with pytest.raises(ValueError, match=PROMISED + r": f = -[0-9.]+e\+0[0-9] at w = 150\.37, where the run"):
        ss.cycle(params)
    with pytest.raises(ValueError, match=PROMISED):
        ss.simulate(params)
    res = CliRunner().invoke(
        main, ["cycle", "--law", "expr", "--f", POLE, "--param", "P=150.37", "--nu", "120"]
    )
    assert res.exit_code != 0
    last = res.output.strip().splitlines()[-1]
    assert PROMISED in last and "very stiff" not in res.output and "step-size" not in res.output, res.output
    assert time.perf_counter() - started < 90  # one compilation of the law (7 s cold here), then ms


def test_a_stiff_or_runaway_law_is_not_called_a_pole() -> None:
    """Only a blow-up at the stop is a pole: a steep finite law changes by a few times over 0.1 %."""
    from stickslip.dynamics.cycle import pole_reached

    law = ss.ExpressionLaw(POLE, P=150.37)
    assert pole_reached(law, 150.36999858) == pytest.approx(-4.96e8, rel=0.01)
    assert pole_reached(law, 120.0) is None
    assert pole_reached(ss.WeakeningLaw(c=1e6, p=1.0), 0.3) is None  # stiff at the onset, finite
    assert pole_reached(ss.CubicLaw(alpha=0.5, gamma=1.0), 1e6) is None  # a runaway's large w
    assert pole_reached(ss.WeakeningLaw(c=3.8), float("nan")) is None


# --------------------------------------------------------------------------- tables


def _table(path, rows: list[tuple[float, float]]) -> str:
    path.write_text("velocity [um/s],friction coefficient [1]\n" + "".join(f"{v!r},{m!r}\n" for v, m in rows))
    return str(path)


@pytest.mark.parametrize(
    ("values", "line", "shown"),
    [
        ([1e12, 1e12, 0.9e12, 0.8e12, 0.7e12], 2, "1e+12"),  # nu = 1.9e-16: 'check the mass'
        ([1e-300, 0.9e-300, 0.8e-300, 0.7e-300, 0.6e-300], 2, "1e-300"),  # beta = 1.9e301
        ([0.5, 0.45, 0.44, 0.4, 1e9], 6, "1e+09"),  # a jump: 'the law is very stiff'
    ],
)
def test_a_table_of_absurd_coefficients_names_the_file_and_the_row(tmp_path, values, line, shown) -> None:
    path = _table(tmp_path / "mu_v.csv", list(zip([0.0, 1.0, 10.0, 100.0, 1000.0], values, strict=True)))
    with pytest.raises(
        DataError, match=rf"mu_v\.csv: line {line}: friction coefficient {re.escape(shown)} is outside"
    ):
        TabulatedLaw.from_csv(path)
    args = ["cycle", "--law", "table", "--table", path, "--v0", "10 um/s", "--mass", "231 g"]
    res = CliRunner().invoke(main, [*args, "--stiffness", "62 N/m", "--load", "196 mN"])
    assert res.exit_code != 0
    assert res.output.count("Error:") == 1 and f"line {line}" in res.output, res.output
    assert "mass=" not in res.output and "check their units" not in res.output
    with pytest.raises(ValueError, match=r"table: row 1: friction coefficient 2e\+06 is outside"):
        TabulatedLaw(ss.Q_([0.0, 1.0, 2.0, 3.0, 4.0], "um/s"), [2e6, 0.4, 0.4, 0.4, 0.4])
    with pytest.raises(ValueError, match=r"table: static=.*: a static coefficient outside 1e-06\.\.1000"):
        TabulatedLaw(ss.Q_([0.0, 1.0, 2.0, 3.0, 4.0], "um/s"), [0.5, 0.4, 0.4, 0.4, 0.4], static=1e12)
    assert MU_RANGE == (1e-6, 1e3)


def test_a_table_of_too_many_rows_is_refused_in_one_line_naming_the_file(tmp_path) -> None:
    """Above 25 000 rows (1 MB of pieces) numba neither caches the engine nor compiles it lean: 15
    warnings and 1.3 GB at 2e5 rows, 5.4 GB at 1e6. 2e5 rows are refused at once."""
    n = 200_000
    v = np.concatenate([[0.0], np.geomspace(1e-2, 1e4, n - 1)])
    mu = 0.5 - 0.05 * np.log1p(v) / np.log1p(1e4)
    path = _table(tmp_path / "big.csv", list(zip(v.tolist(), mu.tolist(), strict=True)))
    args = ["cycle", "--law", "table", "--table", path, "--v0", "10 um/s", "--mass", "231 g"]
    started = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        res = CliRunner().invoke(main, [*args, "--stiffness", "62 N/m", "--load", "196 mN"])
    assert time.perf_counter() - started < 10
    assert res.exit_code != 0
    lines = res.output.strip().splitlines()
    assert len([x for x in lines if "Error" in x or "warning" in x]) == 1, res.output
    assert f"big.csv: {n} rows, more than {MAX_ROWS}" in lines[-1] and "one row in 9" in lines[-1]
    # the largest table allowed holds its pieces in at most numba's 1e6 bytes (40 bytes a piece)
    w = np.concatenate([[0.0], np.geomspace(1e-2, 1e4, MAX_ROWS - 1)])
    law = TabulatedLaw(ss.Q_(w, "um/s"), 0.5 - 0.05 * np.log1p(w) / np.log1p(1e4))
    assert law.spec.pp.c.shape[1] * 40 <= 1_000_000
