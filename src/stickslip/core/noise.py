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

    A quantized signal (steps about as coarse as the noise, or coarser) gets the root
    mean square of its second differences over ``sqrt(6)`` instead, and at least the
    rounding error's ``step / sqrt(12)``.
    """
    y = np.asarray(y, dtype=float)
    d = np.diff(y, 2)
    if d.size == 0:
        return math.nan
    mad = float(np.median(np.abs(d - np.median(d))))
    # nonzero beyond rounding (values read from text, or rescaled, are multiples of a step only
    # to within a few units in the last place)
    rounding = 64.0 * np.finfo(float).eps * float(np.max(np.abs(y)))
    steps = np.abs(d[np.abs(d) > rounding])
    if steps.size and mad <= 2.5 * float(steps.min()):
        # quantized (an ADC's steps about as coarse as its noise, or coarser): the second
        # differences take a few values, multiples of the step, and their median deviation
        # jumps between them (0 with 0.3 mN of noise in 1 mN steps when half are zero, 45% high
        # when a few less are); their root mean square does not, with the largest 1% (the
        # signal's own fast turns) left out. Far below the step (a slow ramp quantized with
        # little noise) the second differences are mostly 0 and their RMS falls short (0.2 of
        # the residual from a smooth signal at 0.01 step per sample); the rounding error itself,
        # uniform over a step, is at least step / sqrt(12)
        # the signal's turns are left out by clipping at 4 of the kept ones' deviations until
        # none is left (leaving out the largest 1% alone keeps a fast record's drops: 1.98 mN
        # for 0.41 at 136 samples a cycle); white noise loses 6e-5 of its samples
        kept = d
        for _ in range(50):
            within = kept[np.abs(kept) <= 4.0 * math.sqrt(float(np.mean(kept**2)))]
            if within.size == kept.size or within.size == 0:
                break
            kept = within
        rms = math.sqrt(float(np.mean(kept**2)) / 6.0)
        return float(max(rms, float(steps.min()) / math.sqrt(12.0)))
    return float(1.4826 * mad / math.sqrt(6.0))
