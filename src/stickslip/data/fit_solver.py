"""The least-squares machinery of the waveform fit.

A central-difference Jacobian whose steps follow the parameters' standard errors, the
minimiser (Levenberg-Marquardt, then quasi-Newton steps that check the minimum), and the
parameters' covariance from the Jacobian at the minimum, infinite along a direction the
residuals do not constrain.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt
from scipy.optimize import least_squares

FloatArray = npt.NDArray[np.float64]


def _covariance(jac: FloatArray) -> FloatArray:
    """Inverse of the normal matrix ``J^T J``: the parameters' covariance (weighted residuals).

    Inverted with its columns scaled to unit norm, so parameters of very different
    sensitivity do not make it look singular; a direction it does not constrain at all (an
    eigenvalue of the scaled matrix below 1e-14 of the largest, or a parameter the residuals
    do not depend on) gives the parameters along it an infinite variance. (A pseudo-inverse
    gives that direction zero variance: a parameter the record does not constrain would get
    an error of 1e-19 s/m.)
    """
    normal = jac.T @ jac
    scale = np.sqrt(np.diag(normal))
    unit = np.where(scale > 0, scale, 1.0)
    w, v = np.linalg.eigh(normal / np.outer(unit, unit))
    null = w <= 1e-14 * max(float(w.max()), 0.0)
    inv_w = np.where(null, 0.0, 1.0 / np.where(null, 1.0, w))
    cov = (v * inv_w) @ v.T / np.outer(unit, unit)
    free = np.any(np.abs(v[:, null]) > 1e-8, axis=1) | (scale == 0)
    cov[free, :] = np.nan
    cov[:, free] = np.nan
    cov[free, free] = np.inf
    return np.asarray(cov, dtype=float)


class _Jacobian:
    """Central-difference Jacobian of ``fun`` (``n`` residuals), each step one conditional standard error.

    Forward differences are not enough here: near the minimum the gradient's components
    are large and nearly cancel along the Newton step (the cost is very stiff in the peak
    force and the period), and their O(h) error flips its sign. Nor is a fixed step: moved
    alone, a parameter changes the cost by 1 (one standard error, all others held) over
    ``1 / |J_i|``, which is 1e-7 in log mu_s for 60 cycles at 100 Hz, and a step of 1e-6
    there spans ten of them: the residuals of the samples on the drops are far from linear
    over it, the gradient comes out with the wrong sign and the search stops 20 standard
    errors from the minimum with no warning. So each step is ``1 / |J_i|`` from the
    previous Jacobian (first 1e-6), between 1e-10 and 1e-6 of ``max(1, |x_i|)``: the
    model's own error (rtol 1e-10) over such a step is still far below the derivative.
    """

    def __init__(self, fun: Any, n: int) -> None:
        self.fun, self.n = fun, n
        self.steps: FloatArray | None = None

    def __call__(self, x: FloatArray) -> FloatArray:
        scale = np.maximum(1.0, np.abs(x))
        steps = 1e-6 * scale if self.steps is None else self.steps
        jac = np.empty((self.n, x.size))
        for i in range(x.size):
            e = np.zeros_like(x)
            e[i] = steps[i]
            jac[:, i] = (self.fun(x + e) - self.fun(x - e)) / (2.0 * steps[i])
        norm = np.linalg.norm(jac, axis=0)
        with np.errstate(divide="ignore"):
            one_error = np.where(norm > 0, 1.0 / norm, np.inf)
        self.steps = np.clip(one_error, 1e-10 * scale, 1e-6 * scale)
        return jac


def _minimise(fun: Any, x0: FloatArray, name: str) -> tuple[FloatArray, FloatArray, float]:
    """Minimise ``sum(fun(x)**2)``: Levenberg-Marquardt, then a quasi-Newton check of the minimum.

    The Jacobian is by central differences: near the minimum the gradient's components
    are large and nearly cancel along the step (the cost is very stiff in the peak force
    and the period), and forward differences make the methods stop early. With noise on
    every sample the residuals do not vanish at the minimum, and the curvature that
    Gauss-Newton leaves out (sum of residual times second derivative) is not small along
    the poorly determined combination of parameters; BFGS updates of the Gauss-Newton
    matrix pick it up where Levenberg-Marquardt stops short. Stops when the predicted or
    the achieved decrease of the cost is below 1e-4 (a ten-thousandth of the change that
    moves a parameter by one standard error), or when five steps gain less than 0.5
    together (a flat direction).

    Returns the minimiser, the Jacobian of the residuals there and the cost.
    """
    n = fun(x0).size
    jacobian = _Jacobian(fun, n)
    jacobian(x0)  # the first steps: one standard error of each parameter at the start
    res = least_squares(fun, x0, jac=jacobian, method="lm", x_scale="jac", max_nfev=1000)
    x = res.x
    r = fun(x)
    jac = jacobian(x)
    g = 2.0 * jac.T @ r
    hess = 2.0 * jac.T @ jac
    cost = float(r @ r)
    history = [cost]
    for _ in range(200):
        # a flat direction (a parameter the record does not determine) is crawled along forever,
        # each step gaining a few hundredths: five steps together gaining less than 0.5 (the
        # points are within a standard error of each other) end the search
        if len(history) > 5 and history[-6] - history[-1] < 0.5:
            break
        try:
            step = -np.linalg.solve(hess, g)
        except np.linalg.LinAlgError:
            step = -np.linalg.lstsq(hess, g, rcond=None)[0]
        decrement = float(-g @ step)
        if decrement < 1e-4:
            break
        t = 1.0
        while True:
            x_new = x + t * step
            r_new = fun(x_new)
            cost_new = float(r_new @ r_new)
            if cost_new <= cost - 1e-4 * t * decrement or t < 1e-6:
                break
            t *= 0.5
        if cost_new > cost - 1e-4:
            # no descent along the step (at the minimum to the precision of the model), or a
            # flat direction (a parameter the record does not determine: the warnings say so)
            if cost_new < cost:
                x, r, cost = x_new, r_new, cost_new
                jac = jacobian(x)
            break
        jac_new = jacobian(x_new)
        g_new = 2.0 * jac_new.T @ r_new
        sv, yv = x_new - x, g_new - g
        if sv @ yv > 0:
            hs = hess @ sv
            hess = hess - np.outer(hs, hs) / (sv @ hs) + np.outer(yv, yv) / (sv @ yv)
        x, r, jac, g, cost = x_new, r_new, jac_new, g_new, cost_new
        history.append(cost)
    else:
        raise RuntimeError(f"{name}: the waveform fit did not converge in 200 quasi-Newton steps")
    return x, jac, cost
