"""The CUDA kernel of :mod:`stickslip.core.cuda` (imported only when a CUDA backend runs).

A module of its own, importing ``numba.cuda`` at its top: numba's CUDA simulator
swaps the name ``cuda`` in the kernel's module for its own while the kernel runs.
"""

from __future__ import annotations

from typing import Any

from numba import cuda


def make(one: Any) -> Any:
    """Return the CUDA kernel running the per-row function ``one`` (a law's ``engine.attractor_ws``).

    Thread ``i`` runs row ``i`` with work arrays ``K[i]`` .. ``evn[i]``; the
    empty sample and event buffers are shared (an attractor records nothing).
    """

    def rows(  # type: ignore[no-untyped-def]
        law_a, lp_a, nu_a, s0_a, w0_a, from_breakaway, rtol, atol, t_max, conv_tol, max_steps, out,
        K, F, y_new, ytmp, y, trk, t_eval, out_y, out_mode, evbuf, evn,
    ):  # fmt: skip
        i = cuda.grid(1)
        if i < nu_a.shape[0]:
            one(
                law_a[i], lp_a[i], nu_a[i], s0_a[i], w0_a[i], from_breakaway, rtol, atol, t_max,
                conv_tol, max_steps, out[i], K[i], F[i], y_new[i], ytmp[i], y[i], trk[i], t_eval,
                out_y, out_mode, evbuf, evn[i],
            )  # fmt: skip

    return cuda.jit(rows)
