"""Magnitudes of an event catalogue: checked arrays, counts per bin, completeness, the slope.

Magnitudes are ``log10`` of the moment (the sum of the blocks' slips), as in the
catalogue. Here are the pieces the b-value (:mod:`.statistics`) and the power-law
range (:mod:`.powerlaw`) share: the magnitude-frequency counts, the completeness
magnitude by maximum curvature (Wiemer and Wyss 2000: the bin with the most events;
the synthetic catalogue misses no small events, so no correction is added), and the
maximum-likelihood slope of an exponential law of magnitudes above a lower end, of
Aki (1965), ``b = log10(e) / (mean(M) - M_c)``, or, under an upper end, of the
doubly truncated exponential (Page 1968).
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
from scipy.optimize import brentq

from ..errors import ArgumentTypeError
from ..units import check_number

__all__ = ["LOG10E", "completeness_magnitude", "magnitude_frequency"]

FloatArray = npt.NDArray[np.float64]
LOG10E = math.log10(math.e)


def magnitude_frequency(
    m: npt.ArrayLike, bin_width: float = 0.1
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Return bin centres, counts per bin and the cumulative counts ``N(>= lower edge)``."""
    bin_width = _bin_width(bin_width)
    mm = _floats("m", m)
    mm = mm[np.isfinite(mm)]
    if mm.size == 0:
        e = np.empty(0)
        return e, e, e
    lo = math.floor(mm.min() / bin_width) * bin_width
    edges = np.arange(lo, mm.max() + bin_width * 1.0001, bin_width)
    if edges.size < 2:
        edges = np.array([lo, lo + bin_width])
    counts, edges = np.histogram(mm, bins=edges)
    cum = np.cumsum(counts[::-1])[::-1]
    return 0.5 * (edges[:-1] + edges[1:]), counts.astype(float), cum.astype(float)


def completeness_magnitude(m: npt.ArrayLike, bin_width: float = 0.1) -> float:
    """Return the completeness magnitude by maximum curvature: the lower edge of the fullest bin."""
    centres, counts, _ = magnitude_frequency(m, bin_width)
    if centres.size == 0:
        return math.nan
    return float(centres[int(np.argmax(counts))] - 0.5 * bin_width)


def _floats(name: str, values: object) -> FloatArray:
    """Return ``values`` as a float array; text, or entries that are not numbers, are the wrong type."""
    if isinstance(values, str | bytes):
        raise ArgumentTypeError(f"{name}={values!r}: expected an array of numbers")
    try:
        return np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise ArgumentTypeError(
            f"{name}: expected an array of numbers, got {type(values).__name__}"
        ) from None


def _bin_width(value: object) -> float:
    return check_number(value, "bin_width", what="a positive bin width (magnitude units)")


def _mle(m: FloatArray, mc: float, m_max: float) -> float:
    mean = float(np.mean(m)) - mc
    if mean <= 0.0:
        return math.nan
    if not math.isfinite(m_max):
        return LOG10E / mean
    width = m_max - mc

    def score(beta: float) -> float:  # mean of the truncated exponential minus the sample mean
        x = beta * width  # width / expm1(x), without overflow for a steep sample
        return 1.0 / beta - width * math.exp(-x) / -math.expm1(-x) - mean

    if score(1e-9) <= 0.0:  # the sample is not steeper than uniform: b = 0
        return 0.0
    hi = 1.0
    while score(hi) > 0.0:
        if hi > 1e9:  # the events' mean within about 1e-9 (magnitude) of the lower end
            return math.nan
        hi *= 2.0
    return float(brentq(score, 1e-9, hi, xtol=1e-14)) / math.log(10.0)
