"""The noise of a sampled signal, from its second differences (numbers only)."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

__all__ = ["noise_level"]


def noise_level(y: npt.NDArray[np.float64]) -> float:
    """Return the standard deviation of white noise on a sampled signal, from its second differences.

    The second differences of a smooth signal (a ramp, a slow decay) nearly vanish:
    the median absolute deviation of ``y[i+1] - 2 y[i] + y[i-1]`` is the noise's times
    ``sqrt(6)``, robust to the few samples where the signal itself turns fast. (First
    differences would also carry the signal's slope.) NaN for fewer than three samples.
    """
    d = np.diff(np.asarray(y, dtype=float), 2)
    if d.size == 0:
        return math.nan
    return float(1.4826 * np.median(np.abs(d - np.median(d))) / math.sqrt(6.0))
