"""Orbits: steady sliding and its stability, periodic orbits, and attractors polished into them.

The layer under both :mod:`stickslip.dynamics` (the motion from given starts, sweeps) and
:mod:`stickslip.bifurcation` (continuation, regimes), which build on it side by side:

* :mod:`~stickslip.orbits.stability`: the eigenvalues of steady sliding, its Hopf points
  and their criticality, the averaged amplitude of the small cycle;
* :mod:`~stickslip.orbits.periodic`: the pure-slip orbit by Newton shooting and the
  stick-slip orbit through breakaway with saltation matrices, with Floquet multipliers;
* :mod:`~stickslip.orbits.return_map`: non-sticking orbits (slip reversal too) as fixed
  points of the return map on ``w = nu``, computed by the exact non-smooth engine;
* :mod:`~stickslip.orbits.attractors`: what identifies an attractor (its kind and orbit),
  and the polish of the engine's rows into periodic orbits.
"""
