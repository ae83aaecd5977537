"""Solver defaults, in one place.

Every public function that integrates takes these as keyword defaults; change
them here, not at the call sites.
"""

from __future__ import annotations

#: relative tolerance of the slip-phase integration (on spring force and velocity)
RTOL = 1e-10
#: absolute tolerance (units of static friction and of ``mu_s W / sqrt(k m)``)
ATOL = 1e-12
#: longest slip time integrated while looking for an attractor (units of sqrt(m/k))
MAX_SLIP_TIME = 1e5
#: relative change of the amplitude between oscillations at which a transient counts as converged
CONV_TOL = 1e-8
#: largest number of steps of one slip phase
MAX_STEPS = 2_000_000
#: perturbation of steady sliding (units of static friction) used to probe its basin
STEADY_PERTURBATION = 1e-3
#: relative accuracy promised for the measures of a steady oscillation (amplitude, period); a
#: non-sticking orbit whose estimated error is larger is reported as not converged
ORBIT_RTOL = 1e-8
