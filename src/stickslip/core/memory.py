"""Memory the machine can give, and a refusal before an allocation that would exhaust it.

Numbers only: the estimate is the caller's; this module reads what the operating
system reports (``MemAvailable`` on Linux, else the physical memory) and refuses
a request above a fraction of it, with the numbers in the message.
"""

from __future__ import annotations

import os

__all__ = ["MemoryRequestError", "available_memory", "check_memory", "format_bytes"]

#: a request may use at most this fraction of the memory available
FRACTION = 0.6
#: requests below this many bytes are not checked (reading the memory available costs
#: some 60 us; a return map's thousands of one-sample trajectories read it each time)
UNCHECKED_BYTES = 1 << 20


class MemoryRequestError(ValueError):
    """A computation or a file needs more memory than the machine has available."""


def available_memory() -> int:
    """Return the memory available to a new allocation, in bytes (best effort)."""
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return int(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_AVPHYS_PAGES"))
    except (ValueError, OSError, AttributeError):  # pragma: no cover - not a POSIX system
        return 8 << 30


def format_bytes(n: float) -> str:
    """Return ``n`` bytes as a short human-readable string (``'3.2 GB'``)."""
    for unit in ("B", "kB", "MB", "GB", "TB"):
        if abs(n) < 1000 or unit == "TB":
            return f"{n:.3g} {unit}" if unit != "B" else f"{int(n)} B"
        n /= 1000
    return f"{n:.3g} TB"  # pragma: no cover


def check_memory(nbytes: float, what: str, hint: str = "") -> None:
    """Refuse (before allocating) a request of ``nbytes`` above :data:`FRACTION` of the available memory.

    Requests below :data:`UNCHECKED_BYTES` (1 MiB) are let through unread.

    Parameters
    ----------
    nbytes : float
        The estimate of what the request needs.
    what : str
        The request, for the message (``"--points=300000000"``).
    hint : str, optional
        What to do instead.

    Raises
    ------
    MemoryRequestError
        With the estimate and the memory available.

    """
    if nbytes < UNCHECKED_BYTES:
        return
    avail = available_memory()
    if nbytes > FRACTION * avail:
        raise MemoryRequestError(
            f"{what} needs about {format_bytes(nbytes)} of memory, more than this machine can give "
            f"({format_bytes(avail)} available){'; ' + hint if hint else ''}"
        )
