"""The chain's set-up: N blocks, a friction law, the coupling, the ends, the thresholds.

Dimensionless form (``docs/chain.md``): the one-block scaling with ``k = k_p``
(length ``F_s/k_p``, time ``sqrt(m/k_p)``, velocity ``F_s/sqrt(k_p m)``) and
``ell**2 = k_c/k_p``. For one block it is exactly the one-block model.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

from ..errors import ArgumentTypeError
from ..laws import DimensionlessLaw
from ..models import DimensionlessParameters, PhysicalParameters, Scales
from ..units import check_count, check_number, check_seed, parse_quantity

__all__ = ["Boundary", "ChainParameters", "Init", "initial_positions", "sliding_after", "static_thresholds"]

FloatArray = npt.NDArray[np.float64]

#: the largest coupling ell = sqrt(k_c/k_p) (a stiffer chain moves as one block)
ELL_MAX = 1e6


class Boundary(enum.StrEnum):
    """The ends of the chain."""

    FREE = "free"  # x_0 = x_1, x_{N+1} = x_N
    PERIODIC = "periodic"  # x_0 = x_N, x_{N+1} = x_1


class Init(enum.StrEnum):
    """How the blocks start (all at rest)."""

    UNIFORM = "uniform"  # identical blocks at the same position
    RANDOM = "random"  # small seeded displacements


#: laws whose authors forbid backward slip (friction at rest bounded only from above)
_NO_BACKSLIP = frozenset({"carlson-langer"})


@dataclass(frozen=True)
class ChainParameters:
    """A dimensionless Burridge-Knopoff chain.

    Parameters
    ----------
    blocks : int
        Number of blocks ``N >= 1``.
    law : DimensionlessLaw
        Friction of every block, in units of its static friction force.
    nu : float
        Dimensionless driving velocity (> 0).
    ell : float
        Coupling ``ell = sqrt(k_c/k_p)`` (>= 0; 0 uncouples the blocks).
    boundary : {"free", "periodic"}
        The ends. Default free.
    thresholds : array of float, optional
        Each block's static threshold in units of the mean (all 1 by default);
        see :func:`static_thresholds` for seeded heterogeneous ones.
    backslip : bool, optional
        Whether a block may slip backward. Default: yes, except for the
        Carlson-Langer law, whose authors forbid it.
    scales : Scales, optional
        Units of the dimensionless model when the chain was made from physical
        input (:meth:`from_physical`); None otherwise.

    """

    blocks: int
    law: DimensionlessLaw
    nu: float
    ell: float
    boundary: Boundary = Boundary.FREE
    thresholds: FloatArray | None = field(default=None, compare=False, repr=False)
    backslip: bool | None = None
    scales: Scales | None = field(default=None, compare=False, repr=False)

    def __post_init__(self) -> None:
        n = self.blocks
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)):
            raise ArgumentTypeError(f"blocks={n!r}: expected a whole number of blocks from 1 to 10**7")
        if n < 1 or n > 10_000_000:
            raise ValueError(f"blocks={n!r}: expected a whole number of blocks from 1 to 10**7")
        object.__setattr__(self, "blocks", int(n))
        # the one-block model's checks of nu and of the law
        DimensionlessParameters(nu=self.nu, law=self.law)
        object.__setattr__(self, "nu", float(self.nu))
        ell = check_number(self.ell, "ell", allow_zero=True, what="a coupling ell = sqrt(k_c/k_p) >= 0")
        if ell >= ELL_MAX:
            raise ValueError(f"ell={self.ell!r}: expected a coupling ell = sqrt(k_c/k_p) below {ELL_MAX:g}")
        object.__setattr__(self, "ell", ell)
        if not isinstance(self.boundary, str):
            raise ArgumentTypeError(f"boundary={self.boundary!r}: expected 'free' or 'periodic'")
        try:
            object.__setattr__(self, "boundary", Boundary(self.boundary))
        except ValueError:
            raise ValueError(f"boundary={self.boundary!r}: expected 'free' or 'periodic'") from None
        if self.thresholds is not None:
            if isinstance(self.thresholds, str | bytes):
                raise ArgumentTypeError(f"thresholds={self.thresholds!r}: expected one number per block")
            try:
                phi = np.array(self.thresholds, dtype=float)
            except (TypeError, ValueError):
                raise ArgumentTypeError(
                    f"thresholds={self.thresholds!r}: expected one number per block"
                ) from None
            if phi.shape != (self.blocks,):
                raise ValueError(
                    f"thresholds: expected {self.blocks} values (one per block), got shape {phi.shape}"
                )
            if not np.all(np.isfinite(phi)) or np.any(phi <= 0.0):
                raise ValueError("thresholds: expected positive finite static thresholds")
            phi.setflags(write=False)
            object.__setattr__(self, "thresholds", phi)
        if self.backslip is None:
            object.__setattr__(self, "backslip", self.law.name not in _NO_BACKSLIP)
        elif not isinstance(self.backslip, bool | np.bool_):  # "no" is a true string: refused
            raise ArgumentTypeError(
                f"backslip={self.backslip!r}: expected True, False or None (the law's default)"
            )
        object.__setattr__(self, "backslip", bool(self.backslip))

    @property
    def ell2(self) -> float:
        """``ell**2 = k_c/k_p``."""
        return self.ell * self.ell

    @property
    def phi(self) -> FloatArray:
        """The static thresholds (a copy; all 1 for a uniform chain)."""
        return np.ones(self.blocks) if self.thresholds is None else np.array(self.thresholds)

    @classmethod
    def from_physical(
        cls,
        params: PhysicalParameters,
        *,
        blocks: int,
        coupling: Any,
        boundary: Boundary | str = Boundary.FREE,
        thresholds: npt.ArrayLike | None = None,
        backslip: bool | None = None,
    ) -> ChainParameters:
        """Return the chain of ``blocks`` copies of the one-block set-up ``params``.

        Parameters
        ----------
        params : PhysicalParameters
            Mass, loading spring ``k_p`` (``stiffness``), load, driving velocity and law of each block.
        blocks : int
            Number of blocks.
        coupling : pint.Quantity or str
            Stiffness ``k_c`` of the springs between neighbours, e.g. ``"100 N/m"``.
        boundary, thresholds, backslip
            As for :class:`ChainParameters`.

        """
        if not isinstance(params, PhysicalParameters):
            raise ArgumentTypeError(f"params={params!r}: expected PhysicalParameters")
        kc = parse_quantity(coupling, "coupling", "[mass] / [time] ** 2", "100 N/m", allow_zero=True)
        kp = params.stiffness.to("N/m").magnitude
        ratio = float(kc.to("N/m").magnitude) / float(kp)
        if not (np.isfinite(ratio) and math.sqrt(ratio) < ELL_MAX):
            raise ValueError(
                f"coupling={coupling!r}: k_c/k_p = {ratio:.4g} with the loading spring k_p = {kp:g} N/m; "
                f"expected below {ELL_MAX**2:g} (ell = sqrt(k_c/k_p) below {ELL_MAX:g})"
            )
        d = params.dimensionless()
        return cls(
            blocks=blocks,
            law=d.law,
            nu=d.nu,
            ell=float(np.sqrt(ratio)),
            boundary=Boundary(boundary),
            thresholds=None if thresholds is None else np.asarray(thresholds, dtype=float),
            backslip=backslip,
            scales=params.scales,
        )


def static_thresholds(blocks: int, spread: float, seed: int | None) -> FloatArray | None:
    """Return seeded heterogeneous static thresholds ``1 + spread * U(-1, 1)``, or None for ``spread = 0``.

    Raises
    ------
    ArgumentTypeError
        For a ``spread`` that is not a number.
    ValueError
        For ``spread`` outside ``[0, 1)``.

    """
    blocks = check_count(blocks, "blocks")
    s = check_number(spread, "spread", allow_zero=True, what="a threshold spread in [0, 1)")
    if not (0.0 <= s < 1.0):
        raise ValueError(f"spread={spread!r}: expected a threshold spread in [0, 1)")
    if s == 0.0:
        return None
    # a stream of its own: drawn from the one of the initial positions (the same seed), the
    # strongest block would always start furthest ahead (correlation 1)
    rng = np.random.default_rng(np.random.SeedSequence(check_seed(seed), spawn_key=(1,)))
    return 1.0 + s * rng.uniform(-1.0, 1.0, blocks)


def sliding_after(params: ChainParameters) -> float:
    """Return the default longest event, ``1000/nu + 1000`` time units.

    An event lasting longer is a sliding state of the chain: the blocks never all stick again.
    """
    return 1000.0 / params.nu + 1000.0


def initial_positions(blocks: int, init: Init | str, seed: int | None, amplitude: float = 0.01) -> FloatArray:
    """Return the blocks' initial positions (units of ``F_s/k_p``), all at rest.

    ``uniform``: all at 0 (identical blocks in identical states); ``random``:
    seeded displacements uniform in ``[0, amplitude)``.
    """
    if not isinstance(init, str):
        raise ArgumentTypeError(f"init={init!r}: expected 'uniform' or 'random'")
    try:
        kind = Init(init)
    except ValueError:
        raise ValueError(f"init={init!r}: expected 'uniform' or 'random'") from None
    if kind is Init.UNIFORM:
        return np.zeros(blocks)
    a = check_number(amplitude, "amplitude", what="a positive displacement amplitude")
    return np.random.default_rng(check_seed(seed)).uniform(0.0, a, blocks)
