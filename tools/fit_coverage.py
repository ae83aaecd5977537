"""Coverage of `stickslip fit` on records from the independent SciPy generator (tests/reference/one_block.py).

Usage: python tools/fit_coverage.py FIRST_SEED LAST_SEED [RATE_HZ [NOISE_N]]

For each seed, 60 periods of the zv set-up at 100 um/s (default 1 kHz, 1 mN noise),
starting 0.137 * seed periods (mod 1) after a breakaway, are made by
`reference_record` and fitted; prints the reduced chi-square and the pull
(estimate - truth) / error of each parameter, then their mean, spread and how many
fall within 2 errors.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from reference.one_block import reference_record

import stickslip as S
from stickslip.data.fitting import fit_record
from stickslip.io.records import Record

MASS = float(S.zv_parameters().mass.to("kg").magnitude)
TRUTH = {"mu_s": 0.46, "a": 160.0, "k": 62.0, "m": MASS}


def main(first: int, last: int, rate: float = 1000.0, noise: float = 1e-3) -> None:
    pulls: dict[str, list[float]] = {k: [] for k in TRUTH}
    for seed in range(first, last):
        t, f = reference_record(
            mu0=0.46,
            a=160.0,
            b=0.0,
            k=62.0,
            m=MASS,
            load=0.196,
            v0=1e-4,
            periods=60,
            rate=rate,
            noise=noise,
            seed=seed,
            phase=(0.137 * seed) % 1.0,
        )
        res = fit_record(Record(f"seed {seed}", t, f, None, None, S.Q_(100, "um/s"), S.Q_(196, "mN"), {}))
        for k, truth in TRUTH.items():
            pulls[k].append((res.values[k] - truth) / res.errors[k])
        shown = " ".join(f"{k} {pulls[k][-1]:+.2f}" for k in TRUTH)
        print(f"{seed} reduced chi2 {res.reduced_chi2:.4f} {shown} {list(res.warnings)}", flush=True)
    for k, values in pulls.items():
        p = np.array(values)
        within = int(np.sum(np.abs(p) <= 2))
        print(f"{k}: mean {p.mean():+.2f}, spread {p.std():.2f}, within 2 errors {within}/{p.size}")


if __name__ == "__main__":
    main(int(sys.argv[1]), int(sys.argv[2]), *(float(x) for x in sys.argv[3:5]))
