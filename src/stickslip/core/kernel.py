"""What the array APIs of both engines share: a law's compiled modules and how they are called.

:class:`Kernel` names the compiled modules of one friction law (the one-block
engine, its variational equations, the chain engine). Every call into compiled
code goes through :func:`pole_is_an_error`, so that a law's division by zero is
a ValueError that says so; the row kernels run in blocks of rows on a pool of
:func:`threads` threads (:func:`in_blocks`). The engines' own entry points are in
:mod:`stickslip.core.block_api` (one block) and :mod:`stickslip.core.chain_api`
(a chain of blocks).
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Iterator
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import dataclass
from types import ModuleType

import numba
import numpy as np
import numpy.typing as npt

from . import chain, engine, forced, variational
from .laws import BUILTIN_LAWS

__all__ = [
    "BATCH",
    "SERIAL_ROWS",
    "Kernel",
    "as_kernel",
    "builtin_kernel",
    "in_blocks",
    "pole_is_an_error",
    "threads",
]

#: up to this many rows run in the calling thread
SERIAL_ROWS = 8
#: most rows per call into the compiled code (Ctrl-C is seen between calls)
BATCH = 4096


@dataclass(frozen=True)
class Kernel:
    """The compiled engine of one friction law.

    Attributes
    ----------
    law_id : int
        The law's id in its modules (``LAW_*`` of :mod:`stickslip.core.laws` for a
        built-in law; 0 in a law's own generated modules).
    engine, variational : module
        The compiled modules: :mod:`stickslip.core.engine` and
        :mod:`stickslip.core.variational` for the built-in laws, or their copies
        compiled with a law's generated kernel (:mod:`stickslip.laws.compiler`).
    name : str
        The law, for messages.
    chain : module or None
        The chain engine (:mod:`stickslip.core.chain` or its copy); None: the
        built-in one.
    forced : module or None
        The forced oscillator's engine (:mod:`stickslip.core.forced` or its copy);
        None: the built-in one.

    """

    law_id: int
    engine: ModuleType
    variational: ModuleType
    name: str = ""
    chain: ModuleType | None = None
    forced: ModuleType | None = None

    @property
    def chain_engine(self) -> ModuleType:
        """The chain engine compiled with this law."""
        return self.chain if self.chain is not None else chain

    @property
    def forced_engine(self) -> ModuleType:
        """The forced oscillator's engine compiled with this law."""
        return self.forced if self.forced is not None else forced


_BUILTIN_NAMES = {0: "weakening", 1: "cubic", 2: "coulomb", 3: "carlson-langer"}


def builtin_kernel(law_id: int) -> Kernel:
    """Return the kernel of a built-in law (id ``LAW_*`` of :mod:`stickslip.core.laws`)."""
    return Kernel(int(law_id), engine, variational, _BUILTIN_NAMES.get(int(law_id), ""), chain, forced)


def as_kernel(law: Kernel | int | npt.ArrayLike) -> Kernel:
    """Return ``law`` as a Kernel: itself, or the built-in law of that id (one id, possibly repeated)."""
    if isinstance(law, Kernel):
        return law
    try:
        ids = np.unique(np.asarray(law, dtype=np.int64))
    except (TypeError, ValueError):
        raise TypeError(
            f"law={law!r}: expected a Kernel or a built-in law id 0 (weakening), 1 (cubic), 2 (coulomb) "
            "or 3 (carlson-langer)"
        ) from None
    if ids.size != 1 or int(ids[0]) not in BUILTIN_LAWS:
        raise ValueError(
            f"law={law!r}: expected one law id: 0 (weakening), 1 (cubic), 2 (coulomb) or 3 (carlson-langer)"
        )
    return builtin_kernel(int(ids[0]))


def threads() -> int:
    """Return the number of threads the row kernels use: numba's (``NUMBA_NUM_THREADS``)."""
    return max(1, int(numba.config.NUMBA_NUM_THREADS))  # type: ignore[attr-defined]


def in_blocks(call: Callable[[int, int], None], n: int, done: Callable[[int], None] | None = None) -> None:
    """Run :func:`_in_blocks`; a division by zero in a compiled friction law is a ValueError that says so.

    A user's formula with a pole (``0.001/(w - 0.7)``) raises ZeroDivisionError inside the
    compiled code when a row lands on it exactly: the error names the law's pole, not a
    line deep in the engine.
    """
    with pole_is_an_error():
        _in_blocks(call, n, done)


@contextlib.contextmanager
def pole_is_an_error() -> Iterator[None]:
    """Turn a compiled friction law's ZeroDivisionError into a ValueError that says what it is.

    Every call into the compiled engine goes through it: the row blocks of
    :func:`in_blocks`, a few rows run serially, a trajectory, a chain.
    """
    try:
        yield
    except ZeroDivisionError:
        raise ValueError(
            "the friction law divides by zero at a velocity the motion reached (a pole of its "
            "formula, or of its derivative); give a law that is finite, with a finite slope, at every "
            "velocity w >= 0"
        ) from None


def _in_blocks(call: Callable[[int, int], None], n: int, done: Callable[[int], None] | None = None) -> None:
    """Run ``call(lo, hi)`` over blocks of the rows ``0..n``, in a pool of :func:`threads` threads.

    The row kernels release the GIL, so the blocks run side by side. Blocks are
    small enough that rows of very different cost even out between the threads
    (at least 16 blocks a thread) and at most :data:`BATCH` rows, so that Ctrl-C
    is seen between two calls into the compiled code: the blocks not started are
    cancelled, the running ones finish. A few rows run in the calling thread.
    ``done(k)``, if given, is called in the calling thread as each block of ``k``
    rows finishes.
    """
    workers = min(threads(), -(-n // SERIAL_ROWS))
    if workers <= 1:
        for lo in range(0, n, BATCH):
            call(lo, min(n, lo + BATCH))
            if done is not None:
                done(min(n, lo + BATCH) - lo)
        return
    size = min(BATCH, max(1, -(-n // (16 * workers))))
    with ThreadPoolExecutor(workers, thread_name_prefix="stickslip") as pool:
        spans = [(lo, min(n, lo + size)) for lo in range(0, n, size)]
        futures = {pool.submit(call, lo, hi): hi - lo for lo, hi in spans}
        try:
            for f in as_completed(futures):
                f.result()
                if done is not None:
                    done(futures[f])
        except BaseException:
            for f in futures:
                f.cancel()
            raise
