"""Earthquake statistics of an event catalogue: Gutenberg-Richter b-value, its range, recurrence, ruptures.

Magnitudes here are ``log10`` of the moment (sum of the blocks' slips), as in the
catalogue; a seismological moment magnitude ``M_w = (2/3) log10 M_0 + const``
has a b-value 3/2 times this one.

* b-value by maximum likelihood (:func:`b_value`): Aki (1965), ``b = log10(e) / (mean(M) - M_c)``
  for continuous magnitudes above the completeness ``M_c``; with an upper
  bound ``M_max`` the likelihood of the doubly truncated exponential (Page
  1968) is maximised instead. Its error by bootstrap beside the Shi and Bolt
  (1982) formula. Successive events of a chain are not independent (a large
  event unloads the chain, small ones follow), and resampling them one by one
  understates the error; ``block="auto"`` resamples runs of successive events
  (the circular block bootstrap, Politis and Romano 1992) of a length chosen
  from the magnitudes' autocorrelation (Politis and White 2004, corrected by
  Patton, Politis and White 2009).
* Completeness ``M_c`` and the magnitude-frequency counts: :mod:`.magnitudes`.
* The range of the power law, ``mc="auto"``: :func:`~.powerlaw.power_law_range`
  (:mod:`.powerlaw`); where no range passes, ``b`` is nan and ``verdict`` says why
  the widest range tested failed.
* Connected ruptures and events in pieces: :mod:`.ruptures`.

Every name of :mod:`.magnitudes`, :mod:`.powerlaw` and :mod:`.ruptures` that is imported
from here stays importable from here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from ..core.checks import finite
from ..errors import ArgumentTypeError
from ..units import check_count, check_seed
from .magnitudes import LOG10E as LOG10E
from .magnitudes import FloatArray, _bin_width, _floats, _mle, completeness_magnitude, magnitude_frequency
from .powerlaw import (
    GOF_LEVEL,
    KS_CRITICAL_10,
    MAX_DRAWN,
    MIN_EVENTS,
    MIN_SPAN,
    _distance,
    _gof_pvalues,
    _grid,
    _knee,
    _knee_p,
    _ks,
    _scan,
    power_law_range,
    slope_change,
)
from .powerlaw import KS_CRITICAL_5 as KS_CRITICAL_5
from .powerlaw import MIN_PART as MIN_PART
from .powerlaw import SLOPE_CHANGE_LEVEL as SLOPE_CHANGE_LEVEL
from .ruptures import Ruptures, connected_ruptures, ruptures_in_pieces

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
        mc = finite("mc", mc, what="a finite magnitude, 'auto' or None (maximum curvature)")
    if m_max is not None:
        m_max = finite("m_max", m_max, what=f"a finite magnitude above mc={mc!r}, or None")
        if isinstance(mc, float) and not m_max > mc:
            raise ValueError(f"m_max={m_max!r}: expected a finite magnitude above mc={mc!r}")
    return mc, m_max


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
    # Shi and Bolt's formula is for the untruncated exponential: under an upper bound it covers
    # the true b 74-77 % of the time at 1.96 sigma (measured on chains), the bootstrap 96 %
    untruncated = math.isfinite(b) and math.isinf(top)
    shi = math.log(10.0) * b * b * float(np.std(sel, ddof=1)) / math.sqrt(n) if untruncated else math.nan
    # a block near n resamples rotations of the catalogue, all with its mean: an error of 0;
    # a given block is held to the longest of "auto" (at least three blocks)
    length = block_length(in_order) if block == "auto" else min(int(block), _longest_block(n))
    err = math.nan
    if n_boot > 0:  # event by event: the sorted events (a seed's error does not depend on their order)
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
