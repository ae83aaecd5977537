"""JSON-ready values: non-finite floats become ``null``."""

from __future__ import annotations

import json
import math
from typing import Any

__all__ = ["dumps", "json_clean"]


def json_clean(x: Any) -> Any:
    """Return ``x`` with every NaN or infinite float (in dicts, lists, tuples) replaced by None.

    JSON has no NaN: a quantity that does not exist (no pure-slip attractor, no
    verdict) is written as ``null``.
    """
    if isinstance(x, float):
        return None if not math.isfinite(x) else x
    if isinstance(x, dict):
        return {k: json_clean(v) for k, v in x.items()}
    if isinstance(x, list | tuple):
        return [json_clean(v) for v in x]
    return x


def dumps(obj: Any, **kwargs: Any) -> str:
    """Return ``obj`` as JSON text, NaN and infinities as ``null`` (never the invalid ``NaN``).

    ``json.dumps`` writes ``NaN``, which JSON parsers other than Python's refuse;
    every JSON stickslip writes or
    prints goes through here. Keyword arguments are ``json.dumps``'s.
    """
    return json.dumps(json_clean(obj), allow_nan=False, **kwargs)
