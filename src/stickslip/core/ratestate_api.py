"""The rate-and-state engine's face: what the rate-and-state family calls and the inputs it builds.

The engine's kernels live in :mod:`~stickslip.core.ratestate` (the quasi-static
integrator, the inertial right-hand side and Jacobian, the friction and the slip
rate, the state-law programs) and :mod:`~stickslip.core.radau` (the Radau IIA
integrator of the inertial slider). Above the core they are reached through this
module only (an import-linter contract): the functions called on arrays, the
layout of the parameter vector ``P`` (``P_*``), the state laws and friction forms,
and the opcodes of a user's state-law program (``OP_*``). Their results come
decoded by :mod:`~stickslip.core.results`.
"""

from __future__ import annotations

from .radau import integrate_in, workspace
from .ratestate import (
    AGING,
    LOG,
    N_QUAD,
    OP_ABS,
    OP_ADD,
    OP_ASINH,
    OP_CONST,
    OP_COSH,
    OP_DC,
    OP_DIV,
    OP_EXP,
    OP_LOG,
    OP_MU_RATE,
    OP_MUL,
    OP_PHI,
    OP_POW,
    OP_SINH,
    OP_SQRT,
    OP_TANH,
    OP_V,
    OP_VR,
    P_ETA,
    P_FORM,
    P_KW,
    P_VR,
    REGULARIZED,
    USER,
    in_friction,
    in_jac,
    in_rhs,
    integrate_qs,
    qs_jac,
    qs_velocity,
)

__all__ = [
    "AGING",
    "LOG",
    "N_QUAD",
    "OP_ABS",
    "OP_ADD",
    "OP_ASINH",
    "OP_CONST",
    "OP_COSH",
    "OP_DC",
    "OP_DIV",
    "OP_EXP",
    "OP_LOG",
    "OP_MUL",
    "OP_MU_RATE",
    "OP_PHI",
    "OP_POW",
    "OP_SINH",
    "OP_SQRT",
    "OP_TANH",
    "OP_V",
    "OP_VR",
    "P_ETA",
    "P_FORM",
    "P_KW",
    "P_VR",
    "REGULARIZED",
    "USER",
    "in_friction",
    "in_jac",
    "in_rhs",
    "integrate_in",
    "integrate_qs",
    "qs_jac",
    "qs_velocity",
    "workspace",
]
