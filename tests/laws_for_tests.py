"""A law registered by the tests only: it proves that one module is all a new law needs.

The Stribeck curve with viscous friction, ``f(w) = kin + (1 - kin) exp(-w/ws) + eta w``:
friction falls from the static level to ``kin`` over the velocity ``ws`` and rises again
with ``eta``. Three parameters (the built-in laws have one or two), a physical form with
three physical parameters, and an analytic Hopf point, ``f'(nu) = 0`` at
``nu = ws ln((1 - kin) / (ws eta))``.
"""

from __future__ import annotations

from stickslip.laws import LawSpec, Parameter, register

STRIBECK = LawSpec(
    name="stribeck",
    title="Stribeck curve with viscous friction (a law of the tests)",
    f="kin + (1 - kin)*exp(-w/ws) + eta*w",
    parameters=(
        Parameter("kin", "kinetic level at high velocity, in units of static friction", upper=1.0),
        Parameter("ws", "Stribeck velocity ws = v_s beta"),
        Parameter("eta", "viscous coefficient eta = visc/(mu_s beta)", lower_inclusive=True, default=0.0),
    ),
    physical=(
        Parameter("mu_k", "kinetic coefficient (high velocity)"),
        Parameter("v_s", "Stribeck velocity", unit="m/s", example="100 um/s"),
        Parameter(
            "visc", "viscous coefficient", unit="s/m", example="10 s/m", lower_inclusive=True, default=0.0
        ),
    ),
    to_dimensionless={"kin": "mu_k/mu_s", "ws": "v_s*beta", "eta": "visc/(mu_s*beta)"},
    source="the test suite",
    example={"kin": 0.5, "ws": 0.2, "eta": 0.05},
)
ENTRY = register(STRIBECK)
StribeckLaw = ENTRY.dimensionless_class
PhysicalStribeckLaw = ENTRY.physical_class
