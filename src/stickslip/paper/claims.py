"""The paper's claims, each against the model's number: what the reproduction report judges.

:func:`claims` reads the reproduction dataset (``reproduce.nc``) only and returns
one :class:`Claim` per statement of the paper, with the model's number and a
verdict; :func:`grade` puts a verdict in the report's fixed vocabulary
(:data:`GRADES`). The report that lays them out is :mod:`stickslip.paper.report`.
"""

from __future__ import annotations

import itertools
import json
import math
from dataclasses import dataclass, replace

import numpy as np
import xarray as xr

from ..data.criterion import classify
from .compute import measured_trends

__all__ = ["GRADES", "Claim", "claims", "classify_trend", "grade"]


@dataclass(frozen=True)
class Claim:
    """One claim of the paper and what the model says about it.

    ``verdict`` is the reproduction's word on the claim, with its qualifier; :attr:`grade`
    puts it in the report's fixed vocabulary (:data:`GRADES`).
    """

    number: int
    paper: str
    model: str
    verdict: str

    @property
    def grade(self) -> str:
        """The verdict in one of :data:`GRADES`."""
        return grade(self.verdict)


#: the report's verdicts: does the model bear out what the paper says?
GRADES = ("agrees", "agrees in part", "disagrees", "not testable", "inconsistent in the paper")


def grade(verdict: str) -> str:
    """Return the grade (:data:`GRADES`) of a claim's verdict.

    ``supported`` agrees; ``partly supported`` and ``supported for X`` (and not for
    the others) agree in part; ``contradicted`` disagrees; ``not testable`` stays so; an inconsistency (a
    number or a name the paper gives two ways) is the paper's.

    Raises
    ------
    ValueError
        For a verdict of none of these forms: each must have its grade.

    """
    v = verdict.strip().lower()
    if v.startswith(("partly supported", "supported for")):
        return "agrees in part"
    if v.startswith("supported"):
        return "agrees"
    if v.startswith("contradicted"):
        return "disagrees"
    if v.startswith("not testable"):
        return "not testable"
    if "inconsistency" in v:
        return "inconsistent in the paper"
    raise ValueError(f"verdict {verdict!r}: of none of the report's forms ({', '.join(GRADES)})")


def _slope(x: np.ndarray, y: np.ndarray) -> float:
    ok = np.isfinite(y) & (y > 0)
    return float(np.polyfit(np.log(x[ok]), np.log(y[ok]), 1)[0])


def _per_decade(slope: float) -> float:
    return float(10.0**slope)


def claims(ds: xr.Dataset) -> list[Claim]:
    """Return the paper's claims with the model's numbers, from the reproduction dataset."""
    out: list[Claim] = []
    v2 = ds["fig2_v0"].values
    amp2 = ds["fig2_amplitude"].values
    per2 = ds["fig2_period"].values
    slope_b0 = _slope(v2, amp2[0])
    c2 = 160.0 / 42.0  # a / beta and b / beta of Fig. 2 (zv set-up, beta = 42 s/m)
    p2 = float(ds["fig2_b"].values[1]) / 42.0
    w_min2 = (math.sqrt(c2 / p2) - 1.0) / c2  # f'(w) = -c/(1 + c w)**2 + p = 0
    slope_b100 = _slope(v2, amp2[1])
    reg_b100 = sorted(set(ds["fig2_regime"].values[1].tolist()))
    measured = measured_trends()
    zv_slope = float(measured["zv"]["slope"])
    bri_slope = float(measured["bri"]["slope"])

    f = ds["fig1_spring_force"].values
    phase = ds["fig1_phase"].values
    n_stick = int(np.sum((phase[1:] == 0) & (phase[:-1] != 0)))
    out.append(
        Claim(
            0,
            "Fig. 1: with mu0 = 0.46, a = 160 s/m, k = 62 N/m (fitted to the zv record) the computed "
            "spring force agrees well with the measured one.",
            f"Stick-slip sawtooth at {ds.attrs.get('fig1_v0')}: spring force from {1e3 * f.min():.1f} "
            f"to {1e3 * f.max():.1f} mN ({n_stick} stick phases shown). The measured record is not "
            "public, so the agreement cannot be checked here.",
            "not testable from the paper",
        )
    )
    out.append(
        Claim(
            0,
            "The calculated amplitude increases with the driving velocity (F1, b = 0).",
            f"log-log slope of amplitude against v0 over 5-1000 um/s: {slope_b0:+.4f} "
            f"(amplitude x{_per_decade(slope_b0):.3f} per decade; from {1e3 * amp2[0, 0]:.2f} to "
            f"{1e3 * amp2[0, -1]:.2f} mN).",
            "supported" if slope_b0 > 0 else "contradicted",
        )
    )
    out.append(
        Claim(
            0,
            "Also for F2 with p = 2.38 (b = 100 s/m), which keeps the whole velocity range in the "
            "stick-slip regime.",
            f"slope {slope_b100:+.4f} (x{_per_decade(slope_b100):.3f} per decade); regimes found over "
            f"the range: {', '.join(reg_b100)}. Note the amplitude is much smaller than for b = 0 "
            f"({1e3 * amp2[1, 0]:.3f} to {1e3 * amp2[1, -1]:.2f} mN): with c = {c2:.3f}, "
            f"p = {p2:.3f} friction weakens only for w < {w_min2:.3f} (where f' = 0), i.e. slip "
            f"velocities below {1e6 * w_min2 / 42.0:.0f} um/s.",
            "supported" if slope_b100 > 0 and reg_b100 == ["stick-slip"] else "contradicted",
        )
    )
    out.append(
        Claim(
            0,
            "The calculated velocity dependence of the amplitude is entirely different from the zv "
            "experiment, where " + str(measured["zv"]["text"]) + ".",
            f"the stated trend implies a slope of {zv_slope:+.3f}; the model gives {slope_b0:+.4f} "
            f"(b = 0) and {slope_b100:+.4f} (b = 100 s/m): opposite signs.",
            "supported: the model's amplitude rises where the zv record's falls, the difference the "
            "paper states"
            if slope_b0 > 0 > zv_slope
            else "contradicted",
        )
    )
    ps0, ps100 = _slope(v2, per2[0]), _slope(v2, per2[1])
    out.append(
        Claim(
            0,
            "The period decreases with the driving velocity, as in the experiment.",
            f"log-log slope of the period: {ps0:+.3f} (b = 0), {ps100:+.3f} (b = 100 s/m). At small "
            "v0 the stick phase dominates: period ~ mu0 W (1 - s_stop)/(k v0), slope -1.",
            "supported" if ps0 < 0 and ps100 < 0 else "contradicted",
        )
    )
    w = ds["load_W"].values
    la = [_slope(w, ds["load_amplitude"].values[j]) for j in range(ds.sizes["load_v0"])]
    lp = [_slope(w, ds["load_period"].values[j]) for j in range(ds.sizes["load_v0"])]
    vs = [f"{v:g}" for v in ds["load_v0"].values]
    out.append(
        Claim(
            0,
            "The period and the amplitude depend on the normal load in the same direction as in the "
            "experiment.",
            f"least-squares slopes over W from {1e3 * w.min():.3g} to {1e3 * w.max():.3g} mN: "
            "d log(amplitude)/d log(W) = "
            + ", ".join(f"{s:+.2f}" for s in la)
            + "; d log(period)/d log(W) = "
            + ", ".join(f"{s:+.2f}" for s in lp)
            + f" at v0 = {', '.join(vs)} um/s; the curves bend, local slopes of the amplitude "
            + "; ".join(_local_slopes(w, ds["load_amplitude"].values[j]) for j in range(ds.sizes["load_v0"]))
            + " (F1, the zv set-up's mass and stiffness, so beta falls "
            f"as 1/W): {_directions(la, lp)}. The paper does not say in "
            "which direction the measured ones go, so the agreement cannot be checked from its text.",
            "not testable from the paper",
        )
    )
    out.append(_mass_claim(ds))
    v3 = ds["fig3_v0"].values
    s3 = [_slope(v3, ds["fig3_amplitude"].values[i]) for i in range(ds.sizes["fig3_beta"])]
    betas = [float(b) for b in ds["fig3_beta"].values]
    out.append(
        Claim(
            0,
            "Fig. 3 (a = 250 s/m, b = 0): for every beta investigated the amplitude remains constant "
            "or increases with v0.",
            "slopes "
            + ", ".join(f"{s:+.3f} at beta = {b:g} s/m" for b, s in zip(betas, s3, strict=True))
            + ".",
            "supported" if all(s >= -1e-3 for s in s3) else "contradicted",
        )
    )
    out.append(_fig3_order_claim(ds))
    i158 = betas.index(158.0) if 158.0 in betas else 1
    beta2 = float(ds.attrs.get("fig3_beta_for_doubling", math.nan))
    out.append(
        Claim(
            0,
            "beta = 158 s/m reproduces the increase measured by [bri], where "
            + str(measured["bri"]["text"])
            + ".",
            f"at beta = 158 s/m the model's amplitude {_trend(float(s3[i158]))} "
            f"(slope {s3[i158]:+.3f}) against about x2 (slope {bri_slope:+.3f}) measured; "
            f"x2 per decade needs beta = {beta2:.0f} s/m.",
            _against_measured(float(s3[i158]), bri_slope),
        )
    )
    spread = float(ds.attrs.get("scale_check_spread", math.nan))
    out.append(
        Claim(
            0,
            "Fig. 3: the vertical scale of each curve depends on the coefficient mu0 W.",
            f"at fixed beta (the mass adjusted with the load) and a, the amplitude in units of mu0 W is "
            f"the same for W = 50, 196 and 500 mN at 5, 100 and 1000 um/s, to {spread:.1e} (relative): "
            "the curve's shape depends on beta and a only, mu0 W sets its scale.",
            "supported" if spread < 1e-9 else "contradicted",
        )
    )
    zv_verdict = classify_trend(zv_slope)
    bri_verdict = classify_trend(bri_slope)
    model = classify(v2, amp2[0])
    out.append(
        Claim(
            0,
            "By the criterion (amplitude rises with v0 in stick-slip, falls in pure slip), the zv "
            "oscillations are pure slip and the bri ones stick-slip.",
            f"applied to the trends as the paper states them (no data points are public): zv slope "
            f"{zv_slope:+.3f} -> {zv_verdict}; bri slope {bri_slope:+.3f} -> {bri_verdict}. Applied to "
            f"the model's own F1 curve: {model.verdict} ({model.reason}).",
            "supported (as a reading of the criterion)"
            if (zv_verdict, bri_verdict) == ("pure-slip", "stick-slip")
            else "contradicted",
        )
    )
    out.append(_succession_claim(ds))
    out.append(_friction_range_claim(ds))
    out.append(
        Claim(
            0,
            "Parameters: beta = 42 s/m for the zv experiment, with a moving mass 'of order 1000 g'.",
            f"inconsistent: k = 62 N/m, m = 1 kg and mu0 W = 0.0902 N give beta = "
            f"{float(ds.attrs.get('beta_from_1kg', math.nan)):.1f} s/m; beta = 42 s/m needs m = "
            f"{float(ds.attrs.get('mass_for_beta_42', math.nan)):.3f} kg. This reproduction uses the "
            "stated beta = 42 s/m (the paper's p = 2.38 = b/beta confirms that it computed with it).",
            "inconsistency in the paper; beta = 42 s/m used",
        )
    )
    if "kappa" in ds.dims:
        out += _appendix_claims(ds)
    return [replace(c, number=i) for i, c in enumerate(out, start=1)]


def _appendix_claims(ds: xr.Dataset) -> list[Claim]:
    import sympy as sp

    from ..ratestate.dulac import derive, paper_divergence

    d = derive()
    same = sp.simplify(d.divergence - paper_divergence()) == 0
    mult = ds["return_multiplier"].values
    kap = [float(k) for k in ds["kappa"].values]
    b_minus_a = float(ds.attrs["appendix_B"]) - float(ds.attrs["appendix_A"])
    text = "; ".join(
        f"kappa = {k:g}: {np.nanmin(mult[i]):.6f} to {np.nanmax(mult[i]):.6f}"
        if np.any(np.isfinite(mult[i]))
        else f"kappa = {k:g}: runs away within one turn"
        for i, k in enumerate(kap)
    )
    i_eq = int(np.argmin([abs(k - b_minus_a) for k in kap]))
    closed = float(np.nanmax(np.abs(mult[i_eq] - 1.0)))
    gs, gl = ds["growth_simulated"].values, ds["growth_linear"].values
    rel = float(np.max(np.abs(gs - gl) / np.abs(gl)))
    ratio = ds["inertia_kc_ratio"].values
    eps = ds["inertia_eps"].values
    dev = float(np.nanmax(np.abs(ratio - 1.0 - eps) / eps))
    runaway = str(ds.attrs.get("appendix_quasi_static_runaway", ""))
    return [
        Claim(
            0,
            "Appendix: the quasi-static Rice-Ruina model has divergence (B - A - kappa)(gamma/A) "
            "phi^(-B/A) exp(-kappa alpha/A) (Dulac function g = 1), so it has no periodic orbits "
            "unless B - A - kappa = 0.",
            f"derived with sympy from the physical equations (stickslip dulac): "
            f"{sp.sstr(d.divergence)}; difference from the paper's expression simplifies to 0: "
            f"{same}. Return multipliers on the section alpha = alpha*: {text}. At kappa = B - A "
            f"the orbits close to {closed:.1e}: a continuum of closed orbits (the flow preserves "
            "area), none isolated, so no limit cycle there either.",
            "supported" if same else "contradicted",
        ),
        Claim(
            0,
            "(Standard result used by the appendix) steady sliding loses stability at the critical "
            "stiffness k_c = (B - A) W / D0, the 'transition point' where the divergence vanishes.",
            "growth rates of small perturbations, simulated / linearised, at k/k_c = "
            + ", ".join(
                f"{r:g}: {a:+.5f} / {b:+.5f} 1/s"
                for r, a, b in zip(ds["stiffness_ratio"].values, gs, gl, strict=True)
            )
            + f"; largest relative difference {rel:.1e}; the sign changes at k_c.",
            "supported" if rel < 0.05 and np.all(np.sign(gs) == np.sign(gl)) else "contradicted",
        ),
        Claim(
            0,
            "(Beyond the appendix) with inertia the phase space is three-dimensional and the "
            "theorem no longer applies.",
            f"linearised inertial model: k_c(m)/k_c(0) - 1 = m v0^2/(W A D0) to within "
            f"{dev:.1e} (relative) over 1e-4 to 10, so the quasi-static threshold holds while "
            "m v0^2/(W A D0) is small. At k = 0.8 k_c and v0 = "
            f"{float(ds.attrs['appendix_inertia_v0']) * 1e3:g} mm/s the inertial slider"
            f"{_demo_mass(ds)} settles on a bounded stick-slip cycle{_settling(ds)} (peak velocity "
            f"{float(ds.attrs['appendix_cycle_peak_velocity']):.3g} m/s, period "
            f"{float(ds.attrs['appendix_cycle_period']):.3g} s), while the quasi-static one "
            f"{runaway}.",
            "supported (shown by the inertial slider's simulation)",
        ),
    ]


def _trend(slope: float) -> str:
    """``rises x1.41 per decade``, ``falls x0.71 per decade``, ``stays flat``, ``is not measured``."""
    if not math.isfinite(slope):
        return "is not measured"
    if slope == 0.0:
        return "stays flat"
    return f"{'rises' if slope > 0 else 'falls'} x{_per_decade(slope):.2f} per decade"


def _against_measured(slope: float, measured: float) -> str:
    """Judge a model's log-log slope against a measured one: the verdict depends on the slope's ratio.

    Opposite signs contradict; a ratio within 0.75 to 1/0.75 supports; another ratio of
    the same sign supports in part (steeper or shallower).
    """
    if not (math.isfinite(slope) and math.isfinite(measured)) or slope * measured <= 0.0:
        return "contradicted"
    ratio = slope / measured
    if 0.75 <= ratio <= 1.0 / 0.75:
        return "supported"
    return f"partly supported (right direction, {'steeper' if ratio > 1.0 else 'shallower'})"


def _settling(ds: xr.Dataset) -> str:
    """Say so where the demonstration cycle had not settled at the end of its run (a quick run's)."""
    change = float(ds.attrs.get("appendix_cycle_last_peak_change", 0.0))
    return f" (still settling: its last peak moved by {100 * change:.2g} %)" if change > 1e-3 else ""


def _demo_mass(ds: xr.Dataset) -> str:
    """Return the inertial demonstration slider's mass as the report names it (quick and full runs differ)."""
    mass = float(ds.attrs.get("appendix_inertia_demo_mass", float("nan")))
    return f" (m = {mass * 1e3:.3g} g)" if math.isfinite(mass) else ""  # a reproduce.nc without it


#: the zv experiment's normal load (N), where a local slope is read
ZV_LOAD = 0.196


def _local_slopes(w: np.ndarray, y: np.ndarray) -> str:
    """``from 1.2 to 7.3 (1.6 at 196 mN)``: the range of d log y / d log w, and its value at the zv load."""
    ok = np.isfinite(y) & (y > 0)
    if ok.sum() < 3:
        return "not measured"
    lw, ly = np.log(w[ok]), np.log(y[ok])
    local = np.gradient(ly, lw)
    at = float(np.interp(math.log(ZV_LOAD), lw, local)) if lw[0] <= math.log(ZV_LOAD) <= lw[-1] else math.nan
    where = f" ({at:.2g} at {1e3 * ZV_LOAD:g} mN)" if math.isfinite(at) else ""
    return f"from {local.min():.2g} to {local.max():.2g}{where}"


def _percent(x: float) -> str:
    """Return a relative change for reading: ``+3.2%``, ``-41%``; a factor (``x84``, ``x0.003``) beyond."""
    if x > 10.0 or x < -0.9:
        return f"x{1.0 + x:.2g}" if x < 0 else f"x{1.0 + x:.3g}"
    return f"{100 * x:+.2g}%" if abs(x) < 0.1 else f"{100 * x:+.0f}%"


def _directions(amplitude: list[float], period: list[float]) -> str:
    """Say how the amplitude and the period each go with the load, from the signs of their slopes."""

    def way(slopes: list[float], what: str) -> str:
        if all(s > 0 for s in slopes):
            return f"the {what} increases with the load"
        if all(s < 0 for s in slopes):
            return f"the {what} decreases with the load"
        return f"the {what} goes either way with the load"

    return f"{way(amplitude, 'amplitude')}, {way(period, 'period')}"


def _mass_claim(ds: xr.Dataset) -> Claim:
    """Judge the small-mass 'exception' for both laws of Fig. 2."""
    masses = ds["mass_mass"].values
    unit = ds["mass_mass"].attrs.get("units", "")
    v = ds["mass_v0"].values
    amp = ds["mass_amplitude"].values  # (b, mass, v0)
    parts, verdicts, exception = [], [], {}
    for i, b in enumerate(ds["mass_b"].values):
        slopes = [_slope(v, amp[i, j]) for j in range(masses.size)]
        change = [float(amp[i, j, -1] / amp[i, j, 0] - 1.0) for j in range(masses.size)]
        regimes = set(ds["mass_regime"].values[i].ravel().tolist())
        law = "F1" if b == 0 else f"F2 (b = {b:g} s/m)"
        parts.append(
            f"{law}: slope "
            + ", ".join(f"{x:+.2e} at {m:g} {unit}" for m, x in zip(masses, slopes, strict=True))
            + " (amplitude change over the range "
            + ", ".join(_percent(c) for c in change)
            + f"; regimes: {', '.join(sorted(regimes))})"
        )
        falling = [m for m, x in zip(masses, slopes, strict=True) if x < 0]
        weakest = max(abs(x) for m, x in zip(masses, slopes, strict=True) if m in falling) if falling else 0.0
        exception[law] = bool(falling) and min(masses) in falling
        if falling:
            verdicts.append(
                f"{law}: an exception in sign for m <= {max(falling):g} {unit}, and weak (slopes down to "
                f"{-weakest:.1e}): the stick-slip amplitude falls with v0, against the criterion"
            )
        else:
            verdicts.append(
                f"{law}: the dependence is very weak at small masses (slope {slopes[0]:.1e} at "
                f"{masses[0]:g} {unit}) but the amplitude still rises: no exception in sign"
            )
    text = "; ".join(parts) + ". " + "; ".join(verdicts) + "."
    with_exception = [law for law, e in exception.items() if e]
    without = [law for law, e in exception.items() if not e]
    if with_exception and without:
        verdict = (
            f"supported for {', '.join(with_exception)}; for {', '.join(without)} weak but not an exception"
        )
    elif with_exception:
        verdict = "supported"
    else:
        verdict = "partly supported (weak, but not an exception)"
    return Claim(
        0,
        "The only exception (to the amplitude rising with v0) is a very small mass (< 1 g), where the "
        "velocity dependence is very weak; the paper shows F1 and F2 (b = 100 s/m) in Fig. 2.",
        text,
        verdict,
    )


def _fig3_order_claim(ds: xr.Dataset) -> Claim:
    """Judge the order of Fig. 3's curves (caption: beta = 42 s/m highest, 418 s/m lowest)."""
    v = ds["fig3_v0"].values
    au = ds["fig3_amplitude_au"].values
    betas = [float(b) for b in ds["fig3_beta"].values]
    order = np.argsort(betas)
    lo_beta, hi_beta = order[0], order[-1]
    highest = np.all(au[lo_beta] >= au.max(axis=0))
    lowest_ok = au[hi_beta] <= au.min(axis=0)
    where_not = v[~lowest_ok]
    crossings = []
    for a, b in itertools.combinations(range(len(betas)), 2):
        d = au[a] - au[b]
        for k in np.flatnonzero(np.sign(d[:-1]) * np.sign(d[1:]) < 0):
            # crossing by linear interpolation in log v0 between the two grid points around it
            x = np.log(v[k]) - d[k] * (np.log(v[k + 1]) - np.log(v[k])) / (d[k + 1] - d[k])
            crossings.append(f"beta = {betas[a]:g} and {betas[b]:g} s/m cross at {math.exp(x):.0f} um/s")
    if highest and lowest_ok.all():
        model, verdict = "the order holds at every v0 from 5 to 1000 um/s.", "supported"
    else:
        model = (
            f"beta = {betas[lo_beta]:g} s/m is highest {'everywhere' if highest else 'not everywhere'}; "
            f"beta = {betas[hi_beta]:g} s/m is lowest only up to {v[lowest_ok].max():.0f} um/s and not "
            f"from {where_not.min():.0f} um/s on ({'; '.join(crossings)}); at 1000 um/s the amplitudes are "
            + ", ".join(f"{au[i, -1]:.3f} (beta = {betas[i]:g} s/m)" for i in order)
            + " in units of mu0 W."
        )
        verdict = "partly supported (the order holds below the crossing)"
    return Claim(
        0,
        "Fig. 3 (caption): the curves are ordered, beta = 42 s/m highest, 418 s/m lowest.",
        model,
        verdict,
    )


def _succession_claim(ds: xr.Dataset) -> Claim:
    """Judge the introduction: stick-slip, pure slip and steady sliding succeed one another with v0."""
    seqs = {k[len("regimes_") :]: json.loads(v) for k, v in ds.attrs.items() if k.startswith("regimes_")}
    names = {
        "f1": "F1 (c = 3.81)",
        "f2": "F2 (c = 3.81, p = 2.38)",
        "cubic": "cubic (alpha = 0.5, gamma = 1/6)",
    }
    parts = []
    holds = {}
    for key, seq in seqs.items():
        labels = [
            iv["regime"]
            + ("" if iv["attractors"] == [iv["regime"]] else f" [{' + '.join(iv['attractors'])}]")
            for iv in seq
        ]
        ends = [f"{iv['nu_max']:.4g}" for iv in seq[:-1]]
        parts.append(
            f"{names.get(key, key)}: "
            + " -> ".join(
                f"{lab}" + (f" (to nu = {e})" if e else "")
                for lab, e in zip(labels, [*ends, ""], strict=True)
            )
        )
        holds[key] = [iv["regime"] for iv in seq] == ["stick-slip", "pure-slip", "steady-sliding"] and seq[1][
            "attractors"
        ] == ["pure-slip"]
    ok = [names.get(k, k) for k, h in holds.items() if h]
    model = (
        "regimes over nu from 0.001 to 10 (continuation and direct simulation, stickslip regimes): "
        + "; ".join(parts)
        + ". The succession holds for the cubic law of Thomsen and Fidlin (supercritical Hopf point); "
        "F2 has a subcritical Hopf point (stick-slip coexists with steady sliding, no pure slip), and "
        "F1 never slides steadily (f' < 0 everywhere): its non-sticking oscillation at large nu "
        "reverses the slip direction."
    )
    return Claim(
        0,
        "Introduction (after Thomsen and Fidlin): stick-slip, pure slip and uniform motion are three "
        "distinct possibilities, one succeeding another as v0 increases.",
        model,
        f"supported for {', '.join(ok)} only"
        if ok and len(ok) < len(holds)
        else ("supported" if ok else "contradicted"),
    )


def _friction_range_claim(ds: xr.Dataset) -> Claim:
    """Judge the captions' 'amplitude of the friction force' against the text's spring force."""
    fr = ds["fig2_friction_range"].values
    amp = ds["fig2_amplitude"].values
    rel = fr / amp - 1.0
    parts = [
        f"{'F1' if b == 0 else f'F2 (b = {b:g} s/m)'}: friction range / spring-force range - 1 from "
        f"{_percent(float(np.min(rel[i])))} to {_percent(float(np.max(rel[i])))}"
        for i, b in enumerate(ds["fig2_b"].values)
    ]
    small = bool(np.all(np.abs(rel) < 0.01))
    return Claim(
        0,
        "Figs. 2 and 3 (captions) plot the 'amplitude of the friction force'; the text and Fig. 1 take "
        "the range of the spring force as the amplitude.",
        "over a steady cycle friction balances the spring while the block sticks and is f(v) while it "
        "slips, so the two ranges differ; from the stop force and the peak velocity (events): "
        + "; ".join(parts)
        + ". The figures here plot the spring force's range, as the text defines it.",
        "a naming inconsistency; immaterial for F1 (below 1%)"
        if small
        else "a naming inconsistency that matters: the two amplitudes differ by more than 1%",
    )


def classify_trend(slope: float) -> str:
    """Return the criterion's verdict on a stated trend (its sign)."""
    if slope > 0:
        return "stick-slip"
    if slope < 0:
        return "pure-slip"
    return "inconclusive"
