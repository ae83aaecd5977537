r"""Exact 1-D total-variation denoising (numbers only).

.. math::

    \hat x = \arg\min_x \tfrac12 \sum_i (y_i - x_i)^2 + \lambda \sum_i |x_{i+1} - x_i|

solved exactly, in one pass of worst-case O(n^2) and, on measured signals, O(n) time,
by L. Condat's direct algorithm (*A direct algorithm for 1-D total variation
denoising*, IEEE Signal Processing Letters 20, 1054, 2013). The solution is
piecewise constant; the algorithm grows the current segment while the dual variable
``u`` (the running sum of ``y - x``) can stay within ``[-lambda, lambda]`` and, where
it cannot, closes the segment at the last place a jump up (``k_plus``) or down
(``k_minus``) was still possible. A flat stretch of a signal stays flat where the
running sum of its noise stays within ``lambda``, and a jump of height ``h`` between
segments of ``n1`` and ``n2`` samples is shrunk by ``lambda (1/n1 + 1/n2)``.
"""

from __future__ import annotations

import numba
import numpy as np
import numpy.typing as npt

__all__ = ["tv_denoise"]


@numba.njit(cache=True, nogil=True)
def _tv_denoise(
    y: npt.NDArray[np.float64], lam: float, x: npt.NDArray[np.float64]
) -> None:  # pragma: no cover
    n = y.size
    if n == 0:
        return
    k = 0  # the sample being added to the current segment
    k0 = 0  # the first sample of the current segment
    k_plus = 0  # the last sample where the segment's upper bound was reached
    k_minus = 0  # the last sample where the segment's lower bound was reached
    v_lo = y[0] - lam  # the lowest value the segment may take
    v_hi = y[0] + lam  # the highest
    u_lo = lam  # the dual variable at the end of the segment, for the value v_lo
    u_hi = -lam  # ... for the value v_hi
    while True:
        while k == n - 1:  # the right end: the dual variable must come to 0
            if u_lo < 0.0:  # v_lo is too high: close the segment at k_minus with it
                for i in range(k0, k_minus + 1):
                    x[i] = v_lo
                k0 = k_minus + 1
                k = k0
                k_minus = k0
                v_lo = y[k0]
                u_lo = lam
                u_hi = v_lo + u_lo - v_hi
            elif u_hi > 0.0:  # v_hi is too low: close it at k_plus with v_hi
                for i in range(k0, k_plus + 1):
                    x[i] = v_hi
                k0 = k_plus + 1
                k = k0
                k_plus = k0
                v_hi = y[k0]
                u_hi = -lam
                u_lo = v_hi + u_hi - v_lo
            else:  # the last segment: its value makes the dual variable end at 0
                v = v_lo + u_lo / (k - k0 + 1)
                for i in range(k0, k + 1):
                    x[i] = v
                return
        u_lo += y[k + 1] - v_lo
        u_hi += y[k + 1] - v_hi
        if u_lo < -lam:  # a jump down is needed: the segment ends at k_minus, at v_lo
            for i in range(k0, k_minus + 1):
                x[i] = v_lo
            k0 = k_minus + 1
            k = k0
            k_plus = k0
            k_minus = k0
            v_lo = y[k0]
            v_hi = v_lo + 2.0 * lam
            u_lo = lam
            u_hi = -lam
        elif u_hi > lam:  # a jump up is needed: the segment ends at k_plus, at v_hi
            for i in range(k0, k_plus + 1):
                x[i] = v_hi
            k0 = k_plus + 1
            k = k0
            k_plus = k0
            k_minus = k0
            v_hi = y[k0]
            v_lo = v_hi - 2.0 * lam
            u_lo = lam
            u_hi = -lam
        else:  # the segment grows by one sample; its bounds tighten where the dual hits them
            k += 1
            if u_lo >= lam:
                v_lo += (u_lo - lam) / (k - k0 + 1)
                u_lo = lam
                k_minus = k
            if u_hi <= -lam:
                v_hi += (u_hi + lam) / (k - k0 + 1)
                u_hi = -lam
                k_plus = k


def tv_denoise(y: npt.ArrayLike, lam: float) -> npt.NDArray[np.float64]:
    """Return the exact total-variation denoising of ``y`` with weight ``lam``.

    Parameters
    ----------
    y : array_like
        The samples (1-D, finite).
    lam : float
        The weight of the total variation, in the unit of ``y`` (>= 0; 0 returns ``y``).

    Returns
    -------
    ndarray
        The piecewise-constant minimiser, as many samples as ``y``.

    """
    arr = np.ascontiguousarray(y, dtype=np.float64)
    if arr.ndim != 1:
        raise ValueError(f"y: expected a 1-D array, got shape {arr.shape}")
    if not (lam >= 0 and np.isfinite(lam)):
        raise ValueError(f"lam={lam!r}: expected a finite weight >= 0")
    out = np.empty_like(arr)
    _tv_denoise(arr, float(lam), out)
    return out
