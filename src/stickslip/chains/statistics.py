"""Earthquake statistics of an event catalogue: Gutenberg-Richter b-value, its range, recurrence, ruptures.

Magnitudes here are ``log10`` of the moment (sum of the blocks' slips), as in the
catalogue; a seismological moment magnitude ``M_w = (2/3) log10 M_0 + const``
has a b-value 3/2 times this one.

* b-value by maximum likelihood: Aki (1965), ``b = log10(e) / (mean(M) - M_c)``
  for continuous magnitudes above the completeness ``M_c``; with an upper
  bound ``M_max`` the likelihood of the doubly truncated exponential (Page
  1968) is maximised instead. Its error by bootstrap beside the Shi and Bolt
  (1982) formula. Successive events of a chain are not independent (a large
  event unloads the chain, small ones follow), and resampling them one by one
  understates the error; ``block="auto"`` resamples runs of successive events
  (the circular block bootstrap, Politis and Romano 1992) of a length chosen
  from the magnitudes' autocorrelation (Politis and White 2004, corrected by
  Patton, Politis and White 2009).
* Completeness ``M_c``: maximum curvature (Wiemer and Wyss 2000), the bin with
  the most events; the synthetic catalogue misses no small events, so no
  correction is added.
* The range of the power law, ``mc="auto"`` (:func:`power_law_range`): a
  catalogue of a chain is not one power law from ``M_c`` up (one-block events pile up at
  one magnitude, a plateau of few-block events follows, ruptures of the whole chain make a
  bump at the top), and a b-value over the wrong range is a wrong verdict. For every
  upper end ``M_hi`` on the magnitude grid (and none) the lower end is the one that
  minimises the Kolmogorov-Smirnov distance between the events of ``[M_lo, M_hi]`` and
  the (truncated) exponential fitted to them, as Clauset, Shalizi and Newman (2009,
  section 3.3) choose the start of a power law. Of these ranges the one whose events
  span the most magnitude units is kept (the upper end as Deluca and Corral 2013 choose
  it) among those that pass two tests at CSN's level, p >= 0.1 (their section 4.2), both
  drawn by one parametric bootstrap that chooses the lower end again in each sample
  (their section 4.1): KS, and one slope against two at the most likely cut (the largest
  likelihood ratio over the cuts of the grid: a change-point test). KS compares whole
  distributions and is weak near a range's top, where a chain's plateau or bump of large
  events starts; the change of slope is what sets the upper end there. A range must hold
  50 events spreading over at least one magnitude unit, a decade of moment. Where no
  range passes, the catalogue is not a power law over a decade of moment: ``b`` is nan,
  and ``verdict`` says why the widest range tested failed. The range still depends on
  the catalogue's size where the local slope drifts: a small catalogue cannot reject a
  range that a large one does (docs/chain.md measures it); compare catalogues of
  different sizes over a range fixed by hand.
* Connected ruptures (:func:`connected_ruptures`): an event of a chain, from all blocks
  stuck to all stuck, may hold slips in separate places; Carlson and Langer's event is
  one connected run of slipping blocks.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import numpy.typing as npt
from scipy.optimize import brentq
from scipy.stats import chi2

from ..errors import ArgumentTypeError
from ..units import check_count, check_number, check_seed

__all__ = [
    "BValue",
    "Ruptures",
    "b_value",
    "block_length",
    "check_fit_range",
    "completeness_magnitude",
    "connected_ruptures",
    "magnitude_frequency",
    "power_law_range",
    "recurrence_times",
    "ruptures_in_pieces",
    "slope_change",
]

FloatArray = npt.NDArray[np.float64]
LOG10E = math.log10(math.e)
#: Stephens (1974, JASA 69, 730), Table 1A, exponential with estimated scale: the
#: modified statistic ``(D - 0.2/n)(sqrt(n) + 0.26 + 0.5/sqrt(n))`` exceeds this
#: with probability 5 % when the sample is exponential
KS_CRITICAL_5 = 1.094
#: the same table's 10 % value: the KS test of a range when no bootstrap is made (``n_boot=0``),
#: and a bound that spares the bootstrap of a range that fails anyway (its p is below 0.1)
KS_CRITICAL_10 = 0.995
#: a range whose goodness-of-fit p-value (KS by parametric bootstrap; one slope against two) is
#: below this is not a power law: Clauset, Shalizi and Newman (2009, section 4.2) rule a power law
#: out at p <= 0.1, which rejects about one true power law in ten, to be safe from false ones
GOF_LEVEL = 0.1
#: level of the test of one slope against two (at the most likely cut) that a power-law range passes
SLOPE_CHANGE_LEVEL = GOF_LEVEL
#: a power law claims at least this many magnitude units (a decade of moment: M = log10 moment),
#: from the range's lower end to its largest event
MIN_SPAN = 1.0
#: the fewest events in a range that :func:`power_law_range` tests
MIN_EVENTS = 50
#: the most ranges whose tests :func:`power_law_range` draws (each ``n_boot`` samples): where the
#: widest ranges all fail at the edge of the tests, drawing on through narrower ones costs minutes
#: on a large catalogue and finds, at last, a range that passes by the chance of its draws
MAX_DRAWN = 12
#: the fewest events on either side of a cut where the change of slope is sought (:func:`_knee`):
#: a slope of fewer is too loose to tell from noise, and the largest ratio over the cuts would
#: be that noise's
MIN_PART = 10
#: how the statistics of a catalogue are computed; stores of ensembles record it, so that a
#: resumed ensemble does not mix members' b-values from two versions (2: block bootstrap errors
#: and the slope-change test of the power-law range; 3: the lower end by the least KS distance,
#: KS by parametric bootstrap, both tests at 10 %, no b-value where no range passes)
STATISTICS_VERSION = 3


@dataclass(frozen=True)
class BValue:
    """A Gutenberg-Richter fit ``log10 N(>= M) = a - b M``.

    Attributes
    ----------
    b : float
        Maximum-likelihood b-value: nan with fewer than 2 events above ``mc``, and, for a
        range chosen by :func:`power_law_range` (``method`` ``"power-law range"``), where no
        range passes as a power law over a decade of moment (``verdict`` says why; the
        other fields then describe the widest range drawn, else the closest fit by KS).
    error : float
        Standard deviation of ``b`` over bootstrap resamples.
    shi_bolt : float
        The Shi and Bolt (1982) standard error (``ln(10) b^2 sigma(M) / sqrt(n)``; their
        2.30 is ln 10), for independent events and no upper bound; nan with ``m_max`` (it assumes the
        untruncated exponential; the bootstrap's ``error`` does not).
    mc : float
        Completeness magnitude used.
    m_max : float
        Upper magnitude of the fit (inf: none).
    n : int
        Events in the fit.
    a : float
        ``log10`` of the number of events above ``mc``, plus ``b mc``.
    ks : float
        Stephens' modified Kolmogorov-Smirnov statistic of the events in the
        range against the fitted exponential (truncated at ``m_max``); above
        :data:`KS_CRITICAL_10` the range is not a power law at 10 % (the test
        where no bootstrap was made).
    method : str
        How the range was chosen: ``"given"``, ``"maximum curvature"`` or
        ``"power-law range"`` (:func:`power_law_range`).
    block : int
        Events per block of the bootstrap behind ``error`` (1: events resampled
        one by one, as if independent).
    b_lower, b_upper : float
        The b-values below and above ``m_split``, fitted apart, at the most likely
        change of slope in the range.
    m_split : float
        That cut: of the cuts on the magnitude grid with at least :data:`MIN_PART`
        events on either side, the one where two slopes (and shares of the events)
        fit best against one slope, by likelihood ratio; nan where no cut qualifies.
    slope_p : float
        The p-value of one slope against two at that cut, the search over the cuts
        counted: by the parametric bootstrap beside ``ks_p``, or without one
        (``n_boot=0``) Bonferroni's bound, the cuts tried times the chi-square
        p-value (2 degrees of freedom). Below :data:`GOF_LEVEL` the slope changes
        across the range, and it is not a power law. Nan where no cut qualifies:
        ``power_law`` then rests on KS alone.
    ks_p : float
        The p-value of the Kolmogorov-Smirnov distance by parametric bootstrap
        (Clauset, Shalizi and Newman 2009, section 4.1): the share of samples drawn
        from the fit whose distance is at least the catalogue's, the lower end chosen
        again in each where the range was chosen by :func:`power_law_range`; below
        :data:`GOF_LEVEL`, not a power law. Nan without a bootstrap (``n_boot=0``):
        ``ks`` against :data:`KS_CRITICAL_10` is the test then.
    span : float
        Magnitude units from ``mc`` to the largest event of the range (decades of
        moment); a power law needs at least :data:`MIN_SPAN`.
    n_upper : int
        Events of the range at or above ``m_split``: a few of them test the slope there
        weakly, and a top that flattens can pass.

    """

    b: float
    error: float
    shi_bolt: float
    mc: float
    m_max: float
    n: int
    a: float
    ks: float = math.nan
    method: str = "given"
    block: int = 1
    b_lower: float = math.nan
    b_upper: float = math.nan
    m_split: float = math.nan
    slope_p: float = math.nan
    ks_p: float = math.nan
    span: float = math.nan
    n_upper: int = 0

    @property
    def power_law(self) -> bool:
        """Whether the range passes as a power law over a decade of moment.

        Its events span :data:`MIN_SPAN` magnitude units at least, and neither test rejects
        it at :data:`GOF_LEVEL`: KS (``ks_p`` by bootstrap, or ``ks`` against Stephens'
        10 % value without one) and one slope against two (``slope_p``). A test that could
        not be made (nan) rejects nothing.
        """
        return math.isfinite(self.b) and self._failure() == ""

    def _failure(self) -> str:
        """Why the range fails as a power law, in words (empty where it passes its tests)."""
        if not math.isfinite(self.ks):
            return ""
        if self.span < MIN_SPAN:
            return (
                f"its events span {self.span:.2f} magnitude units from M = {self.mc:.2f}, less than "
                f"{MIN_SPAN:g} (a decade of moment)"
            )
        if self.ks_p < GOF_LEVEL:
            return f"Kolmogorov-Smirnov p = {self.ks_p:.2g} by parametric bootstrap, below {GOF_LEVEL:g}"
        if not math.isfinite(self.ks_p) and not self.ks <= KS_CRITICAL_10:
            return f"Kolmogorov-Smirnov statistic {self.ks:.3g} above Stephens' 10 % value {KS_CRITICAL_10}"

        def slope(b: float) -> str:
            return f"{b:.3g}" if math.isfinite(b) else "none (no events)"

        if self.slope_p < GOF_LEVEL:
            return (
                f"the slope changes across the range: b = {slope(self.b_lower)} below "
                f"M = {self.m_split:.2f}, {slope(self.b_upper)} above (p = {self.slope_p:.2g})"
            )
        return ""

    @property
    def verdict(self) -> str:
        """Why the range is not a power law, in one line (empty where it is)."""
        if self.power_law:
            return ""
        why = self._failure()
        if self.method == "power-law range":
            if not math.isfinite(self.ks):
                return (
                    f"no b-value (no range of magnitudes holds {MIN_EVENTS} events spread over "
                    f"{MIN_SPAN:g} unit, a decade of moment: too few to test a power law)"
                )
            if not math.isfinite(self.b):
                top = f"{self.m_max:.2f}" if math.isfinite(self.m_max) else "the largest event"
                why = why or f"it is not among the {MAX_DRAWN} widest ranges drawn"
                # the range described: the widest drawn, else (none drawn) the closest fit by KS
                return (
                    f"not a power law over a decade of moment: no range passes (M = {self.mc:.2f} to "
                    f"{top}: {why}); no b-value"
                )
        if not math.isfinite(self.b) or not why:
            return "no b-value (too few events, or their magnitudes do not spread)"
        return f"not a power law: {why}"

    def expected_cumulative(self, m: npt.ArrayLike, n_above: int = 0) -> FloatArray:
        """Return the fit's ``N(>= m)`` for ``mc <= m <= m_max``, to compare with a catalogue's.

        The fitted law is truncated at ``m_max``: its ``n`` events have
        ``N(>= m) = n (10**(-b (m - mc)) - q) / (1 - q)`` with
        ``q = 10**(-b (m_max - mc))`` (``q = 0`` without ``m_max``; a flat
        distribution where ``b = 0``), and the catalogue's events above
        ``m_max``, which the fit leaves out by design, add to every ``N(>= m)``.

        Parameters
        ----------
        m : array_like of float
            Magnitudes (``log10`` of the moment), within the fitted range.
        n_above : int, optional
            The catalogue's events above ``m_max``.

        Returns
        -------
        ndarray of float
            Expected number of events of magnitude at least ``m`` (nan where
            the fit is undefined, or ``b <= 0`` without an upper end).

        """
        mm = np.asarray(m, dtype=float)
        top = math.isfinite(self.m_max)
        if not math.isfinite(self.b) or (self.b <= 0.0 and not top):
            return np.full(mm.shape, math.nan)
        if self.b == 0.0:
            share = (self.m_max - mm) / (self.m_max - self.mc)
        else:
            beta = self.b * math.log(10.0)
            share = np.exp(-beta * (mm - self.mc))
            if top:  # (10**(-b u) - q) / (1 - q), exact for small b as well
                share = (
                    share * np.expm1(-beta * (self.m_max - mm)) / math.expm1(-beta * (self.m_max - self.mc))
                )
        return np.asarray(self.n * share + n_above, dtype=float)


def check_fit_range(mc: float | str | None, m_max: float | None) -> tuple[float | str | None, float | None]:
    """Return the range ``(mc, m_max)`` of a b-value fit, checked; ``ValueError`` names a bad end.

    ``mc``: a finite magnitude, ``"auto"`` (:func:`power_law_range`) or None
    (maximum curvature); ``m_max``: None or a finite magnitude, above ``mc``
    where ``mc`` is a magnitude.
    """
    if isinstance(mc, str) and mc != "auto":
        raise ValueError(f"mc={mc!r}: expected a magnitude, 'auto' or None (maximum curvature)")
    if mc is not None and not isinstance(mc, str):
        mc = _magnitude("mc", mc, "a finite magnitude, 'auto' or None (maximum curvature)")
    if m_max is not None:
        m_max = _magnitude("m_max", m_max, f"a finite magnitude above mc={mc!r}, or None")
        if isinstance(mc, float) and not m_max > mc:
            raise ValueError(f"m_max={m_max!r}: expected a finite magnitude above mc={mc!r}")
    return mc, m_max


def _magnitude(name: str, value: object, expected: str) -> float:
    try:
        out = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise ArgumentTypeError(f"{name}={value!r}: expected {expected}") from None
    if not math.isfinite(out):
        raise ValueError(f"{name}={value!r}: expected {expected}")
    return out


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


def _distance(sel: FloatArray, lo: float, hi: float, beta: float) -> float:
    """Return the KS distance of sorted ``sel`` to the exponential of rate ``beta`` (natural) on [lo, hi]."""
    n = sel.size
    u = sel - lo
    if beta <= 0.0:
        f = u / (hi - lo) if math.isfinite(hi) else np.zeros(n)
    else:
        f = -np.expm1(-beta * u)
        if math.isfinite(hi):
            f /= -math.expm1(-beta * (hi - lo))
    i = np.arange(1, n + 1) / n
    return max(float(np.max(i - f)), float(np.max(f - (i - 1.0 / n))))


def _stephens(d: float, n: int) -> float:
    """Stephens' (1974) modified KS statistic of a distance ``d`` over ``n`` events."""
    rn = math.sqrt(n)
    return (d - 0.2 / n) * (rn + 0.26 + 0.5 / rn)


def _ks(sel: FloatArray, lo: float, hi: float, b: float) -> float:
    """Stephens' modified KS statistic of sorted ``sel`` against the exponential of ``b`` on [lo, hi]."""
    n = sel.size
    if n < 2 or not math.isfinite(b):
        return math.nan
    return _stephens(_distance(sel, lo, hi, b * math.log(10.0)), n)


def _rates(excess: FloatArray, width: FloatArray) -> FloatArray:
    """Return maximum-likelihood rates ``beta = b ln 10`` of exponentials truncated at ``width``, vectorised.

    ``excess`` is each sample's mean above its lower end: the rate solves
    ``1/beta - width/expm1(beta width) = excess`` (:func:`_mle`'s equation), ``1/excess``
    for an infinite width, 0 where ``excess >= width/2`` (not steeper than uniform), nan where
    ``excess <= 0``. With ``x = beta width`` and ``r = excess/width`` the root of the
    decreasing, convex ``h(x) = 1/x - 1/expm1(x)`` at ``h = r`` lies above ``1/r - 2``
    (``h(y) > 1/(y + 2)`` for every ``y > 0``), and Newton's steps from there rise to it
    monotonically: 40 of them reach the rounding of a double from any start (a start far
    below the root at least doubles each step).
    """
    excess = np.asarray(excess, dtype=float)
    width = np.broadcast_to(np.asarray(width, dtype=float), excess.shape)
    out = np.full(excess.shape, math.nan)
    pos = excess > 0.0
    open_ = pos & np.isinf(width)
    out[open_] = 1.0 / excess[open_]
    r = np.where(pos & np.isfinite(width), excess / np.where(np.isfinite(width), width, 1.0), math.nan)
    out[r >= 0.5] = 0.0
    solve = np.flatnonzero(r < 0.5)
    if solve.size:
        target = r[solve]
        x = np.maximum(1.0 / target - 2.0, 0.0)
        for _ in range(40):
            small = x < 1e-2  # the series, where 1/x - 1/expm1(x) would cancel
            xs = np.where(small, 1.0, np.minimum(x, 700.0))  # beyond, 1/expm1(x) is 0 to a double
            em = np.expm1(xs)
            h = np.where(small, 0.5 - x / 12.0 + x**3 / 720.0 - x**5 / 30240.0, 1.0 / xs - 1.0 / em)
            dh = np.where(
                small, -1.0 / 12.0 + x**2 / 240.0 - x**4 / 6048.0, -1.0 / xs**2 - 1.0 / (em * np.expm1(-xs))
            )
            step = np.maximum(x - (h - target) / dh, x)  # from below the root: never down
            if np.array_equal(step, x):
                break
            x = step
        out[solve] = x / width[solve]
    return out


def _grid(s: FloatArray, bin_width: float) -> FloatArray:
    """Return the grid of ``bin_width`` from below the smallest of sorted ``s`` to above its largest."""
    k0 = math.floor(s[0] / bin_width + 1e-9)
    k1 = math.ceil(s[-1] / bin_width - 1e-9)
    return np.asarray(np.round(np.arange(k0, k1 + 1) * bin_width, 12), dtype=float)


def _lower_end(
    s: FloatArray, hi: float, edges: FloatArray, min_width: float, min_events: int
) -> tuple[float, float, int, int] | None:
    """Return ``(lo, D, i0, i1)``: the lower end of ``[lo, hi]`` closest to its fit in KS distance ``D``.

    ``lo`` is on ``edges``; the range of sorted ``s`` is the one closest to the exponential
    fitted to it (Clauset, Shalizi and Newman 2009, section 3.3) among those holding at least
    ``min_events`` events, the largest ``min_width`` or more above ``lo``: ``s[i0:i1]``.
    None where no lower end qualifies.
    """
    i1 = int(np.searchsorted(s, hi, "right")) if math.isfinite(hi) else s.size
    if i1 < max(min_events, 2):
        return None
    i0 = np.searchsorted(s, edges, "left")
    n = i1 - i0
    top = float(s[i1 - 1])
    ok = np.flatnonzero((n >= max(min_events, 2)) & (edges < hi) & (top - edges >= min_width - 1e-9))
    if ok.size == 0:
        return None
    csum = np.concatenate([[0.0], np.cumsum(s[:i1])])
    excess = (csum[i1] - csum[i0[ok]]) / n[ok] - edges[ok]
    beta = _rates(excess, hi - edges[ok])
    best: tuple[float, float, int, int] | None = None
    for k, rate in zip(ok, beta, strict=True):
        if not math.isfinite(rate):
            continue
        lo = float(edges[k])
        d = _distance(s[i0[k] : i1], lo, hi, float(rate))
        if best is None or d < best[1]:
            best = (lo, d, int(i0[k]), i1)
    return best


class _Knee(NamedTuple):
    """The most likely place of a change of slope in a range (:func:`_knee`)."""

    ratio: float  # twice the log-likelihood ratio of two slopes (cut there) against one
    cut: float
    b_lower: float
    b_upper: float
    n_upper: int  # events at or above the cut
    cuts: int  # the cuts tried


def _part_loglik(k: FloatArray, excess: FloatArray, width: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Return the maximised log-likelihoods of parts of ``k`` events, mean ``excess`` above their lower end.

    Each part is an exponential truncated at ``width`` (inf: none) with its maximum-likelihood
    rate (:func:`_rates`; rate 0: uniform over ``width``); nan where the rate is nan. The
    rates are returned beside them.
    """
    beta = _rates(excess, width)
    with np.errstate(divide="ignore", invalid="ignore"):
        norm = np.where(np.isfinite(width), -np.expm1(-beta * np.where(np.isfinite(width), width, 1.0)), 1.0)
        steep = k * np.log(beta) - beta * k * excess - k * np.log(norm)
        flat = -k * np.log(np.where(np.isfinite(width), width, np.inf))
    return np.where(beta > 0.0, steep, np.where(beta == 0.0, flat, math.nan)), beta


def _knee(sel: FloatArray, lo: float, hi: float, edges: FloatArray) -> _Knee:
    """Return the cut of ``[lo, hi]`` on ``edges`` where two slopes fit sorted ``sel`` best against one.

    At each cut with :data:`MIN_PART` events on either side, the events below it (an
    exponential truncated at the cut) and above it (truncated at ``hi``) get a slope and a
    share of the events each; twice their log-likelihood ratio against one slope over the
    range is chi-square with 2 degrees of freedom at a cut fixed beforehand (Wilks). The
    largest over the cuts, where a chain's catalogue turns into a plateau or a bump, is
    the change-point statistic whose p-value :func:`_gof_pvalues` draws (or bounds,
    :func:`_knee_p`). A ratio of nan where no cut qualifies.
    """
    n = sel.size
    none = _Knee(math.nan, math.nan, math.nan, math.nan, 0, 0)
    top = hi if math.isfinite(hi) else float(sel[-1]) if n else lo
    cuts = edges[(edges > lo + 1e-9) & (edges < top - 1e-9)]
    if n < 2 * MIN_PART or cuts.size == 0:
        return none
    at = np.searchsorted(sel, cuts, "left")
    ok = (at >= MIN_PART) & (n - at >= MIN_PART)
    cuts, at = cuts[ok], at[ok]
    c = cuts.size
    if c == 0:
        return none
    csum = np.concatenate([[0.0], np.cumsum(sel)])
    k1 = at.astype(float)
    k2 = n - k1
    below = csum[at]
    # one solve for all the parts: the range whole, below each cut, above each cut
    k = np.concatenate([[float(n)], k1, k2])
    excess = np.concatenate([[csum[n] / n - lo], below / k1 - lo, (csum[n] - below) / k2 - cuts])
    width = np.concatenate([[hi - lo], cuts - lo, hi - cuts])
    ll, beta = _part_loglik(k, excess, width)
    one, ll1, ll2 = ll[0], ll[1 : c + 1], ll[c + 1 :]
    ratio = 2.0 * (ll1 + ll2 + k1 * np.log(k1 / n) + k2 * np.log(k2 / n) - one)
    if not math.isfinite(one) or not np.isfinite(ratio).any():
        return none
    j = int(np.nanargmax(ratio))
    b1, b2 = float(beta[1 + j]) / math.log(10.0), float(beta[c + 1 + j]) / math.log(10.0)
    return _Knee(max(float(ratio[j]), 0.0), float(cuts[j]), b1, b2, int(k2[j]), c)


def _knee_p(knee: _Knee) -> float:
    """Return Bonferroni's bound on the p-value of a knee: the cuts tried times chi-square's p of its ratio.

    At least the bootstrap's p (:func:`_gof_pvalues`), where the chi-square law of each cut holds:
    a bound below a level rejects, without drawing.
    """
    if not math.isfinite(knee.ratio):
        return math.nan
    return min(1.0, knee.cuts * float(chi2.sf(knee.ratio, 2)))


def _gof_pvalues(
    s: FloatArray,
    lo: float,
    hi: float,
    d_obs: float,
    ratio_obs: float,
    *,
    edges: FloatArray,
    scan: bool,
    min_width: float,
    min_events: int,
    n_boot: int,
    seed: int | None,
    levels: tuple[float, float] = (0.0, 0.0),
) -> tuple[float, float]:
    """Return the p-values of the KS distance ``d_obs`` and the knee ``ratio_obs`` of ``[lo, hi]``, drawn.

    Clauset, Shalizi and Newman (2009, section 4.1): each of ``n_boot`` samples has as many
    events as sorted ``s``; each event is drawn, with the catalogue's shares, from the events
    below ``lo``, from the exponential fitted to ``[lo, hi]`` or from the events above ``hi``.
    With ``scan``, the lower end of each sample is chosen again as :func:`_lower_end` chose
    ``lo`` (the upper end is held), else the range is held and only the fit is redone. Each
    p-value is the share of samples whose statistic (distance to their fit; the largest
    ratio of two slopes to one, :func:`_knee`) is at least the catalogue's; samples without
    a range or a cut that qualifies are left out (nan where none is left, or ``ratio_obs``
    is nan). With ``levels`` (KS, knee), the draws stop where either p cannot reach its level
    any more, and bounds below it are returned.
    """
    rng = np.random.default_rng(seed)
    inside = s[(s >= lo) & (s <= hi)]
    below = s[s < lo] if scan else s[:0]
    above = s[s > hi] if scan else s[:0]
    n = below.size + inside.size + above.size
    rate = _mle(inside, lo, hi) * math.log(10.0)
    shares = np.array([below.size, inside.size, above.size], dtype=float) / n
    knee = math.isfinite(ratio_obs)
    exceed = np.zeros(2)
    valid = np.zeros(2)
    for r in range(n_boot):
        kb, ki, ka = rng.multinomial(n, shares)
        u = rng.uniform(size=ki)
        if rate <= 0.0:
            drawn = lo + u * (hi - lo)
        elif math.isfinite(hi):
            drawn = lo - np.log1p(u * math.expm1(-rate * (hi - lo))) / rate
        else:
            drawn = lo - np.log1p(-u) / rate
        x = np.sort(np.concatenate([rng.choice(below, kb) if kb else below[:0], drawn,
                                    rng.choice(above, ka) if ka else above[:0]]))  # fmt: skip
        if scan:
            found = _lower_end(x, hi, edges, min_width, min_events)
            d, lo_r, part = (
                (math.nan, lo, x[:0]) if found is None else (found[1], found[0], x[found[2] : found[3]])
            )
        else:
            b = _mle(x, lo, hi)
            d = _distance(x, lo, hi, b * math.log(10.0)) if math.isfinite(b) and x.size >= 2 else math.nan
            lo_r, part = lo, x
        stats = (d, _knee(part, lo_r, hi, edges).ratio if knee and part.size else math.nan)
        for i, (got, obs) in enumerate(zip(stats, (d_obs, ratio_obs), strict=True)):
            if math.isfinite(got):
                valid[i] += 1
                exceed[i] += got >= obs
        left = n_boot - r - 1
        most = (exceed + left) / np.maximum(valid + left, 1)
        if most[0] < levels[0] or (knee and most[1] < levels[1]):
            return float(most[0]), float(most[1]) if knee else math.nan
    p = np.where(valid > 0, exceed / np.maximum(valid, 1), math.nan)
    return float(p[0]), float(p[1]) if knee else math.nan


def _loglik(sel: FloatArray, lo: float, hi: float, b: float) -> float:
    """Log-likelihood of ``sel`` under the exponential of ``b`` on ``[lo, hi]`` (``hi`` may be inf)."""
    n = sel.size
    if b <= 0.0:  # uniform on a bounded range
        return -n * math.log(hi - lo) if math.isfinite(hi) else -math.inf
    beta = b * math.log(10.0)
    norm = -math.expm1(-beta * (hi - lo)) if math.isfinite(hi) else 1.0
    return n * math.log(beta) - beta * float(np.sum(sel - lo)) - n * math.log(norm)


def slope_change(m: npt.ArrayLike, mc: float, m_max: float = math.inf) -> tuple[float, float, float, float]:
    """Test one Gutenberg-Richter slope against two over ``[mc, m_max]``.

    The range is cut in the middle (of ``mc`` and the largest event where
    ``m_max`` is inf). One exponential over the range (one parameter) is
    nested in the law with a slope of its own in each half and a free share
    of the events below the cut (three): twice their log-likelihood ratio is
    chi-square with 2 degrees of freedom where the slope is one (Wilks). The
    Kolmogorov-Smirnov test compares the whole distribution and is weak near a
    range's ends, where a chain's bump starts (measured: docs/chain.md). The cut in
    the middle sees a change near the top weakly, where few events lie above it:
    :func:`power_law_range` and ``b_value`` seek the change at every cut instead.

    Parameters
    ----------
    m : array of float
        Magnitudes; those outside ``[mc, m_max]`` and non-finite ones are skipped.
    mc, m_max : float
        The range.

    Returns
    -------
    b_lower, b_upper, m_split, p : float
        The halves' b-values (nan for a half without events: its share is
        0, its slope free), the cut and the p-value (small: the slope
        changes; nan with fewer than 2 events, and where a half's events all
        sit at its lower end, whose slope has no finite fit: the b-values and
        p nan, the cut given; :func:`power_law_range` then judges by KS alone). The test holds its level
        with few events in a half, down to one (rejections of truncated
        Gutenberg-Richter samples with 1-60 events above the cut: 0.6-1.6 %
        at 1 %, measured), but it is weak there.

    """
    mm = _floats("m", m)
    sel = np.sort(mm[np.isfinite(mm) & (mm >= mc) & (mm <= m_max)])
    return _slope_change(sel, float(mc), float(m_max), _mle(sel, mc, m_max) if sel.size else math.nan)


def _slope_change(sel: FloatArray, lo: float, hi: float, b: float) -> tuple[float, float, float, float]:
    """:func:`slope_change` of sorted ``sel`` in ``[lo, hi]`` whose one slope is ``b``."""
    nan = math.nan
    if sel.size < 2 or not math.isfinite(b):
        return nan, nan, nan, nan
    cut = 0.5 * (lo + (hi if math.isfinite(hi) else float(sel[-1])))
    k = int(np.searchsorted(sel, cut, "left"))
    n = sel.size
    two = 0.0  # the log-likelihood of a slope and a share of the events in each half
    slopes = []
    for part, a, c in ((sel[:k], lo, cut), (sel[k:], cut, hi)):
        if part.size == 0:  # all events in the other half: its share is 1 (and its slope free)
            slopes.append(nan)
            continue
        bp = _mle(part, a, c)
        if not math.isfinite(bp):  # the half's events all at its lower end: no slope to compare
            return nan, nan, cut, nan
        slopes.append(bp)
        two += part.size * math.log(part.size / n) + _loglik(part, a, c, bp)
    ratio = max(2.0 * (two - _loglik(sel, lo, hi, b)), 0.0)
    return slopes[0], slopes[1], cut, float(chi2.sf(ratio, 2))


def power_law_range(
    m: npt.ArrayLike,
    *,
    m_max: float | None = None,
    bin_width: float = 0.1,
    min_width: float = MIN_SPAN,
    min_events: int = MIN_EVENTS,
    slope_level: float = GOF_LEVEL,
    level: float = GOF_LEVEL,
    n_boot: int = 200,
    seed: int | None = 0,
) -> tuple[float, float, float]:
    """Return ``(mc, m_max, ks)``: the range of magnitudes that is a Gutenberg-Richter power law.

    For every upper end ``hi`` on the grid of ``bin_width`` (and none), the lower end
    ``lo`` on the grid is the one whose events in ``[lo, hi]`` are closest, in
    Kolmogorov-Smirnov distance, to the exponential fitted to them by maximum likelihood
    (truncated at ``hi``): Clauset, Shalizi and Newman (2009, section 3.3) choose the
    start of a power law so. The range must hold ``min_events`` events, the largest
    at least ``min_width`` above ``lo`` (a decade of moment for 1). Of these ranges, one
    for each upper end, the one whose events span the most magnitude units is returned
    (then the one with the most events; Deluca and Corral 2013 choose the upper end so)
    among those that pass two tests, drawn from one parametric bootstrap of ``n_boot``
    samples in which the lower end is chosen again (CSN section 4.1): KS at ``level``,
    and one slope against two at the most likely cut (the largest likelihood ratio over
    the cuts of the grid with :data:`MIN_PART` events on either side) at
    ``slope_level``. KS compares whole distributions, and misses a slope that changes
    near a range's top, where a chain's plateau or bump of large events starts: the
    slope test sets the upper end there. Ranges that fail a cheap bound are not drawn:
    Stephens' (1974) modified KS statistic above his 10 % value
    (:data:`KS_CRITICAL_10`), or Bonferroni's bound on the slope test (the cuts times
    chi-square's p) below ``slope_level``; with ``n_boot=0`` these bounds are the tests.
    At most :data:`MAX_DRAWN` ranges are drawn, the widest first. Where none passes,
    the widest range drawn (else the one that fits best by Stephens' statistic) is
    returned, and ``b_value(m, mc="auto")`` has no b-value (``verdict`` says why). The
    upper end is not chosen again in the bootstrap: the p-value of a range whose top
    was picked among many is a little high.

    Parameters
    ----------
    m : array of float
        Magnitudes; non-finite ones are skipped.
    m_max : float, optional
        A fixed upper end (only the lower one is chosen).
    bin_width : float
        Spacing of the grid of candidate ends (magnitude units).
    min_width : float
        The fewest magnitude units a range's events span (lower end to largest event).
    min_events : int
        Fewest events in a range considered.
    slope_level : float
        Level of the test of one slope against two (0: none).
    level : float
        Level of the KS test (Clauset, Shalizi and Newman's 0.1 by default).
    n_boot : int
        Samples of the bootstrap (0: Stephens' value and Bonferroni's bound instead).
    seed : int, optional
        Seed of the bootstrap.

    Returns
    -------
    mc, m_max, ks : float
        The range (``m_max`` inf: unbounded) and Stephens' modified KS statistic of
        its events; all nan where no range qualifies.

    """
    found = _scan(_floats("m", m), m_max, bin_width, min_width, min_events, slope_level, level,
                  n_boot, seed)  # fmt: skip
    return (found[0], found[1], found[2]) if found is not None else (math.nan, math.nan, math.nan)


def _scan(
    m: FloatArray,
    m_max: float | None,
    bin_width: float,
    min_width: float,
    min_events: int,
    slope_level: float,
    level: float,
    n_boot: int,
    seed: int | None,
) -> tuple[float, float, float, float, float, bool] | None:
    """:func:`power_law_range`, with the range's p-values (KS, knee) and whether it passed.

    The p-values are nan where the range did not pass (none did).
    """
    for name, x in (("bin_width", bin_width), ("min_width", min_width), ("slope_level", slope_level),
                    ("level", level)):  # fmt: skip
        if isinstance(x, bool) or not isinstance(x, numbers.Real):
            raise ArgumentTypeError(f"{name}={x!r} (type {type(x).__name__}): expected a number")
    if not (bin_width > 0 and min_width > 0):
        raise ValueError(f"bin_width={bin_width!r}, min_width={min_width!r}: expected positive widths")
    if not 0.0 <= slope_level < 1.0:
        raise ValueError(f"slope_level={slope_level!r}: expected a level in [0, 1) (0: no slope test)")
    if not 0.0 < level < 1.0:
        raise ValueError(f"level={level!r}: expected a level in (0, 1)")
    n_boot = check_count(n_boot, "n_boot", minimum=0, what="a whole number of bootstrap resamples")
    s = np.sort(m[np.isfinite(m)])
    if s.size < max(int(min_events), 2):
        return None
    edges = _grid(s, bin_width)
    tops = [float(m_max)] if m_max is not None else [*edges.tolist(), math.inf]
    ranges = []  # (span, events, -lo, hi) to maximise, then lo, hi, distance, Stephens' statistic
    for hi in tops:
        found = _lower_end(s, hi, edges, min_width, int(min_events))
        if found is None:
            continue
        lo, d, i0, i1 = found
        ranges.append(((float(s[i1 - 1]) - lo, i1 - i0, -lo, hi), lo, hi, d, _stephens(d, i1 - i0), i0, i1))
    if not ranges:
        return None
    nan = math.nan
    drawn: list[tuple[float, float, float]] = []
    for _, lo, hi, d, ks, i0, i1 in sorted(ranges, key=lambda r: r[0], reverse=True):
        # Stephens' p below 10 %: the bootstrap's is too (his value is exact for a fixed open range,
        # conservative for a truncated one, and a lower end chosen again only brings samples closer)
        if not ks <= KS_CRITICAL_10 and (n_boot == 0 or level >= GOF_LEVEL):
            continue
        knee = _knee(s[i0:i1], lo, hi, edges) if slope_level > 0 else _Knee(nan, nan, nan, nan, 0, 0)
        if _knee_p(knee) < slope_level:  # Bonferroni's bound rejects: the bootstrap would
            continue
        if n_boot == 0:
            return lo, hi, ks, nan, _knee_p(knee), True
        if len(drawn) == MAX_DRAWN:  # the widest ranges fail at the edge of the tests: marginal
            break
        drawn.append((lo, hi, ks))
        p_ks, p_knee = _gof_pvalues(s, lo, hi, d, knee.ratio, edges=edges, scan=True, min_width=min_width,
                                    min_events=int(min_events), n_boot=n_boot, seed=seed,
                                    levels=(level, slope_level))  # fmt: skip
        if p_ks >= level and not p_knee < slope_level:
            return lo, hi, ks, p_ks, p_knee, True
    if drawn:  # the widest range drawn, which failed
        return *drawn[0], nan, nan, False
    _, lo, hi, d, ks, _, _ = min(ranges, key=lambda r: r[4])
    return lo, hi, ks, nan, nan, False


def block_length(x: npt.ArrayLike) -> int:
    """Return the block length of a circular block bootstrap of the mean of the series ``x``.

    The rule of Politis and White (2004) with the correction of Patton,
    Politis and White (2009): the autocovariances up to twice the first lag
    ``m`` from which ``K_N = max(5, sqrt(log10 n))`` successive
    autocorrelations (lags ``m`` to ``m + K_N - 1``, as in Patton's code and
    the ``arch`` package) are all insignificant (below ``2 sqrt(log10(n) / n)``),
    weighted by the flat-top window, give the block length ``(2 G**2 /
    D)**(1/3) n**(1/3)`` that minimises the error of the variance estimate.
    Without a run of insignificant lags, the window reaches ``m_max =
    ceil(sqrt(n)) + K_N``; the length is at most ``min(3 sqrt(n), n / 3)``,
    as in the ``arch`` package's ``optimal_block_length``. Independent values
    give 1 (rounded up from a fraction); a series that repeats each value
    ``r`` times gives about ``r`` or more.

    Parameters
    ----------
    x : array of float
        The series in its order (a catalogue's magnitudes in time order).

    Returns
    -------
    int
        Values per block, at least 1 (1 for fewer than 8 values or a constant
        series).

    """
    xs = _floats("x", x)
    n = xs.size
    if n < 8:
        return 1
    d = xs - xs.mean()
    k_n = max(5, math.ceil(math.sqrt(math.log10(n))))
    m_max = min(math.ceil(math.sqrt(n)) + k_n, n - 1)
    # autocovariances up to m_max by FFT (zero-padded: not circular)
    size = 1 << int(2 * n - 1).bit_length()
    f = np.fft.rfft(d, size)
    acov = np.fft.irfft(f * np.conj(f), size)[: m_max + 1] / n
    if not acov[0] > 0.0:  # a constant series
        return 1
    small = np.abs(acov[1:] / acov[0]) < 2.0 * math.sqrt(math.log10(n) / n)  # small[k - 1]: lag k
    # the first m >= 1 with lags m .. m + K_N - 1 insignificant, as in Patton's code and arch's
    m_hat = next((m for m in range(1, m_max - k_n + 1) if small[m - 1 : m - 1 + k_n].all()), None)
    big_m = m_max if m_hat is None else min(2 * m_hat, m_max)
    k = np.arange(1, big_m + 1)
    t = k / big_m
    window = np.where(t <= 0.5, 1.0, 2.0 * (1.0 - t))
    g_big = 2.0 * float(np.sum(window * k * acov[1 : big_m + 1]))
    g0 = float(acov[0] + 2.0 * np.sum(window * acov[1 : big_m + 1]))
    d_cb = 4.0 / 3.0 * g0 * g0
    if not d_cb > 0.0:
        return 1
    length = (2.0 * g_big * g_big / d_cb) ** (1.0 / 3.0) * n ** (1.0 / 3.0)
    return int(min(max(math.ceil(length), 1), _longest_block(n)))


def _longest_block(n: int) -> int:
    """Return the longest block of ``n`` values, ``min(3 sqrt(n), n / 3)`` (three blocks at least)."""
    return math.ceil(min(3.0 * math.sqrt(n), n / 3.0))


def b_value(
    m: npt.ArrayLike,
    mc: float | str | None = None,
    m_max: float | None = None,
    *,
    n_boot: int = 200,
    seed: int | None = 0,
    bin_width: float = 0.1,
    block: int | str = 1,
) -> BValue:
    """Fit the b-value of magnitudes ``m`` above ``mc`` (and below ``m_max``) by maximum likelihood.

    Parameters
    ----------
    m : array of float
        Magnitudes (``log10`` moment); non-finite ones are skipped.
    mc : float or "auto", optional
        Completeness magnitude; default :func:`completeness_magnitude` (maximum
        curvature). ``"auto"``: the range of the power law by
        :func:`power_law_range`, both ends (the lower only where ``m_max`` is given):
        the lower end by the least KS distance, tested by KS (bootstrap, ``n_boot``
        samples, ``seed``) and one slope against two at 10 %; where no range passes,
        ``b`` is nan (not a power law over a decade of moment) and ``verdict`` says why.
        For a range given or by maximum curvature, ``b`` is fitted whatever the tests say,
        and ``power_law`` and ``verdict`` tell.
    m_max : float, optional
        Upper end of the fit (the power law of small events, below a bump of
        large ones); default none.
    n_boot : int
        Bootstrap resamples for the error, and samples of the KS test's parametric bootstrap
        (``ks_p``; 0: none, error and ``ks_p`` nan, KS judged by Stephens' 10 % value; else
        at least 2).
    seed : int, optional
        Seed of the bootstrap.
    block : int or "auto"
        Events per block of the bootstrap. 1: the events in the range are
        resampled one by one, which assumes they are independent. ``L > 1``:
        the circular block bootstrap, runs of ``L`` successive events in the
        range (``m`` must then be in time order), which keeps the correlation
        of successive events in the error; ``L`` is held to at most
        ``min(3 sqrt(n), n / 3)`` of the ``n`` events (``BValue.block`` says
        what was used). ``"auto"``: ``L`` by
        :func:`block_length` of the magnitudes in the range.
    bin_width : float
        Magnitude bins of the completeness estimate and grid of the range scan.
        Magnitudes spread over less than a bin give no fit (``b`` nan).

    """
    mm = _floats("m", m)
    if mm.ndim != 1:  # a 2-D array was flattened, its rows' time order lost to the block bootstrap
        raise ValueError(f"m: magnitudes of shape {mm.shape}; expected one catalogue, a 1-D array")
    mm = mm[np.isfinite(mm)]
    n_boot = check_count(n_boot, "n_boot", minimum=0, what="a whole number of bootstrap resamples")
    if n_boot == 1:  # one resample has no spread
        raise ValueError("n_boot=1: expected 0 (no error) or at least 2 bootstrap resamples")
    seed = check_seed(seed)
    bin_width = _bin_width(bin_width)
    blocks = f"block={block!r}: expected a whole number of events >= 1 or 'auto'"
    if isinstance(block, str):
        if block != "auto":
            raise ValueError(blocks)
    elif isinstance(block, bool) or not isinstance(block, (int, np.integer)):
        raise ArgumentTypeError(blocks)
    elif block < 1:
        raise ValueError(blocks)
    mc, m_max = check_fit_range(mc, m_max)
    found: tuple[float, float, float, float, float, bool] | None = None
    if isinstance(mc, str):
        found = _scan(mm, m_max, bin_width, MIN_SPAN, MIN_EVENTS, GOF_LEVEL, GOF_LEVEL, n_boot, seed)
        method = "power-law range"
        if found is None:  # no range of a magnitude unit holds enough events to test
            top = math.inf if m_max is None else float(m_max)
            return BValue(math.nan, math.nan, math.nan, math.nan, top, 0, math.nan, method=method)
        mc_, top = found[0], found[1]
    else:
        method = "maximum curvature" if mc is None else "given"
        mc_ = completeness_magnitude(mm, bin_width) if mc is None else float(mc)
        top = math.inf if m_max is None else float(m_max)
    in_order = mm[(mm >= mc_) & (mm <= top)]  # the events of the range, in the catalogue's order
    sel = np.sort(in_order)
    n = int(sel.size)
    # magnitudes that do not spread over a bin (identical events: one block, identical blocks)
    # say nothing of a power law; their "b" would be 1/(bin-level gap above mc), with no error
    if n < 2 or not math.isfinite(mc_) or sel[-1] - sel[0] < bin_width:
        return BValue(math.nan, math.nan, math.nan, mc_, top, n, math.nan, math.nan, method)
    b = _mle(sel, mc_, top)
    ks = _ks(sel, mc_, top, b)
    span = float(sel[-1]) - mc_
    ordered = np.sort(mm)
    edges = _grid(ordered, bin_width)
    knee = _knee(sel, mc_, top, edges)
    if found is not None and found[5]:  # the range passed the scan's tests: their p-values
        ks_p, slope_p = found[3], found[4]
    elif n_boot > 0 and math.isfinite(b):
        d = _distance(sel, mc_, top, b * math.log(10.0))
        ks_p, slope_p = _gof_pvalues(ordered, mc_, top, d, knee.ratio, edges=edges, scan=found is not None,
                                     min_width=MIN_SPAN, min_events=MIN_EVENTS, n_boot=n_boot,
                                     seed=seed)  # fmt: skip
    else:
        ks_p, slope_p = math.nan, _knee_p(knee)
    tests = (knee.b_lower, knee.b_upper, knee.cut, slope_p, ks_p, span, knee.n_upper)
    if found is not None and not found[5]:  # no range passes: no b-value, the range reported described
        return BValue(math.nan, math.nan, math.nan, mc_, top, n, math.nan, ks, method, 1, *tests)
    # Shi and Bolt's formula is for the untruncated exponential: under an upper bound it
    # covered the true b 74-77 % of the time at 1.96 sigma (chains audit), the bootstrap 96 %
    untruncated = math.isfinite(b) and math.isinf(top)
    shi = math.log(10.0) * b * b * float(np.std(sel, ddof=1)) / math.sqrt(n) if untruncated else math.nan
    # a block near n resamples rotations of the catalogue, all with its mean: an error of 0;
    # a given block is held to the longest of "auto" (at least three blocks)
    length = block_length(in_order) if block == "auto" else min(int(block), _longest_block(n))
    err = math.nan
    if n_boot > 0:  # event by event: the sorted events, as before blocks (the same draws for a seed)
        err = _bootstrap_error(sel if length <= 1 else in_order, mc_, top, length, n_boot, seed)
    a = math.log10(n) + b * mc_ if math.isfinite(b) else math.nan
    return BValue(float(b), err, shi, mc_, top, n, a, ks, method, length, *tests)


def _bootstrap_error(
    x: FloatArray, mc: float, top: float, length: int, n_boot: int, seed: int | None
) -> float:
    """Return the b-value's standard deviation over circular block bootstrap resamples of ``x``.

    ``length`` 1: the events one by one (independent draws).
    """
    rng = np.random.default_rng(seed)
    n = x.size
    if length <= 1:
        boots = [_mle(rng.choice(x, n), mc, top) for _ in range(n_boot)]
    else:
        blocks = -(-n // length)
        run = np.arange(length)
        boots = []
        for _ in range(n_boot):
            idx = ((rng.integers(0, n, blocks)[:, None] + run) % n).ravel()[:n]
            boots.append(_mle(x[idx], mc, top))
    return float(np.nanstd(boots, ddof=1))


def recurrence_times(t_start: npt.ArrayLike) -> FloatArray:
    """Return the times between successive event starts (in the order of a catalogue: increasing)."""
    dt = np.diff(_floats("t_start", t_start))
    if np.any(dt < 0):  # unsorted starts gave negative recurrence times
        i = int(np.flatnonzero(dt < 0)[0]) + 1
        raise ValueError(f"t_start[{i}]: the event starts are not in increasing order (as in a catalogue)")
    return dt


def ruptures_in_pieces(
    n_blocks: npt.ArrayLike,
    first_block: npt.ArrayLike,
    last_block: npt.ArrayLike,
    slips: npt.ArrayLike | None = None,
    *,
    periodic: bool = False,
) -> tuple[int, int]:
    """Count the events whose slipping blocks are not one connected stretch of the chain.

    An event runs from one moment when every block sticks to the next. On a long
    chain that moment is rare, and slips far apart, unrelated ruptures, fall into one
    event (the chain audit: 764 of 1500 events of 100 Carlson-Langer blocks; one of
    12 blocks spread from block 2 to block 992 on 1000). Carlson and Langer count
    connected clusters instead; a magnitude-frequency law of such events is not theirs.

    Parameters
    ----------
    n_blocks, first_block, last_block : array_like
        The catalogue's columns: blocks that slipped and their extent.
    slips : array_like, optional
        ``slip(recorded_event, block)`` of the first events (NaN rows unrecorded);
        needed on a periodic chain, where the extent does not tell a stretch across
        the ends from two pieces.
    periodic : bool, optional
        The chain's ends are joined.

    Returns
    -------
    (int, int)
        Events in pieces, and events checked (all on a free chain; the recorded ones
        on a periodic chain).

    """
    nb = np.asarray(n_blocks, dtype=np.int64)
    if not periodic:
        span = np.asarray(last_block, dtype=np.int64) - np.asarray(first_block, dtype=np.int64) + 1
        return int(np.count_nonzero(nb < span)), int(nb.size)
    if slips is None:
        return 0, 0
    rows = np.asarray(slips, dtype=float)
    rows = rows[np.all(np.isfinite(rows), axis=1)] if rows.ndim == 2 else np.empty((0, 0))
    moved = rows != 0.0
    # pieces on a ring: the places where a stuck block is followed by a slipping one
    starts = np.count_nonzero(moved & ~np.roll(moved, 1, axis=1), axis=1)
    return int(np.count_nonzero(starts > 1)), int(rows.shape[0])


class Ruptures(NamedTuple):
    """The connected ruptures of events (:func:`connected_ruptures`), one entry per rupture.

    Attributes
    ----------
    event : ndarray of int
        The event (row of the slips) each rupture belongs to; ruptures in event order, then
        by their first block.
    first_block, last_block : ndarray of int
        The rupture's ends (0-based); on a ring a rupture across the ends has
        ``last_block < first_block``.
    n_blocks : ndarray of int
        Blocks that slipped in the rupture.
    moment : ndarray of float
        Sum of its blocks' slips.

    """

    event: npt.NDArray[np.int64]
    first_block: npt.NDArray[np.int64]
    last_block: npt.NDArray[np.int64]
    n_blocks: npt.NDArray[np.int64]
    moment: FloatArray


def connected_ruptures(slips: npt.ArrayLike, *, periodic: bool = False) -> Ruptures:
    """Split events into connected ruptures: each run of neighbouring blocks that slipped.

    Carlson and Langer (1989) count an event as a connected cluster of slipping blocks;
    an event of a chain (from all stuck to all stuck) may hold several, separated by
    blocks that never slipped, and on a long chain at a fast drive it often does (5 168 of
    10 000 events of 100 Carlson-Langer blocks at ``nu = 0.01``, ``ell = 10``). Each run is one
    rupture here, with its own moment (the sum of its blocks' slips) and block count.
    A block slipped where its slip is not zero. The split is by place only: a run
    that slipped twice in one event (a rupture, then another over the same blocks)
    stays one rupture.

    Parameters
    ----------
    slips : array_like, shape (events, blocks)
        Each block's slip in each event (the catalogue's ``slip``); every value finite.
    periodic : bool, optional
        The chain's ends are joined: a run through the last block and the first is one.

    Returns
    -------
    Ruptures

    """
    s = _floats("slips", slips)
    if s.ndim != 2:
        raise ValueError(f"slips: shape {s.shape}; expected (events, blocks), each block's slip per event")
    if not np.isfinite(s).all():
        row = int(np.flatnonzero(~np.isfinite(s).all(axis=1))[0])
        raise ValueError(
            f"slips[{row}]: not finite (an event whose slips were not recorded); expected finite slips"
        )
    e, n = s.shape
    moved = s != 0.0
    edges = np.diff(np.pad(moved, ((0, 0), (1, 1))).astype(np.int8), axis=1)
    event, first = np.nonzero(edges == 1)  # row by row, left to right
    _, end = np.nonzero(edges == -1)  # one past each run's last block, in the same order
    # a run's slips and the zeros up to the next run's start sum to its moment exactly
    starts = event * n + first
    moment = np.add.reduceat(s.ravel(), starts) if starts.size else np.zeros(0)
    count = end - first
    last = end - 1
    if periodic and n > 1 and e:
        # a row that slipped at both ends, not everywhere: its last run continues into its first
        wrap = moved[:, 0] & moved[:, -1] & ~moved.all(axis=1)
        rows = np.flatnonzero(wrap)
        if rows.size:
            head = np.searchsorted(event, rows, "left")  # each such row's first run (at block 0)
            tail = np.searchsorted(event, rows, "right") - 1  # and its last (to block n - 1)
            count[tail] += count[head]
            moment[tail] += moment[head]
            last[tail] = last[head]
            keep = np.ones(event.size, dtype=bool)
            keep[head] = False
            event, first, last, count, moment = (
                event[keep],
                first[keep],
                last[keep],
                count[keep],
                moment[keep],
            )
    i8 = np.int64
    return Ruptures(
        event.astype(i8), first.astype(i8), last.astype(i8), count.astype(i8), moment.astype(float)
    )
