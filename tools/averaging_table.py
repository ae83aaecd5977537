"""Print the Thomsen-Fidlin averaging table of docs/regimes.md (markdown).

Usage::

    python tools/averaging_table.py
"""

from __future__ import annotations

from stickslip.bifurcation.averaging import averaging_table


def main() -> None:
    rows = averaging_table((1.0, 0.5, 0.25, 0.125, 0.0625, 0.03125))
    print(
        "| eps | alpha | gamma | nu_H numeric | nu_H formula | border numeric | border formula "
        "| rel. error | nu | amplitude numeric | amplitude formula | rel. error |"
    )
    print("|" + "---|" * 12)
    for r in rows:
        print(
            f"| {r.eps:g} | {r.alpha:.6g} | {r.gamma:.6g} | {r.nu_hopf:.12f} | {r.nu_hopf_formula:.12f} "
            f"| {r.nu_border:.10f} | {r.nu_border_formula:.10f} | {r.border_error:.2e} | {r.nu:.6f} "
            f"| {r.amplitude:.10f} | {r.amplitude_formula:.10f} | {r.amplitude_error:.2e} |"
        )


if __name__ == "__main__":
    main()
