"""The SEAS BP1 spring-slider written from its equations for SciPy, not from stickslip's code.

Quasi-dynamic: ``tau(t) = tau0 + k (V_pl t - slip) = sigma f(V, theta) + eta V`` solved
for the slip rate ``V`` by ``brentq``, the regularized friction
``f = a asinh(V/(2 V0) exp((f0 + b ln(V0 theta/Dc))/a))`` and the aging law. The
reference of ``tests/test_cycles.py`` and ``benchmarks/bench_bp1.py``; state ``y =
(slip [m], theta [s])``, time in s.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

A, B, F0 = 0.01, 0.015, 0.6
DC = 8e-3  # m
SIGMA = 50e6  # Pa
V0 = 1e-6  # m/s
VPL = 1e-9  # m/s
ETA = 4.62e6  # Pa s/m
K = 0.5 * SIGMA * (B - A) / DC  # half the critical stiffness (Pa/m)


def friction(v: float, theta: float) -> float:
    """The regularized rate-and-state friction coefficient."""
    return A * math.asinh(v / (2 * V0) * math.exp((F0 + B * math.log(V0 * theta / DC)) / A))


THETA0 = 0.5 * DC / VPL
TAU0 = SIGMA * friction(VPL, THETA0) + ETA * VPL


def slip_rate(t: float, y: np.ndarray) -> float:
    """The slip rate (m/s) that balances the spring's stress at time ``t``."""
    tau = TAU0 + K * (VPL * t - y[0])
    return float(
        brentq(lambda v: SIGMA * friction(v, y[1]) + ETA * v - tau, 0.0, tau / ETA, xtol=1e-300, rtol=1e-15)
    )


def rhs(t: float, y: np.ndarray) -> np.ndarray:
    """``d(slip, theta)/dt``."""
    v = slip_rate(t, y)
    return np.array([v, 1.0 - v * y[1] / DC])
