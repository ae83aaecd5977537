"""Check `regimes` against direct simulation on random laws (a wider run than the test suite's).

Usage: python tools/check_regimes_random.py SEED N

For N random laws (cubic with alpha 0.01-1.5 and gamma 0.01-3, negative friction
included; weakening with c 0.3-50 and p/c 0.005-0.9; F1 with c 0.3-50), computes the
regime diagram and confirms every interval by direct simulation from several starts
(`confirm`), counting distinct attractors. Prints each disagreement and a summary.
"""

from __future__ import annotations

import math
import sys
import time
import warnings

import numpy as np

from stickslip import CubicLaw, WeakeningLaw
from stickslip.bifurcation.regimes import confirm, regimes


def main(seed: int, n: int) -> int:
    warnings.simplefilter("ignore", UserWarning)  # negative cubic friction, on purpose
    rng = np.random.default_rng(seed)
    bad = 0
    t0 = time.perf_counter()
    for i in range(n):
        kind = i % 3
        if kind == 0:
            g = float(np.exp(rng.uniform(np.log(0.01), np.log(3))))
            a = float(np.exp(rng.uniform(np.log(0.01), np.log(1.5))))
            law = CubicLaw(alpha=a, gamma=g)
            nh = math.sqrt(a / (3 * g))
            lo, hi = nh / 20, 4 * nh
        elif kind == 1:
            c = float(np.exp(rng.uniform(np.log(0.3), np.log(50))))
            p = float(np.exp(rng.uniform(np.log(0.005 * c), np.log(0.9 * c))))
            law = WeakeningLaw(c=c, p=p)
            nh = (math.sqrt(c / p) - 1) / c
            lo, hi = nh / 20, 4 * nh
        else:
            law = WeakeningLaw(c=float(np.exp(rng.uniform(np.log(0.3), np.log(50)))))
            lo, hi = 0.01, 8.0
        d = regimes(law, lo, hi, n_grid=101)
        checks = confirm(d)
        if not all(c.agree for c in checks):
            bad += 1
            print(law, [(iv.regime, round(iv.nu_min, 5), iv.attractors) for iv in d.intervals])
            for c in checks:
                if not c.agree:
                    print("   expected", c.expected, "found", c.found, "at nu", c.nu)
    print(f"seed {seed}: {n} laws, {bad} disagreements, {time.perf_counter() - t0:.1f} s")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(int(sys.argv[1]), int(sys.argv[2])))
