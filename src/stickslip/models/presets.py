"""Named set-ups to start from: a preset fills the values a user does not give.

``zv`` is the paper's experiment (PHYSICS.md §4): W = 196 mN, mu0 = 0.46,
a = 160 s/m, k = 62 N/m, driven at 10 um/s, with the mass that makes
``beta = sqrt(k m)/(mu_s W) = 42 s/m`` (0.231 kg), the value the paper computes with.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import pint

from ..units import Q_
from .parameters import ZV_A, ZV_BETA, ZV_LOAD, ZV_MU0, ZV_STIFFNESS, mass_of_beta

__all__ = ["PRESETS", "Preset"]


@dataclass(frozen=True)
class Preset:
    """A physical set-up by name: driving velocity, stiffness, load, beta, and law values per law.

    Attributes
    ----------
    name : str
        The preset's name (``--preset NAME``).
    v0, stiffness, load, beta : str or pint.Quantity
        The set-up; the mass is the one that gives ``beta`` with the law's static coefficient.
    laws : dict
        For each law name, the law's own values (``{"weakening": {"mu_s": 0.46, "a": 160 s/m}}``);
        another law takes only the set-up.

    """

    name: str
    v0: Any
    stiffness: pint.Quantity
    load: pint.Quantity
    beta: pint.Quantity
    mu_s: float
    laws: Mapping[str, Mapping[str, Any]] = field(default_factory=dict)

    def fill(self, values: Mapping[str, Any], law: str | None = None) -> dict[str, Any]:
        """Return ``values`` with the preset's set-up (and ``law``'s values) where they are ``None``.

        A given ``beta`` sets the mass, so the preset's mass is then left out.
        """
        out = dict(values)
        mass = mass_of_beta(self.beta, self.beta, self.stiffness, self.load, self.mu_s)
        setup = {"v0": self.v0, "mass": Q_(float(mass), "kg"), "stiffness": self.stiffness}
        setup["load"] = self.load
        for key, value in setup.items():
            if out.get(key) is None and not (key == "mass" and out.get("beta") is not None):
                out[key] = value
        for key, value in (self.laws.get(law, {}) if law is not None else {}).items():
            if out.get(key) is None:
                out[key] = value
        return out


#: the presets by name
PRESETS = {
    "zv": Preset(
        "zv",
        v0="10 um/s",
        stiffness=ZV_STIFFNESS,
        load=ZV_LOAD,
        beta=ZV_BETA,
        mu_s=ZV_MU0,
        laws={"weakening": {"mu_s": ZV_MU0, "a": ZV_A}},
    )
}
