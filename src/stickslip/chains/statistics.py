"""Earthquake statistics of an event catalogue: Gutenberg-Richter b-value, completeness, recurrence.

Magnitudes here are ``log10`` of the moment (sum of the blocks' slips), as in the
catalogue; a seismological moment magnitude ``M_w = (2/3) log10 M_0 + const``
has a b-value 3/2 times this one.

* b-value by maximum likelihood: Aki (1965), ``b = log10(e) / (mean(M) - M_c)``
  for continuous magnitudes above the completeness ``M_c``; with an upper
  bound ``M_max`` the likelihood of the doubly truncated exponential (Page
  1968) is maximised instead. Its error by bootstrap (resampling the events)
  beside the Shi and Bolt (1982) formula.
* Completeness ``M_c``: maximum curvature (Wiemer and Wyss 2000), the bin with
  the most events; the synthetic catalogue misses no small events, so no
  correction is added.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
from scipy.optimize import brentq

__all__ = ["BValue", "b_value", "completeness_magnitude", "magnitude_frequency", "recurrence_times"]

FloatArray = npt.NDArray[np.float64]
LOG10E = math.log10(math.e)


@dataclass(frozen=True)
class BValue:
    """A Gutenberg-Richter fit ``log10 N(>= M) = a - b M``.

    Attributes
    ----------
    b : float
        Maximum-likelihood b-value (nan with fewer than 2 events above ``mc``).
    error : float
        Standard deviation of ``b`` over bootstrap resamples.
    shi_bolt : float
        The Shi and Bolt (1982) standard error.
    mc : float
        Completeness magnitude used.
    m_max : float
        Upper magnitude of the fit (inf: none).
    n : int
        Events in the fit.
    a : float
        ``log10`` of the number of events above ``mc``, plus ``b mc``.

    """

    b: float
    error: float
    shi_bolt: float
    mc: float
    m_max: float
    n: int
    a: float


def magnitude_frequency(
    m: npt.ArrayLike, bin_width: float = 0.1
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Return bin centres, counts per bin and the cumulative counts ``N(>= lower edge)``."""
    mm = np.asarray(m, dtype=float)
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


def _mle(m: FloatArray, mc: float, m_max: float) -> float:
    mean = float(np.mean(m)) - mc
    if mean <= 0.0:
        return math.nan
    if not math.isfinite(m_max):
        return LOG10E / mean
    width = m_max - mc

    def score(beta: float) -> float:  # mean of the truncated exponential minus the sample mean
        return 1.0 / beta - width / math.expm1(beta * width) - mean

    if score(1e-9) <= 0.0:  # the sample is not steeper than uniform: b = 0
        return 0.0
    hi = 1.0
    while score(hi) > 0.0 and hi < 1e6:
        hi *= 2.0
    return float(brentq(score, 1e-9, hi, xtol=1e-14)) / math.log(10.0)


def b_value(
    m: npt.ArrayLike,
    mc: float | None = None,
    m_max: float | None = None,
    *,
    n_boot: int = 200,
    seed: int | None = 0,
    bin_width: float = 0.1,
) -> BValue:
    """Fit the b-value of magnitudes ``m`` above ``mc`` (and below ``m_max``) by maximum likelihood.

    Parameters
    ----------
    m : array of float
        Magnitudes (``log10`` moment); non-finite ones are skipped.
    mc : float, optional
        Completeness magnitude; default :func:`completeness_magnitude`.
    m_max : float, optional
        Upper end of the fit (the power law of small events, below a bump of
        large ones); default none.
    n_boot : int
        Bootstrap resamples for the error (0: none, error nan).
    seed : int, optional
        Seed of the bootstrap.
    bin_width : float
        Magnitude bins of the completeness estimate.

    """
    mm = np.asarray(m, dtype=float)
    mm = mm[np.isfinite(mm)]
    mc_ = completeness_magnitude(mm, bin_width) if mc is None else float(mc)
    top = math.inf if m_max is None else float(m_max)
    sel = mm[(mm >= mc_) & (mm <= top)]
    n = int(sel.size)
    if n < 2 or not math.isfinite(mc_):
        return BValue(math.nan, math.nan, math.nan, mc_, top, n, math.nan)
    b = _mle(sel, mc_, top)
    shi = 2.3 * b * b * float(np.std(sel, ddof=1)) / math.sqrt(n) if math.isfinite(b) else math.nan
    err = math.nan
    if n_boot > 0:
        rng = np.random.default_rng(seed)
        boots = [_mle(rng.choice(sel, n), mc_, top) for _ in range(n_boot)]
        err = float(np.nanstd(boots, ddof=1))
    a = math.log10(n) + b * mc_ if math.isfinite(b) else math.nan
    return BValue(float(b), err, shi, mc_, top, n, a)


def recurrence_times(t_start: npt.ArrayLike) -> FloatArray:
    """Return the times between successive event starts."""
    return np.diff(np.asarray(t_start, dtype=float))
