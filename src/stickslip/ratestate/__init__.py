"""Rate-and-state friction: the Rice-Ruina model, laboratory protocols, Dulac's criterion.

:mod:`~stickslip.ratestate.model` (parameters with units),
:mod:`~stickslip.ratestate.protocols` (velocity steps, slide-hold-slide,
simulations and linear stability; the compiled kernels are in
:mod:`stickslip.core.ratestate`) and :mod:`~stickslip.ratestate.dulac` (the
paper's appendix, derived with sympy).
"""
