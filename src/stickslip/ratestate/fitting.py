"""Fitting rate-and-state parameters to a laboratory record (velocity steps, slide-hold-slide).

The model is the quasi-static spring-slider of :mod:`stickslip.ratestate.protocols`
driven by the record's own load-point history, evaluated at the record's sample
times from the integrator's dense output. Fitted: ``a``, ``b`` and ``Dc`` (and a
second ``b``, ``Dc`` with two state variables; ``k/W`` with ``fit_stiffness``),
by nonlinear least squares in the logarithms of the parameters (they stay
positive). As a friction lab does it:

* **Detrending.** Friction records drift with slip (gouge compaction, wear). With
  ``detrend="linear"`` (default) a friction offset and a slope in load-point
  displacement are fitted together with the rate-and-state parameters (solved
  exactly at each evaluation, so they cost nothing and cannot be forgotten);
  ``"offset"`` fits only the offset (the level ``mu0`` is then free), ``"none"``
  neither (``mu0`` as given).
* **Window.** ``window=(t0, t1)`` fits only the samples in that time range (a lab
  cuts the run-in and any part where the machine misbehaved); the simulation
  starts at the first sample in steady sliding at the first velocity.
* **Noise and errors.** The noise of the record is estimated from its second
  differences (robust to the signal); errors are the one-sigma errors of the
  linearised fit, scaled by the reduced chi-squared when it exceeds one; the
  correlation matrix is reported, and identifiability warnings name the parameters
  the record cannot separate.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt
from scipy.optimize import least_squares

from ..core.noise import noise_level
from ..io.errors import DataError
from ..io.lab import LabRecord
from ..units import Q_, check_number, parse_quantity
from .model import STATE_LAWS, RateStateParameters
from .protocols import RateStateStopped, simulate_rate_state

__all__ = ["DETRENDS", "RateStateFit", "fit_rate_state"]

FloatArray = npt.NDArray[np.float64]
DETRENDS = ("linear", "offset", "none")
UNITS = {"a": "1", "b": "1", "dc": "m", "b_2": "1", "dc_2": "m", "stiffness_per_load": "1/m"}


@dataclass(frozen=True)
class RateStateFit:
    """Rate-and-state parameters fitted to a record.

    Attributes
    ----------
    values, errors : dict
        Fitted values and one-sigma errors (SI: ``dc`` in m, ``stiffness_per_load`` in 1/m).
    correlation : ndarray
        Correlation matrix in the order of ``names``.
    names : tuple of str
        Fitted parameters.
    warnings : tuple of str
        Identifiability and quality warnings.
    reduced_chi2 : float
        Sum of squared residuals over the noise variance and the degrees of freedom.
    noise : float
        Standard deviation of the record's noise (friction), estimated from the data.
    samples : int
        Samples in the fitting window.
    offset, trend : float
        Fitted friction offset and slope (1/m of load-point displacement), 0 when not fitted.
    parameters : RateStateParameters
        The fitted slider.
    time, friction, model : ndarray
        The window's times (s, from the record's start), measured and fitted friction.

    """

    values: dict[str, float]
    errors: dict[str, float]
    correlation: FloatArray
    names: tuple[str, ...]
    warnings: tuple[str, ...]
    reduced_chi2: float
    noise: float
    samples: int
    offset: float
    trend: float
    parameters: RateStateParameters
    time: FloatArray
    friction: FloatArray
    model: FloatArray

    @property
    def residuals(self) -> FloatArray:
        """Measured minus fitted friction in the window."""
        return self.friction - self.model

    def as_dict(self) -> dict[str, Any]:
        """Return a JSON-ready dictionary in the shape of ``stickslip fit --json``."""

        def num(x: float) -> float | None:
            return None if not math.isfinite(x) else float(x)

        return {
            "parameters": {
                n: {"value": self.values[n], "error": num(self.errors[n]), "unit": UNITS[n]}
                for n in self.names
            },
            "correlation": {
                a: {b: num(float(self.correlation[i, j])) for j, b in enumerate(self.names)}
                for i, a in enumerate(self.names)
            },
            "detrend": {"offset": self.offset, "trend": {"value": self.trend, "unit": "1/m"}},
            "warnings": list(self.warnings),
            "reduced_chi2": self.reduced_chi2,
            "method": "waveform",
            "noise": {"value": self.noise, "unit": "1"},
            "samples": self.samples,
            "fit_on": f"friction waveform ({self.samples} samples), quasi-static rate-and-state slider "
            f"({', '.join(self.parameters.laws)} law) driven by the record's load-point history",
        }


def _option(value: Any, meta: dict[str, str], key: str, name: str) -> Any:
    if value is not None:
        return value
    if meta.get(key, "").strip():  # an empty '# mu0 =' line is no value, as a missing one
        return meta[key]
    raise DataError(f"{name} is not given: pass it as an option or as '# {key} = ...' in the record's header")


#: a change of the load-point velocity counts as a step beyond this in ln(v2/v1) (5 %), and beyond
#: ten times the sample-to-sample noise of its plateaus
STEP_MIN_LOG = 0.05


def velocity_steps(v: FloatArray) -> npt.NDArray[np.intp]:
    """Return the samples at which the load-point velocity steps (into or out of a hold too).

    A logged velocity is noisy (a servo's 1e-4), and one computed from a displacement
    column differs in its last bits from row to row: ``np.diff(v) != 0`` would call every
    row a step (and fit a = b = 0.032, Dc = 3e-10 m with tiny error bars to a record of
    a = 0.008, b = 0.012, Dc = 20 um). A step is a change of ``ln v`` beyond
    :data:`STEP_MIN_LOG` and beyond ten times the noise, the median change between
    neighbours (steps are rare among the rows; 1.4826 turns it into a standard deviation).
    """
    moving = v > 0
    with np.errstate(divide="ignore", invalid="ignore"):
        change = np.abs(np.diff(np.log(np.where(moving, v, np.nan))))
    known = change[np.isfinite(change)]
    noise = 1.4826 * float(np.median(known)) if known.size else 0.0
    threshold = max(STEP_MIN_LOG, 10.0 * noise)
    hold = moving[1:] != moving[:-1]
    return np.flatnonzero(hold | (np.nan_to_num(change, nan=0.0) > threshold)) + 1


def _initial(
    t: FloatArray, mu: FloatArray, x: FloatArray, v: FloatArray, n_states: int, kw: float
) -> dict[str, float]:
    """Return starting values from the steps: direct jump, steady-state change and decay length."""
    jumps = velocity_steps(v)
    a_est, ab_est, dc_est = [], [], []
    for k, i in enumerate(jumps):
        begin = jumps[k - 1] if k else 0
        stop = jumps[k + 1] if k + 1 < len(jumps) else len(v)
        v1, v2 = float(np.median(v[begin:i])), float(np.median(v[i:stop]))  # the plateaus, not one sample
        if v1 <= 0 or v2 <= 0:
            continue
        r = math.log(v2 / v1)
        end = jumps[k + 1] if k + 1 < len(jumps) else len(v)
        seg = slice(i, end)
        before = mu[max(0, i - 5) : i].mean()
        after = mu[max(i, end - max(3, (end - i) // 10)) : end].mean()
        dev = (mu[seg] - before) * np.sign(r)
        j = int(np.argmax(dev))
        a_est.append(max(dev[j] / abs(r), 1e-4))
        ab_est.append((after - before) / r)
        # decay: where friction has come within 1/e of its new level after the peak
        level = (mu[seg] - after) * np.sign(r)
        below = np.flatnonzero(level[j:] <= level[j] / math.e)
        if below.size:
            dc_est.append(max(x[i + j + below[0]] - x[i + j], 1e-9))
    if a_est:
        a0 = float(np.median(a_est)) * 1.2
        b0 = max(a0 - float(np.median(ab_est)), 0.2 * a0)
        dc0 = float(np.median(dc_est)) if dc_est else float(np.ptp(x)) / 20
    if not a_est or not (1e-5 < a0 < 0.5 and float(np.ptp(x)) * 1e-6 < dc0 < float(np.ptp(x))):
        # slide-hold-slide only, or estimates no laboratory gives (a step read off noise):
        # typical laboratory values, the fit refines them
        a0, b0, dc0 = 0.01, 0.012, float(np.ptp(x)) / 50
    out = {"a": a0, "b": b0, "dc": dc0}
    if n_states == 2:
        out.update({"b": 0.7 * b0, "dc": 0.5 * dc0, "b_2": 0.3 * b0, "dc_2": 5.0 * dc0})
    if math.isfinite(kw):
        out["stiffness_per_load"] = kw
    return out


#: the fewest samples a fit takes (in the record, or in its window)
MIN_SAMPLES = 10
#: a fit's default bound on wall time (s); the fits of the tests and tutorials take 1 to 40 s
MAX_FIT_SECONDS = 300.0


class _OutOfTime(Exception):
    """The fit's wall-time bound passed (raised through least_squares)."""


def fit_rate_state(
    record: LabRecord,
    *,
    mu0: Any = None,
    v_ref: Any = None,
    stiffness_per_load: Any = None,
    law: str | None = None,
    n_states: int = 1,
    fit_stiffness: bool = False,
    detrend: str = "linear",
    window: tuple[Any, Any] | None = None,
    initial: dict[str, float] | None = None,
    max_seconds: float = MAX_FIT_SECONDS,
) -> RateStateFit:
    """Fit ``a``, ``b``, ``Dc`` (``b_2``, ``Dc_2``; ``k/W``) to a velocity-step or slide-hold-slide record.

    Parameters
    ----------
    record : LabRecord
        Times, load-point history and friction (:func:`stickslip.io.lab.read_lab_record`).
    mu0, v_ref, stiffness_per_load, law : optional
        Reference friction, reference velocity (e.g. ``"1 um/s"``), ``k/W`` (e.g.
        ``"1e-3 1/um"``; a starting value with ``fit_stiffness``) and the evolution law;
        taken from the record's header (``# mu0 = 0.6``, ...) when not given.
    n_states : int, optional
        1 or 2 state variables.
    fit_stiffness : bool, optional
        Fit ``k/W`` too.
    detrend : str, optional
        ``"linear"`` (offset and slope in load-point displacement fitted), ``"offset"`` or ``"none"``.
    window : (time, time), optional
        Fit only the samples in this range (times on the record's clock).
    initial : dict, optional
        Starting values (SI) of some or all fitted parameters (``a``, ``b``,
        ``dc``; ``b_2``, ``dc_2``; ``stiffness_per_load`` with
        ``fit_stiffness``), instead of the estimates read from the steps.
    max_seconds : float, optional
        Give up, with an error that says what to check, after this many seconds of
        wall time (default :data:`MAX_FIT_SECONDS`): a record whose units are off
        (a velocity in um/s under a header in mm/s) may take hours to fail.

    Returns
    -------
    RateStateFit

    Raises
    ------
    DataError
        Missing friction or parameters, a window without samples, a record without steps.

    """
    if record.friction is None:
        raise DataError(f"{record.name}: the record has no friction column to fit")
    meta = record.metadata
    mu0_raw = _option(mu0, meta, "mu0", "mu0")
    try:
        mu0_v = float(mu0_raw)
    except (TypeError, ValueError):
        raise ValueError(f"mu0={mu0_raw!r}: expected a reference friction coefficient (a number)") from None
    mu0_v = check_number(mu0_v, "mu0", what="a positive reference friction coefficient")
    vr = parse_quantity(_option(v_ref, meta, "v_ref", "v_ref"), "v_ref", "[length] / [time]", "1 um/s")
    kw_q = parse_quantity(
        _option(stiffness_per_load, meta, "stiffness_per_load", "stiffness_per_load"),
        "stiffness_per_load",
        "1 / [length]",
        "1e-3 1/um",
    )
    law_v = str(law if law is not None else meta.get("law") or "aging")
    if law_v not in ("aging", "slip", "prz"):
        whence = "" if law is not None else " (the record's '# law' line; --law or law= fits another anyway)"
        raise DataError(
            f"law={law_v!r}{whence}: the fit supports 'aging', 'slip' or 'prz' (of {', '.join(STATE_LAWS)})"
        )
    if n_states not in (1, 2):
        raise DataError(f"n_states={n_states!r}: expected 1 or 2")
    max_seconds = check_number(max_seconds, "max_seconds", what="a positive time bound in seconds")
    deadline = time.monotonic() + max_seconds
    if detrend not in DETRENDS:
        raise DataError(f"detrend={detrend!r}: expected one of {', '.join(DETRENDS)}")
    t_all = record.time - record.time[0]
    sel = np.ones(t_all.size, dtype=bool)
    if window is not None:
        try:
            if isinstance(window, str):
                raise ValueError
            w0, w1 = window  # a pair: a tuple, a list, an array, a pint array
        except (TypeError, ValueError):
            expected = "expected (start, end) times, e.g. ('5 s', '60 s')"
            raise ValueError(f"window={window!r}: {expected}") from None
        lo, hi = (
            float(parse_quantity(w, "window", "[time]", "10 s", allow_negative=True).to("s").magnitude)
            - record.time[0]
            for w in (w0, w1)
        )
        if not hi > lo:
            raise ValueError(f"window={window!r}: its end is not after its start")
        sel = (t_all >= lo) & (t_all <= hi)
        if sel.sum() < MIN_SAMPLES:
            raise DataError(f"window={window!r}: {int(sel.sum())} samples in it; a fit needs many more")
    elif sel.sum() < MIN_SAMPLES:
        raise DataError(
            f"{record.name}: {int(sel.sum())} samples; a fit of a, b, Dc needs many more (at least "
            f"{MIN_SAMPLES}, and a velocity step or a hold among them)"
        )
    i0 = int(np.argmax(sel))
    t = t_all[sel] - t_all[i0]
    mu = record.friction[sel]
    x = record.displacement[sel] - record.displacement[i0]
    v = record.velocity[sel]
    if v[0] <= 0:
        moving = np.flatnonzero(v > 0)
        where = "the fitting window" if window is not None else record.name
        slide = f"; sliding begins at t = {t_all[sel][moving[0]] + record.time[0]:g} s" if moving.size else ""
        raise DataError(
            f"{where} starts in a hold (load-point velocity {v[0] * 1e6:g} um/s{slide}): the fit "
            "starts from steady sliding at the first sample's velocity, which a hold does not "
            "give; start the window while sliding (--window / window=)"
        )
    if np.unique(v[:-1]).size == 1:  # the last sample's velocity holds after the record
        where = "in the window" if window is not None else "in the record"
        raise DataError(
            f"{record.name}: the load-point velocity never changes {where} ({v[0] * 1e6:g} um/s "
            "throughout): steady sliding tells only a - b; a velocity step or a hold is what "
            "constrains a, b and Dc"
        )
    sub = LabRecord(record.name, t, v, x, mu, dict(meta))
    hist = sub.history()
    kw0 = float(kw_q.to("1/m").magnitude)
    names = (
        ["a", "b", "dc"]
        + (["b_2", "dc_2"] if n_states == 2 else [])
        + (["stiffness_per_load"] if fit_stiffness else [])
    )
    # the estimates read from the steps, with the user's starting values over them
    start = _initial(t, mu, x, v, n_states, kw0)
    for key, value in (initial or {}).items():
        if key not in names:
            raise ValueError(f"initial: {key!r} is not a fitted parameter here; expected one of {names}")
        start[key] = check_number(value, f"initial[{key!r}]", what="a positive starting value (SI)")
    x0 = np.log([start[n] for n in names])
    sigma = noise_level(mu)
    read = math.isfinite(sigma) and sigma > 0  # the noise was read off the record
    if not read:
        sigma = 1e-6
    # a record without noise (the package's own, written to 17 digits) has residuals at the
    # model's integration accuracy: weighted by a noise of 7.5e-13 they read as a misfit
    # (reduced chi-square 7.9 with the parameters exact)
    floor = NOISE_FLOOR * float(np.median(np.abs(mu)))
    floored = sigma < floor
    sigma = max(sigma, floor)

    def build(theta: FloatArray) -> RateStateParameters:
        val = dict(zip(names, np.exp(theta), strict=True))
        kw = val.get("stiffness_per_load", kw0)
        bs = [val["b"]] + ([val["b_2"]] if n_states == 2 else [])
        dcs = [Q_(val["dc"], "m")] + ([Q_(val["dc_2"], "m")] if n_states == 2 else [])
        return RateStateParameters(
            a=val["a"],
            b=bs if n_states == 2 else bs[0],
            dc=dcs if n_states == 2 else dcs[0],
            v_ref=vr,
            mu0=mu0_v,
            stiffness_per_load=Q_(kw, "1/m"),
            state_law=law_v,
        )

    def model(theta: FloatArray) -> FloatArray:
        left = min(30.0, max(deadline - time.monotonic(), 1.0))  # one run within the fit's bound
        ds = simulate_rate_state(build(theta), hist, sample=t, rtol=1e-12, atol=1e-14, max_seconds=left)
        out = ds.friction.values
        if out.size != t.size:
            raise RuntimeError("incomplete")
        return np.asarray(out, dtype=float)

    basis = {
        "linear": np.column_stack([np.ones_like(x), x]),
        "offset": np.ones((x.size, 1)),
        "none": np.zeros((x.size, 0)),
    }[detrend]
    # a run that cannot be simulated (a runaway, the bound on the work) weighs more than any run
    # that can: a friction misfit of FAILED_MISFIT beyond the record's range in every sample, in
    # units of its noise. A fixed number of noise units is not enough: on a noise-free record (the
    # floor, 6e-11) a misfit of 1e-6 is 1.7e4 of them, so a failed trial step would look better
    # than every finite one and the fit would end where the model cannot run
    penalty = np.full(t.size, (FAILED_MISFIT + float(np.ptp(mu))) / sigma)
    # the detrending basis is fixed: factor it once (Q R), for the residuals and the Jacobian
    q_b, r_b = np.linalg.qr(basis)

    def detrended(m: FloatArray) -> tuple[FloatArray, FloatArray]:
        r = mu - m
        if basis.shape[1] == 0:
            return r, np.zeros(0)
        qr_ = q_b.T @ r
        return r - q_b @ qr_, np.linalg.solve(r_b, qr_)

    def cannot(exc: Exception, at: str) -> DataError:
        # the integrator's advice for a run (give the slider a mass) is not the fit's to take
        why = str(exc).split(" Give the slider a mass")[0]
        return DataError(
            f"{record.name}: its load-point history cannot be simulated at {at} ({why}). A record "
            "of stick-slip events or of a slider with inertia is not a quasi-static slider's. Check "
            f"the units of the columns too: the load point moves {x[-1]:.3g} m in {t[-1]:.3g} s, at up "
            f"to {np.max(np.abs(v)):.3g} m/s (a velocity in um/s under a header in m/s is 1e6 times "
            "faster); fit_rate_state(initial=...) takes other starting values"
        )

    first = [True]  # the first call is at the starting values (least_squares begins there)

    def residuals(theta: FloatArray) -> FloatArray:
        if time.monotonic() > deadline:
            raise _OutOfTime
        at_start, first[0] = first[0], False
        try:
            m = model(theta)
        except RateStateStopped as exc:
            # a history the integrator cannot follow at the start (a unit mistake): said at once;
            # a runaway is physics: other parameters may not run away
            if at_start and exc.reason == "max-steps":
                a, b, dc = start["a"], start["b"], start["dc"]
                raise cannot(exc, f"the starting values a = {a:.3g}, b = {b:.3g}, Dc = {dc:.3g} m") from None
            return penalty
        except (RuntimeError, ValueError, OverflowError):
            return penalty
        r, _ = detrended(m)
        return r / sigma

    best = None
    for scale in (1.0, 0.3, 3.0):
        x_try = x0.copy()
        x_try[names.index("dc")] += math.log(scale)
        if n_states == 2:
            x_try[names.index("dc_2")] += math.log(scale)
        try:
            sol = least_squares(residuals, x_try, method="trf", diff_step=1e-6, x_scale=1.0, max_nfev=400)
        except _OutOfTime:
            raise DataError(
                f"{record.name}: the fit did not finish in max_seconds={max_seconds:g} s. Check the units "
                f"of the columns: the load point moves {x[-1]:.3g} m in {t[-1]:.3g} s, at up to "
                f"{np.max(np.abs(v)):.3g} m/s (a velocity in um/s under a header in mm/s is 1000 times "
                "faster); or give a longer bound "
                "(max_seconds=, --max-seconds) or starting values (initial=)"
            ) from None
        if best is None or sol.cost < best.cost:
            best = sol
        if best is not None and 2 * best.cost / max(t.size - len(names), 1) < 2.0:
            break
    assert best is not None
    theta = best.x
    try:
        m_fit = model(theta)
    except (RuntimeError, ValueError, OverflowError) as exc:
        ended = ", ".join(f"{n} = {float(np.exp(val)):.3g}" for n, val in zip(names, theta, strict=True))
        raise cannot(exc, f"the parameters the fit ended at, {ended}") from None
    r, coef = detrended(m_fit)
    dof = max(t.size - len(names) - basis.shape[1], 1)
    chi2 = float(np.sum(r**2) / sigma**2 / dof)
    J = best.jac
    # the nuisance (detrend) parameters are profiled out: project them from the Jacobian
    if basis.shape[1]:
        J = J - q_b @ (q_b.T @ J)
    try:
        cov = np.linalg.inv(J.T @ J) * max(chi2, 1.0)
    except np.linalg.LinAlgError:
        cov = np.full((len(names), len(names)), np.nan)
    err_ln = np.sqrt(np.clip(np.diag(cov), 0, None))
    values = dict(zip(names, (float(v) for v in np.exp(theta)), strict=True))
    errors = {n: values[n] * float(e) for n, e in zip(names, err_ln, strict=True)}
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(err_ln, err_ln)
    warnings = _warnings(names, values, errors, corr, chi2, x, n_states)
    if floored:
        warnings.append(
            f"the record has no noise above the model's own accuracy (estimated {noise_level(mu):.2g}): "
            f"it is weighted by a noise floor of {sigma:.2g}, and the errors are that small"
        )
    elif chi2 < CHI2_LOW and read and dof >= 10:  # (with fewer, chance gives 0.25 often: 22 % at 2)
        # e.g. the README's 1 s record: noise 1.3e-5 read off its curvature, chi-square 3.8e-14,
        # errors 5e6 times too large unless this is said
        warnings.append(
            f"reduced chi-squared {chi2:.2g} < {CHI2_LOW:g}: the record fits far better than the noise "
            f"read off it ({sigma:.2g}, from its second differences, which on a record sampled coarsely "
            "against its own changes read their curvature as noise), so that estimate is too large and "
            f"the errors with it, by about {1.0 / math.sqrt(max(chi2, 1e-300)):.2g} times"
        )
    unmodelled = [f"{k} = {meta[k]}" for k in ("radiation_damping", "mass") if meta.get(k)]
    if unmodelled:  # a run of `stickslip ratestate` with them, written as a record
        warnings.insert(
            0,
            f"the record was made with {' and '.join(unmodelled)} (its header), which the fit does not "
            "model (a quasi-static slider: spring force = friction); a, b and Dc absorb their effect "
            "and are biased ("
            + "; ".join(
                example
                for key, example in (
                    ("radiation_damping", "a step from 1 to 10 um/s with 1000 s/m: a 39 % high, Dc 4 %"),
                    (
                        "mass",
                        "1 kg on 1e4 N/m and 10 N, a step from 1 to 10 um/s: a 0.05 % high; more "
                        "for a heavier slider",
                    ),
                )
                if meta.get(key)
            )
            + ")",
        )
    offset = float(coef[0]) if coef.size else 0.0
    trend = float(coef[1]) if coef.size > 1 else 0.0
    return RateStateFit(
        values=values,
        errors=errors,
        correlation=corr,
        names=tuple(names),
        warnings=tuple(warnings),
        reduced_chi2=chi2,
        noise=sigma,
        samples=int(t.size),
        offset=offset,
        trend=trend,
        parameters=build(theta),
        time=t + t_all[i0] + record.time[0],
        friction=mu,
        model=m_fit + (basis @ coef if coef.size else 0.0),
    )


#: reduced chi-squared below which the noise read off the record (and so the errors) is too large
CHI2_LOW = 0.25
#: the smallest noise a record is weighted by, relative to its friction: the model's accuracy
NOISE_FLOOR = 1e-10
#: the friction misfit (beyond the record's range) a run that cannot be simulated counts as, in
#: every sample: more than any run's, as the quasi-static slider's friction stays within about
#: 14 a (a ln 1e6, the runaway bound) of its steady level, a few tenths at most
FAILED_MISFIT = 1.0


def _warnings(
    names: list[str],
    values: dict[str, float],
    errors: dict[str, float],
    corr: FloatArray,
    chi2: float,
    x: FloatArray,
    n_states: int,
) -> list[str]:
    out = []
    for i, a in enumerate(names):
        for j in range(i + 1, len(names)):
            if abs(corr[i, j]) > 0.95:
                out.append(
                    f"{a} and {names[j]} are strongly correlated (r = {corr[i, j]:+.3f}): the record "
                    "constrains a combination of them better than each"
                )
    for n in names:
        e = errors[n]
        if not math.isfinite(e) or e > 0.5 * values[n]:
            out.append(
                f"{n} is poorly constrained (error {e:.3g} on {values[n]:.3g}): "
                "not identifiable from this record"
            )
    span = float(np.ptp(x))
    for n in ("dc", "dc_2"):
        if n in values and values[n] > 0.25 * span:
            out.append(
                f"{n} = {values[n]:.3g} m is not small against the load-point displacement of the record "
                f"({span:.3g} m): longer steps are needed to resolve it"
            )
    if n_states == 2:
        ratio = max(values["dc"], values["dc_2"]) / min(values["dc"], values["dc_2"])
        if ratio < 3:
            out.append(
                f"the two state variables have similar Dc (ratio {ratio:.2g}): they are not separately "
                "identifiable; fit one state variable"
            )
    if chi2 > 3:
        out.append(
            f"reduced chi-squared {chi2:.3g}: the model does not describe the record within its noise "
            "(another law, another number of state variables, or a trend the detrending does not remove)"
        )
    return out
