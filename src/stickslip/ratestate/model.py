"""Rate-and-state friction parameters with units (Dieterich-Ruina laws, several state variables).

Friction ``mu = mu0 + A ln(v/V_r) + sum_i B_i ln(Phi_i V_r / D_c,i)`` (with ``2 D_c,i``
for the Perrin-Rice-Zheng law) with states ``Phi_i`` (times) evolving by

* the aging law ``Phi' = 1 - v Phi / D_c`` (Dieterich 1979),
* the slip law ``Phi' = -(v Phi / D_c) ln(v Phi / D_c)`` (Ruina 1983),
* the Perrin-Rice-Zheng law ``Phi' = 1 - (v Phi / (2 D_c))^2`` (J. Mech. Phys. Solids 43, 1461, 1995),
* the Nagata law ``Phi' = 1 - v Phi / D_c - (c / B) Phi mu'`` (J. Geophys. Res. 117, B02314, 2012).

Sources: J. H. Dieterich, J. Geophys. Res. 84 (1979) 2161; A. Ruina, J. Geophys. Res. 88
(1983) 10359; J. R. Rice and A. L. Ruina, J. Appl. Mech. 50 (1983) 343.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt
import pint

from ..core import ratestate_api as core
from ..units import Q_, check_number, parse_quantity

__all__ = ["STATE_LAWS", "RateStateParameters"]

STATE_LAWS = ("aging", "slip", "prz", "nagata")
FORMS = ("log", "regularized")
YEAR = 365.25 * 24 * 3600.0
#: the longest simulated time (s) of a run or of one stage of a protocol: a billion years (a
#: hold of 100 yr, healing over an interseismic interval, is a standard exercise)
MAX_DURATION = 1e9 * YEAR


def check_dc(dc: pint.Quantity, name: str) -> None:
    """Refuse a slip distance outside 1 pm .. 1 km (1e-320 m: 'stiffness inf' or 'too stiff')."""
    if not 1e-12 <= float(dc.to("m").magnitude) <= 1e3:
        raise ValueError(f"{name}={dc:~P}: expected a slip distance between 1 pm and 1 km")


def _many(value: Any) -> bool:
    return isinstance(value, Sequence) and not isinstance(value, str)


@dataclass(frozen=True)
class RateStateParameters:
    """A rate-and-state spring-slider with one or several state variables.

    Parameters
    ----------
    a : float
        Direct effect ``A > 0`` (dimensionless).
    b : float or sequence of float
        Evolution effect ``B >= 0`` of each state variable (dimensionless); several
        values give several state variables, e.g. ``(0.0185, 0.0088)``.
    dc : pint.Quantity or str, or a sequence of them
        Characteristic slip distance ``D_c`` of each state variable, e.g. ``"10 um"``
        or ``("5 um", "50 um")`` (as many as ``b``).
    v_ref : pint.Quantity or str
        Reference velocity ``V_r`` at which steady friction is ``mu0``, e.g. ``"1 um/s"``.
    mu0 : float
        Steady-state friction at ``V_r``.
    stiffness : pint.Quantity or str, optional
        Spring constant ``k`` (force/length), with ``load``; or give ``stiffness_per_load``.
    load : pint.Quantity or str, optional
        Normal load ``W``.
    stiffness_per_load : pint.Quantity or str, optional
        ``k/W`` as friction per length (1/length), e.g. ``"0.5 1/mm"``.
    mass : pint.Quantity or str, optional
        Mass of the slider: the inertial model (needs ``load``). Default: quasi-static.
    state_law : str or sequence of str, optional
        ``"aging"`` (default), ``"slip"``, ``"prz"`` (Perrin-Rice-Zheng), ``"nagata"``, or a
        formula for ``dPhi/dt`` in ``v``, ``phi``, ``dc``, ``vr`` and ``mu_rate`` (e.g.
        ``"1 - (v*phi/dc)**2"``, see :mod:`stickslip.ratestate.statelaw`): one for every
        state variable, or one each.
    nagata_c : float or sequence of float, optional
        Nagata's coefficient ``c >= 0`` (dimensionless) of each Nagata state variable.
    radiation_damping : pint.Quantity or str, optional
        ``eta / sigma`` (time/length): a damping stress ``eta v`` added to friction
        (the quasi-dynamic approximation), e.g. ``"0.1 s/m"``. Default: none.
    friction_form : str, optional
        ``"log"`` (``mu0 + A ln(v/V_r) + ...``, default) or ``"regularized"``
        (``A asinh(v/(2 V_r) exp((mu0 + ...)/A))``, Rice and Ben-Zion 1996); the
        inertial model is always regularized (it must be defined at ``v <= 0``).

    Raises
    ------
    ValueError
        For a missing, conflicting, non-physical or wrongly dimensioned value.

    """

    a: float
    b: Any
    dc: Any
    v_ref: Any
    mu0: float
    stiffness: Any = None
    load: Any = None
    stiffness_per_load: Any = None
    mass: Any = None
    state_law: Any = "aging"
    nagata_c: Any = 0.0
    radiation_damping: Any = None
    friction_form: str = "log"

    def __post_init__(self) -> None:
        from .statelaw import state_law_formula  # sympy: loaded by a formula's law only

        set_ = object.__setattr__
        set_(self, "a", check_number(self.a, "a", what="a positive direct effect A"))
        bs = list(self.b) if _many(self.b) else [self.b]
        dcs = list(self.dc) if _many(self.dc) else [self.dc]
        if not bs:
            raise ValueError("b is empty: give one evolution effect per state variable")
        if len(bs) != len(dcs):
            raise ValueError(
                f"b has {len(bs)} value(s) and dc {len(dcs)}: give one dc per state variable "
                "(--b and --dc in pairs)"
            )
        bs = [
            check_number(
                v,
                f"b[{i}]" if len(bs) > 1 else "b",
                allow_zero=True,
                what="a non-negative evolution effect B",
            )
            for i, v in enumerate(bs)
        ]
        dcs = [
            parse_quantity(v, f"dc[{i}]" if len(dcs) > 1 else "dc", "[length]", "10 um")
            for i, v in enumerate(dcs)
        ]
        set_(self, "b", bs[0] if len(bs) == 1 else tuple(bs))
        for i, q in enumerate(dcs):
            check_dc(q, f"dc[{i}]" if len(dcs) > 1 else "dc")
        set_(self, "dc", dcs[0] if len(dcs) == 1 else tuple(dcs))
        n = len(bs)
        laws = list(self.state_law) if _many(self.state_law) else [self.state_law]
        if len(laws) not in (1, n):
            raise ValueError(
                f"state_law={self.state_law!r}: give one law for all {n} state variables or one each"
            )
        for lw in laws:
            if not isinstance(lw, str):
                raise ValueError(
                    f"state_law={lw!r}: expected one of {', '.join(map(repr, STATE_LAWS))} or a formula"
                )
            if lw not in STATE_LAWS:
                state_law_formula(lw)  # a formula for dPhi/dt, or a ValueError naming the choices
        set_(self, "state_law", laws[0] if len(laws) == 1 else tuple(laws))
        cs = list(self.nagata_c) if _many(self.nagata_c) else [self.nagata_c] * n
        if len(cs) != n:
            raise ValueError(
                f"nagata_c={self.nagata_c!r}: give one value for all state variables or one each"
            )
        cs = [
            check_number(c, "nagata_c", allow_zero=True, what="a non-negative Nagata coefficient c")
            for c in cs
        ]
        # a coefficient that reaches no Nagata state variable would do nothing, without a word (one value
        # is shared by all, and reaches those that are Nagata's; one each must be 0 for the others)
        if "nagata" not in self.laws and any(c != 0 for c in cs):
            raise ValueError(
                f"nagata_c={self.nagata_c!r} with state_law={self.state_law!r}: the Nagata coefficient "
                "acts on state_law='nagata' only"
            )
        each = _many(self.nagata_c)
        set_(self, "nagata_c", cs[0] if len(set(cs)) == 1 else tuple(cs))
        for i, (law, c_i) in enumerate(zip(self.laws, cs, strict=True)):
            if each and law != "nagata" and c_i != 0:
                raise ValueError(
                    f"nagata_c[{i}]={c_i!r}: state variable {i} follows state_law={law!r}, not "
                    "'nagata': expected 0"
                )
        for law, b_i, c_i in zip(self.laws, bs, cs, strict=True):
            if law == "nagata" and c_i > 0 and b_i == 0:
                raise ValueError("nagata_c > 0 needs b > 0 (the Nagata term is (c/b) Phi mu')")
        set_(self, "mu0", check_number(self.mu0, "mu0", what="a positive reference friction"))
        set_(self, "v_ref", parse_quantity(self.v_ref, "v_ref", "[length] / [time]", "1 um/s"))
        if self.friction_form not in FORMS:
            raise ValueError(f"friction_form={self.friction_form!r}: expected 'log' or 'regularized'")
        if self.radiation_damping is not None:
            set_(
                self,
                "radiation_damping",
                parse_quantity(self.radiation_damping, "radiation_damping", "[time] / [length]", "0.1 s/m"),
            )
        if self.load is not None:
            set_(self, "load", parse_quantity(self.load, "load", "[force]", "10 N"))
        if self.stiffness_per_load is not None:
            if self.stiffness is not None:
                raise ValueError("give stiffness (with load) or stiffness_per_load, not both")
            set_(
                self,
                "stiffness_per_load",
                parse_quantity(self.stiffness_per_load, "stiffness_per_load", "1 / [length]", "0.5 1/mm"),
            )
        elif self.stiffness is not None:
            if self.load is None:
                raise ValueError("stiffness needs load (or give stiffness_per_load = k/W)")
            set_(
                self,
                "stiffness",
                parse_quantity(self.stiffness, "stiffness", "[mass] / [time] ** 2", "1e6 N/m"),
            )
        else:
            raise ValueError("give stiffness and load, or stiffness_per_load (k/W, 1/length)")
        if self.mass is not None:
            if self.load is None:
                raise ValueError("mass needs load: the inertial model is m x'' = k (x_lp - x) - W mu")
            set_(self, "mass", parse_quantity(self.mass, "mass", "[mass]", "1 kg"))

    # ------------------------------------------------------------ state variables
    @property
    def n_states(self) -> int:
        """Number of state variables."""
        return len(self.bs)

    @property
    def bs(self) -> tuple[float, ...]:
        """Evolution effects ``B_i``."""
        return self.b if isinstance(self.b, tuple) else (self.b,)

    @property
    def dcs(self) -> tuple[pint.Quantity, ...]:
        """Characteristic slip distances ``D_c,i``."""
        return self.dc if isinstance(self.dc, tuple) else (self.dc,)

    @property
    def laws(self) -> tuple[str, ...]:
        """Evolution law of each state variable."""
        if isinstance(self.state_law, tuple):
            return self.state_law
        return (self.state_law,) * self.n_states

    @property
    def cs(self) -> tuple[float, ...]:
        """Nagata coefficient of each state variable."""
        return self.nagata_c if isinstance(self.nagata_c, tuple) else (self.nagata_c,) * self.n_states

    @property
    def b_total(self) -> float:
        """``sum_i B_i``: steady-state friction is ``mu0 + (A - sum_i B_i) ln(v/V_r)``."""
        return float(sum(self.bs))

    @property
    def dc_max(self) -> pint.Quantity:
        """The largest ``D_c,i``."""
        return max(self.dcs, key=lambda q: q.to("m").magnitude)

    def state_scale(self, i: int) -> float:
        """Return ``L_i`` (m): ``Phi_i = L_i exp(theta_i) / V_r`` (``2 D_c`` for the PRZ law)."""
        dc = float(self.dcs[i].to("m").magnitude)
        return 2.0 * dc if self.laws[i] == "prz" else dc

    # ------------------------------------------------------------------ spring
    @property
    def kw(self) -> pint.Quantity:
        """``k/W`` (1/m)."""
        if self.stiffness_per_load is not None:
            return self.stiffness_per_load.to("1/m")
        return (self.stiffness / self.load).to("1/m")

    @property
    def inertial(self) -> bool:
        """Whether the slider has a mass (inertial model)."""
        return self.mass is not None

    @property
    def critical_kw(self) -> pint.Quantity:
        """Critical ``k/W`` (1/m) of the quasi-static slider: steady sliding is unstable below it.

        ``max(0, (B - A)/D_c)`` for one state variable (aging or slip law); with
        several, the ``k/W`` at which the leading eigenvalue of the linearisation
        crosses zero. 0: stable at any stiffness. Independent of the sliding
        velocity (log form, no damping, no mass); with radiation damping or a mass it
        depends on it: use :meth:`critical_kw_at`.

        Raises
        ------
        ValueError
            With radiation damping or a mass (the value depends on the velocity).

        """
        if self.radiation_damping is not None or self.inertial:
            what = "radiation damping" if self.radiation_damping is not None else "a mass"
            raise ValueError(
                f"with {what} the critical stiffness depends on the sliding velocity: "
                "use critical_kw_at(v0) (or linear_stability(params, v0).kw_critical)"
            )
        if self.n_states == 1 and self.laws[0] in ("aging", "slip"):
            return Q_(max(0.0, float(((self.b - self.a) / self.dc).to("1/m").magnitude)), "1/m")
        return Q_(_critical_kw_numeric(self, float(self.v_ref.to("m/s").magnitude)), "1/m")

    def critical_kw_at(self, v0: Any) -> pint.Quantity:
        """Critical ``k/W`` (1/m) of steady sliding at the load-point velocity ``v0``.

        The stiffness at which the leading eigenvalue of the linearisation about
        steady sliding at ``v0`` crosses zero, with radiation damping (quasi-static:
        ``(B - A - eta v0 / sigma)/D_c`` for one state variable) and a mass (Rice and
        Ruina: ``(B - A)/D_c (1 + m v0^2/(W A D_c))`` without damping) when the
        parameters have them. 0: stable at any stiffness.
        """
        v = parse_quantity(v0, "v0", "[length] / [time]", "1 um/s")
        return Q_(_critical_kw_numeric(self, float(v.to("m/s").magnitude)), "1/m")

    @property
    def critical_stiffness(self) -> pint.Quantity:
        """Critical stiffness ``k_c = (k/W)_c W`` (N/m); needs ``load``. See :attr:`critical_kw`."""
        if self.load is None:
            raise ValueError("critical_stiffness needs load; use critical_kw for k/W")
        return (self.critical_kw * self.load).to("N/m")

    def kappa(self) -> float:
        """Return the appendix's ``kappa = k D0 / W`` (one state variable)."""
        return float((self.kw * self.dcs[0]).to("").magnitude)

    def steady_state_friction(self, v: Any) -> npt.NDArray[np.float64]:
        """Return ``mu_ss = mu0 + (A - sum_i B_i) ln(v/V_r)`` at slip velocity ``v`` (> 0)."""
        if isinstance(v, str):
            v = parse_quantity(v, "v", "[length] / [time]", "1 um/s", allow_zero=True)
        if not isinstance(v, pint.Quantity) or not v.check("[length] / [time]"):
            raise ValueError(f"v={v!r}: expected a velocity with units such as '1 um/s'")
        x = np.asarray((v / self.v_ref).to("").magnitude, dtype=float)
        if np.any(~(x > 0)):
            raise ValueError(f"v={v!r}: mu_ss has ln(v/V_r), the logarithm needs a positive velocity")
        vr = float(self.v_ref.to("m/s").magnitude)
        if any(lw not in STATE_LAWS for lw in self.laws):
            psi = np.vectorize(
                lambda xi: float(np.dot(self.bs, steady_log_states(self, xi * vr))), otypes=[float]
            )(x)
        else:
            psi = self.b_total * np.log(1.0 / x)
        if self.friction_form == "regularized" or self.inertial:
            return self.a * np.arcsinh(0.5 * x * np.exp((self.mu0 + psi) / self.a))
        return self.mu0 + self.a * np.log(x) + psi

    def core_arrays(self) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """Return ``(P, S)`` in SI for the compiled core (:mod:`stickslip.core.ratestate`)."""
        from .statelaw import program_table, state_law_formula  # sympy: loaded by a formula's law only

        wm = (self.load / self.mass).to("m/s**2").magnitude if self.mass is not None else 0.0
        eta = 0.0 if self.radiation_damping is None else self.radiation_damping.to("s/m").magnitude
        form = core.REGULARIZED if (self.friction_form == "regularized" or self.inertial) else core.LOG
        P = np.array(
            [self.a, self.v_ref.to("m/s").magnitude, self.mu0, self.kw.to("1/m").magnitude, wm, eta, form],
            dtype=float,
        )
        S = np.array(
            [
                [b, d.to("m").magnitude, STATE_LAWS.index(lw) if lw in STATE_LAWS else core.USER, c]
                for b, d, lw, c in zip(self.bs, self.dcs, self.laws, self.cs, strict=True)
            ],
            dtype=float,
        )
        programs = [None if lw in STATE_LAWS else state_law_formula(lw).program for lw in self.laws]
        return P, np.hstack([S, program_table(programs)])

    def dimensionless(self, v0: Any) -> dict[str, float]:
        """Return the appendix's ``omega = v0/V_r``, ``gamma = exp(-mu0/A)``, ``kappa = k D0/W``."""
        v = (
            parse_quantity(v0, "v0", "[length] / [time]", "1 um/s")
            if not isinstance(v0, pint.Quantity)
            else v0
        )
        return {
            "omega": float((v / self.v_ref).to("").magnitude),
            "gamma": math.exp(-self.mu0 / self.a),
            "kappa": self.kappa(),
            "A": self.a,
            "B": self.b_total,
        }


def steady_log_states(params: RateStateParameters, v: float) -> npt.NDArray[np.float64]:
    """Log-states of steady sliding at ``v`` (m/s): ``ln(V_r / v)`` for the built-in laws."""
    from .statelaw import state_law_formula  # sympy: loaded by a formula's law only

    vr = float(params.v_ref.to("m/s").magnitude)
    out = np.full(params.n_states, math.log(vr / v))
    for i, lw in enumerate(params.laws):
        if lw not in STATE_LAWS:
            dc = float(params.dcs[i].to("m").magnitude)
            out[i] = math.log(state_law_formula(lw).steady_phi(v, dc, vr) * vr / dc)
    return out


def steady_state(params: RateStateParameters, v: float, P: Any, S: Any) -> npt.NDArray[np.float64]:
    """Steady sliding at load-point velocity ``v`` (m/s) in the core's variables.

    The spring carries friction plus the damping stress ``eta v``; with a mass the
    state holds the slip velocity too.
    """
    theta = steady_log_states(params, v)
    if not params.inertial:
        mu = float(params.steady_state_friction(Q_(v, "m/s"))) + P[core.P_ETA] * v
        return np.concatenate([[mu], theta])
    mu_s = core.in_friction(v, np.concatenate([[0.0, v], theta]), S, params.n_states, P) + P[core.P_ETA] * v
    return np.concatenate([[mu_s, v], theta])


def jacobian(params: RateStateParameters, v: float, kw: float | None = None) -> npt.NDArray[np.float64]:
    """Return the Jacobian (1/s) of the model about steady sliding at ``v`` (m/s), at ``k/W = kw``."""
    P, S = params.core_arrays()
    if kw is not None:
        P[core.P_KW] = kw
    n = params.n_states
    y = steady_state(params, v, P, S)
    jac = np.empty((y.size, y.size))
    if params.inertial:
        core.in_jac(y, P, S, n, jac)
    else:
        core.qs_jac(y, P, S, n, jac)
    return jac


def growth_rate(params: RateStateParameters, kw: float, v: float) -> float:
    """Largest real part (1/s) of the linearisation about steady sliding at ``v`` (m/s), at ``k/W = kw``."""
    return float(np.max(np.linalg.eigvals(jacobian(params, v, kw)).real))


def _critical_kw_numeric(params: RateStateParameters, v: float) -> float:
    """Critical ``k/W`` (1/m) at velocity ``v`` (m/s), by bisection on the growth rate."""
    scale = max(float(b) / float(d.to("m").magnitude) for b, d in zip(params.bs, params.dcs, strict=True))
    lo, hi = 1e-9 * scale, 10.0 * scale
    if growth_rate(params, lo, v) <= 0.0:
        return 0.0  # stable at any stiffness (velocity strengthening, or damped enough)
    while growth_rate(params, hi, v) > 0.0:  # a mass raises it (Rice and Ruina)
        hi *= 10.0
        if hi > 1e12 * scale:
            return math.inf
    for _ in range(200):
        mid = math.sqrt(lo * hi)
        if growth_rate(params, mid, v) > 0.0:
            lo = mid
        else:
            hi = mid
        if hi / lo - 1.0 < 1e-12:
            break
    return 0.5 * (lo + hi)
