"""Bifurcation analysis: the branches of steady states and periodic orbits, and the regimes.

:mod:`~stickslip.bifurcation.regimes` (every branch over a range of ``nu`` and the
intervals of each set of attractors, checked by direct simulation), assembled from
:mod:`~stickslip.bifurcation.branches` (the branch, interval and diagram types),
:mod:`~stickslip.bifurcation.continuation` (the pure-slip branches born at Hopf points)
and :mod:`~stickslip.bifurcation.probes` (the stick-slip branch and the attractors the
engine reaches); :mod:`~stickslip.bifurcation.regime_map` (two-parameter maps and the
criterion on trial) and :mod:`~stickslip.bifurcation.averaging` (Thomsen and Fidlin's
closed forms). Steady sliding's stability, the periodic orbits and the polish of
attractors are one layer down, in :mod:`stickslip.orbits`, shared with
:mod:`stickslip.dynamics`, which sits beside this package and imports nothing of it
(:mod:`~stickslip.bifurcation.stability` and :mod:`~stickslip.bifurcation.orbits` name
them here too).
"""
