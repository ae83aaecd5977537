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

from typing import TYPE_CHECKING

from ..lazy import exports

if TYPE_CHECKING:  # loaded on first use by __getattr__
    from .cycles import SpringSliderFault, earthquake_cycles
    from .fitting import RateStateFit, fit_rate_state
    from .inertia import BautinPoint, InertialSlider
    from .model import RateStateParameters
    from .protocols import linear_stability, simulate_rate_state, slide_hold_slide, velocity_steps

_HOME = {
    "RateStateParameters": "model",
    "linear_stability": "protocols",
    "simulate_rate_state": "protocols",
    "slide_hold_slide": "protocols",
    "velocity_steps": "protocols",
    "RateStateFit": "fitting",
    "fit_rate_state": "fitting",
    "SpringSliderFault": "cycles",
    "earthquake_cycles": "cycles",
    "InertialSlider": "inertia",
    "BautinPoint": "inertia",
}


__getattr__, __dir__ = exports(__name__, _HOME)

__all__ = [
    "BautinPoint",
    "InertialSlider",
    "RateStateFit",
    "RateStateParameters",
    "SpringSliderFault",
    "earthquake_cycles",
    "fit_rate_state",
    "linear_stability",
    "simulate_rate_state",
    "slide_hold_slide",
    "velocity_steps",
]
