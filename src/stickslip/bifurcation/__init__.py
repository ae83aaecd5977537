"""Bifurcation analysis: steady sliding and its stability, periodic orbits, regimes.

:mod:`~stickslip.bifurcation.stability` (Hopf points and their criticality),
:mod:`~stickslip.bifurcation.orbits` (pure-slip and stick-slip periodic orbits
with Floquet multipliers), :mod:`~stickslip.bifurcation.attractors` (an attractor
polished into its orbit, and orbit identity), :mod:`~stickslip.bifurcation.regimes`
(continuation of every branch and the intervals of each attractor),
:mod:`~stickslip.bifurcation.regime_map` (two-parameter maps and the criterion
on trial) and :mod:`~stickslip.bifurcation.averaging` (Thomsen and Fidlin's closed
forms).
"""
