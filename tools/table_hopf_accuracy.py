"""How far a tabulated F2 puts the Hopf point, by interpolation and row layout (docs/laws.md).

Run: ``.venv/bin/python tools/table_hopf_accuracy.py``. F2 (c = 3.8, p = 0.5, beta = 1 s/m)
is tabulated at log-spaced rows from 1e-3 m/s to 10 or 20 m/s plus v = 0; the table's Hopf
point is compared with F2's own. The error is the interpolant's near nu_H, so it depends on
where rows fall, not only on how many there are.
"""

from __future__ import annotations

import warnings

import numpy as np

import stickslip as ss
from stickslip.laws.table import TabulatedLaw
from stickslip.orbits.stability import hopf_points


def main() -> None:
    f2 = ss.WeakeningLaw(c=3.8, p=0.5)
    (exact,) = hopf_points(f2, 0.01, 10.0)
    print(f"F2: nu_H = {exact.nu:.10f} ({exact.criticality})")
    print("interpolation  rows  top [m/s]  |nu_H - F2's|  type")
    for interpolation in ("pchip", "cubic"):
        for top in (10.0, 20.0):
            for rows in (32, 64, 128, 256):
                w = np.concatenate([[0.0], np.geomspace(1e-3, top, rows)])
                mu = np.asarray(f2.forward(w), dtype=float)
                mu[0] = 1.0
                law = TabulatedLaw(ss.Q_(w, "m/s"), mu, interpolation=interpolation)
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")  # pchip's "on a row" notes
                    (h,) = hopf_points(law.nondimensionalize("1 s/m"), 0.01, 10.0)
                off = abs(h.nu - exact.nu)
                print(f"{interpolation:13s}  {rows:4d}  {top:9g}  {off:13.2g}  {h.criticality}")


if __name__ == "__main__":
    main()
