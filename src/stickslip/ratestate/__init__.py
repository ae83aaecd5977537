"""Rate-and-state friction: the Rice-Ruina model, laboratory protocols, Dulac's criterion.

:mod:`~stickslip.ratestate.model` (parameters with units),
:mod:`~stickslip.ratestate.protocols` (velocity steps, slide-hold-slide,
simulations and linear stability), driving the compiled kernels of
:mod:`stickslip.core.ratestate` and :mod:`stickslip.core.radau` through
:mod:`~stickslip.ratestate.solvers` and writing a run's dataset with
:mod:`~stickslip.ratestate.series`; :mod:`~stickslip.ratestate.fitting` (fits to
laboratory records), :mod:`~stickslip.ratestate.cycles` (earthquake cycles on a
spring-slider), :mod:`~stickslip.ratestate.statelaw` (a state law from a formula) and
:mod:`~stickslip.ratestate.dulac` (the paper's appendix, derived with sympy).
"""
