"""Bifurcation analysis: steady sliding and its stability, periodic orbits, regimes.

:mod:`~stickslip.bifurcation.stability` (Hopf points and their criticality),
:mod:`~stickslip.bifurcation.orbits` (pure-slip and stick-slip periodic orbits
with Floquet multipliers), :mod:`~stickslip.bifurcation.regimes`
(continuation of every branch and the intervals of each attractor),
:mod:`~stickslip.bifurcation.regime_map` (two-parameter maps and the criterion
on trial) and :mod:`~stickslip.bifurcation.averaging` (Thomsen and Fidlin's closed
forms). The attractors of the basic operations, polished into their orbits, and the
return map of non-sticking orbits are one layer down, in :mod:`stickslip.dynamics`.
"""
