"""Faster numba compilation: the typing of Python's operators remembered per argument types.

numba types every operator of a function afresh: ``a * b`` with two float64 is
resolved again at each of its hundreds of occurrences in the unrolled DOP853
stages, by trying every registered template for ``operator.mul`` (including the
overloads for typed lists, strings, records, ...) and hashing the compile flags
each time. That repetition was a quarter of the time of a first ``stickslip
cycle`` (measured with cProfile: ``BaseFunction.get_call_type``, 6 200 calls, a
few hundred distinct).

:func:`install` wraps ``numba.core.types.functions.BaseFunction.get_call_type``
so that the answer for one function of :mod:`operator` or :mod:`builtins`, one
typing context, one set of compile flags and one tuple of argument types
(literal values included) is computed once and then reused. The wrapped method
is deterministic in exactly these inputs: it asks the templates in a fixed
order and returns the first signature that matches; the implementation it
records (``_impl_keys``) stays recorded on the same interned function type.
Calls with keyword arguments, functions of other modules (numpy, math, user
functions and dispatchers) and failed resolutions (errors) are not remembered.
The machine code is unchanged: ``tests/test_coldstart.py`` compiles a kernel
with and without it in fresh processes and compares the LLVM IR.

It is installed when :mod:`stickslip.core` is imported; ``STICKSLIP_NUMBA_MEMO=0``
leaves numba untouched. Where numba's method does not have the expected form
(another numba version), nothing is installed.
"""

from __future__ import annotations

import inspect
import os
from typing import Any

__all__ = ["install", "installed"]

_MODULES = frozenset({"_operator", "operator", "builtins"})
_STATE: dict[str, Any] = {"installed": False}


def installed() -> bool:
    """Return whether the memo is in place."""
    return bool(_STATE["installed"])


def install() -> bool:
    """Wrap numba's operator typing with the memo (once); return whether it is in place."""
    if _STATE["installed"]:
        return True
    if os.environ.get("STICKSLIP_NUMBA_MEMO", "1").strip() in ("0", "false", "no", "off"):
        return False
    try:
        from numba.core import targetconfig
        from numba.core.types import functions
    except ImportError:  # pragma: no cover - a numba without these modules
        return False
    cls = functions.BaseFunction
    orig = cls.__dict__.get("get_call_type")
    stack = getattr(targetconfig, "ConfigStack", None)
    if (
        orig is None
        or stack is None
        or not hasattr(stack, "top_or_none")
        or list(inspect.signature(orig).parameters) != ["self", "context", "args", "kws"]
    ):
        return False
    memo: dict[tuple[Any, ...], Any] = {}
    # each compilation's flags (kept alive, so that their ids stay unique) and their values
    # as text: flags are compared by their values, computed once per compilation
    flags_seen: dict[int, tuple[Any, str]] = {}

    def fingerprint(flags: Any) -> str:
        seen = flags_seen.get(id(flags))
        if seen is None:
            values = flags.values() if flags is not None else {}
            seen = (flags, repr(sorted(values.items())))
            flags_seen[id(flags)] = seen
        return seen[1]

    def get_call_type(self: Any, context: Any, args: Any, kws: Any) -> Any:
        key = self.key[0] if isinstance(self.key, tuple) and self.key else self.key
        if kws or getattr(key, "__module__", None) not in _MODULES:
            return orig(self, context, args, kws)
        k = (self, context, fingerprint(stack.top_or_none()), args)
        try:
            return memo[k]
        except KeyError:
            pass
        except TypeError:  # an unhashable argument type
            return orig(self, context, args, kws)
        sig = orig(self, context, args, kws)
        if sig is not None:
            memo[k] = sig
        return sig

    get_call_type.__wrapped__ = orig  # type: ignore[attr-defined]
    get_call_type.__doc__ = orig.__doc__
    cls.get_call_type = get_call_type  # type: ignore[method-assign]
    _STATE["installed"] = True
    return True
