"""One DOP853 step of a chain's slipping blocks, and the stops and breakaways inside it (compiled).

The part of the chain engine (:mod:`.chain`) that integrates a *segment*, a stretch of
time over which the same blocks slip: the vector field of the slipping blocks
(:func:`_rhs`; the stuck blocks next to them enter as constant positions), one DOP853
step of it with its error norm (:func:`_step`) and its 7th-order interpolant
(:func:`_dense`), and the events located on that interpolant by the Illinois iteration
of :mod:`.dop853` (:func:`_root`):

* stop of a slipping block: ``d_j v_j`` reaches 0 (a dip to zero inside a step
  included: the minimum of the interpolant is located first), :func:`_find_stops`;
* breakaway of a stuck block next to a slipping one: ``e_j`` reaches ``phi_j``
  (forward) or ``-phi_j`` (backward), maxima inside a step included,
  :func:`_find_breakaways`.

Events closer than :data:`SIMULTANEOUS` (in units of a step) are handled together,
in block order (:func:`_simultaneous`). The arrays are those of :func:`.chain.chain_run`,
passed one by one; ``at`` (the interpolant of the step, :mod:`.chain`) is unpacked in
functions compiled into their caller only.
"""

from __future__ import annotations

from numba import njit

from ._dop853_tableau import C
from .dop853 import (
    N_STAGES,
    N_STAGES_EXTENDED,
    dense_eval,
    dense_slope,
    illinois_propose,
    illinois_update,
    vec_advance,
    vec_dense_coeffs,
    vec_error,
    vec_stage,
)
from .laws import friction_scalar

#: events closer than this fraction of a step are simultaneous
SIMULTANEOUS = 1e-12
#: the shortest slip from rest sought inside a step (a fraction of the step)
PROBE_MIN = 2.0**-40
#: the rounding of a speed integrated over a step, per unit step and unit force (64 ulps): a block
#: started from rest whose speed stays within it while it is pushed forward has not stopped
ROUND_SPEED = 64 * 2.220446049250313e-16


@njit(cache=True, inline="always")
def _left(j, n, periodic):  # type: ignore[no-untyped-def]
    if j > 0:
        return j - 1
    return n - 1 if periodic else j


@njit(cache=True, inline="always")
def _right(j, n, periodic):  # type: ignore[no-untyped-def]
    if j < n - 1:
        return j + 1
    return 0 if periodic else j


@njit(cache=True)
def _rhs(ctx, t, y, out):  # type: ignore[no-untyped-def]
    """Vector field of the slipping blocks; ``y = (x, v) per slipping block, W_drive, W_friction``.

    ``y`` goes on with the positions of the stuck neighbours of slipping blocks
    (constant over a segment); ``nbl[k]`` and ``nbr[k]`` index the neighbours'
    positions of slipping block ``k`` in ``y``, ``dk`` and ``phk`` are its
    direction and threshold.
    """
    law, P, nu, ell2, nbl, nbr, dk, phk, m, s_stuck, n_stuck, t_ref = ctx
    drive = s_stuck + n_stuck * nu * (t - t_ref)
    fric = 0.0
    load = nu * t
    for k in range(m):
        xj = y[2 * k]
        vj = y[2 * k + 1]
        xl = y[nbl[k]]
        xr = y[nbr[k]]
        fr = phk[k] * friction_scalar(law, P, dk[k], vj)
        out[2 * k] = vj
        sj = load - xj
        out[2 * k + 1] = ell2 * ((xl - xj) + (xr - xj)) + sj - fr
        drive += sj
        fric += fr * vj
    out[2 * m] = nu * drive
    out[2 * m + 1] = fric


@njit(cache=True)
def _force_at(F, y, xs, x, j, nu, ell2, periodic, pos, t0, h):  # type: ignore[no-untyped-def]
    """Force on stuck block ``j`` at fraction ``xs`` of the step (neighbours from the interpolant)."""
    n = x.shape[0]
    jl = _left(j, n, periodic)
    jr = _right(j, n, periodic)
    pl = pos[jl]
    pr = pos[jr]
    xl = dense_eval(F, y, xs, 2 * pl) if pl >= 0 else x[jl]
    xr = dense_eval(F, y, xs, 2 * pr) if pr >= 0 else x[jr]
    xj = x[j]
    return ell2 * ((xl - xj) + (xr - xj)) + (nu * (t0 + xs * h) - xj)


@njit(cache=True)
def _force_slope(F, xs, x, j, nu, ell2, periodic, pos, h):  # type: ignore[no-untyped-def]
    """Time derivative of the force on stuck block ``j`` at fraction ``xs`` of the step."""
    n = x.shape[0]
    jl = _left(j, n, periodic)
    jr = _right(j, n, periodic)
    pl = pos[jl]
    pr = pos[jr]
    dl = dense_slope(F, xs, 2 * pl) if pl >= 0 else 0.0
    dr = dense_slope(F, xs, 2 * pr) if pr >= 0 else 0.0
    return ell2 * (dl + dr) / h + nu


# what a root is sought of, for _root
G_VEL = 0  # sign * v_k(x)
G_VEL_SLOPE = 1  # d v_k / dx
G_FORCE = 2  # sign * (e_j(x) - level)
G_FORCE_SLOPE = 3  # d e_j / dt


@njit(cache=True)
def _g(what, F, y, xs, k, sign, level, x, j, nu, ell2, periodic, pos, t0, h):  # type: ignore[no-untyped-def]
    if what == G_VEL:
        return sign * dense_eval(F, y, xs, 2 * k + 1)
    if what == G_VEL_SLOPE:
        return dense_slope(F, xs, 2 * k + 1)
    if what == G_FORCE:
        return sign * (_force_at(F, y, xs, x, j, nu, ell2, periodic, pos, t0, h) - level)
    return _force_slope(F, xs, x, j, nu, ell2, periodic, pos, h)


@njit(cache=True)
def _root(what, F, y, k, sign, level, x, j, nu, ell2, periodic, pos, t0, h, xa, ga, xb, gb):  # type: ignore[no-untyped-def]
    """Root of ``_g`` on ``[xa, xb]`` (``ga``, ``gb`` of opposite signs) by the shared Illinois iteration."""
    if ga == 0.0:
        return xa
    if gb == 0.0:
        return xb
    side = 0
    xc = xb
    for _ in range(200):
        xc = illinois_propose(xa, ga, xb, gb)
        gc = _g(what, F, y, xc, k, sign, level, x, j, nu, ell2, periodic, pos, t0, h)
        xa, ga, xb, gb, side, done = illinois_update(xa, ga, xb, gb, side, xc, gc)
        if done:
            break
    return xc


@njit(cache=True)
def _dense(ctx, t, h, y, y_new, ytmp, K, F, nvar):  # type: ignore[no-untyped-def]
    """Fill ``F`` with the interpolant of the step just taken (3 more stages in ``K``)."""
    for j in range(N_STAGES + 1, N_STAGES_EXTENDED):
        vec_stage(y, K, h, j, nvar, ytmp)
        _rhs(ctx, t + C[j] * h, ytmp, K[j])
    vec_dense_coeffs(y, y_new, h, K, F, nvar)


@njit(cache=True, inline="always")
def _step(ctx, t, h, y, y_new, ytmp, K, nvar, nctl, rtol, atol):  # type: ignore[no-untyped-def]
    """Take a DOP853 step of ``h`` from ``y`` to ``y_new``; return its error norm (<= 1: accepted)."""
    for s in range(1, N_STAGES):
        vec_stage(y, K, h, s, nvar, ytmp)
        _rhs(ctx, t + C[s] * h, ytmp, K[s])
    vec_advance(y, K, h, nvar, y_new)
    _rhs(ctx, t + h, y_new, K[N_STAGES])
    return vec_error(y, y_new, K, h, nctl, rtol, atol)


@njit(cache=True, inline="always")
def _find_stops(ctx, at, y_new, ytmp, K, nvar, idx, mode, ev_x, ev_k, ev_kind, pk_x, pk_v):  # type: ignore[no-untyped-def]
    """Find the stops of slipping blocks in the step, and their speed maxima in it.

    Writes the stops to ``found`` from its first place and each block's speed maximum
    (``pk_x``, ``pk_v``; fraction 2 where there is none); returns the count of stops
    and whether the interpolant was made.
    """
    F, y, x, pos, nu, ell2, periodic, t, h = at
    m = ctx[8]
    nev = 0
    have_dense = False
    for k in range(m):
        j = idx[k]
        d = mode[j]
        g0 = d * y[2 * k + 1]
        g1 = d * y_new[2 * k + 1]
        a0 = d * K[0, 2 * k + 1]
        a1 = d * K[N_STAGES, 2 * k + 1]
        xe = -1.0
        pk_x[k] = 2.0
        pk_v[k] = 0.0
        peak_in = a0 > 0.0 and a1 < 0.0  # a speed maximum inside the step
        dip_in = a0 < 0.0 and a1 > 0.0 and g1 > 0.0  # a speed minimum: a dip to 0?
        if (peak_in or dip_in or g1 <= 0.0) and not have_dense:
            _dense(ctx, t, h, y, y_new, ytmp, K, F, nvar)
            have_dense = True
        xm = 2.0
        if peak_in or dip_in:
            xm = _root(G_VEL_SLOPE, F, y, k, 1.0, 0.0, x, j, nu, ell2, periodic, pos, t, h, 0.0, d * a0 * h,
                       1.0, d * a1 * h)  # fmt: skip
        if peak_in:
            pk_x[k] = xm
            pk_v[k] = abs(dense_eval(F, y, xm, 2 * k + 1))
        if g1 <= 0.0:
            if g0 > 0.0:
                xe = _root(G_VEL, F, y, k, d, 0.0, x, j, nu, ell2, periodic, pos, t, h, 0.0, g0, 1.0, g1)
            else:
                # started at rest: the stop is where the speed, grown first, returns to 0. A
                # force that touches the threshold and turns back gives a slip of a few 1e-5
                # inside a step of 4e-4: a slip shorter than half the step is sought closer to
                # its start, or it would be taken for none and the block would slip on at once,
                # again and again, at the same time
                xs = 0.5
                xb = 1.0
                gb_ = g1
                gs = d * dense_eval(F, y, xs, 2 * k + 1)
                g_low = min(g1, gs)  # the slowest the block went, at the probes
                while gs <= 0.0 and xs > PROBE_MIN:
                    xb = xs
                    gb_ = gs
                    xs *= 0.5
                    gs = d * dense_eval(F, y, xs, 2 * k + 1)
                    g_low = min(g_low, gs)
                if gs > 0.0:
                    xe = _root(G_VEL, F, y, k, d, 0.0, x, j, nu, ell2, periodic, pos, t, h, xs, gs, xb, gb_)
                elif a1 > 0.0 and -g_low <= ROUND_SPEED * h * (1.0 + ell2 + abs(nu * t)):
                    # pushed forward at the end of the step, with a speed that never left the
                    # rounding of its increments: no stop. Three blocks at threshold together
                    # (c = 0.05, rtol 1e-11) cut one's step to 6.7e-14 at its twin's breakaway,
                    # and its speed comes out -7e-30 for +2e-29: a stop there would break it
                    # away again at the same time until the stall guard (STALL_STEPS) ends the run
                    y_new[2 * k + 1] = 0.0
                else:
                    xe = 0.0
        elif dip_in:
            gm = d * dense_eval(F, y, xm, 2 * k + 1)
            if gm <= 0.0 and g0 > 0.0:
                xe = _root(G_VEL, F, y, k, d, 0.0, x, j, nu, ell2, periodic, pos, t, h, 0.0, g0, xm, gm)
        if xe >= 0.0:
            ev_x[nev] = xe
            ev_k[nev] = j
            ev_kind[nev] = 0
            nev += 1
    return nev, have_dense


@njit(cache=True, inline="always")
def _find_breakaways(  # type: ignore[no-untyped-def]
    ctx, at, y_new, ytmp, K, nvar, na, nev, have_dense, phi, backward, adj, e_adj, e_end, ev_x, ev_k, ev_kind
):
    """Find the breakaways of the watched stuck blocks in the step (forward, and backward where allowed).

    Appends them to the ``nev`` events of ``found``, keeps each block's force at the
    end of the step in ``e_end``; returns the count of events and whether the
    interpolant was made.
    """
    F, y, x, pos, nu, ell2, periodic, t, h = at
    n = x.shape[0]
    for i in range(na):
        j = adj[i]
        e0 = e_adj[i]
        # force at the end of the step: neighbours at y_new
        jl = _left(j, n, periodic)
        jr = _right(j, n, periodic)
        xl = y_new[2 * pos[jl]] if pos[jl] >= 0 else x[jl]
        xr = y_new[2 * pos[jr]] if pos[jr] >= 0 else x[jr]
        e1 = ell2 * ((xl - x[j]) + (xr - x[j])) + (nu * (t + h) - x[j])
        e_end[i] = e1
        vl0 = y[2 * pos[jl] + 1] if pos[jl] >= 0 else 0.0
        vr0 = y[2 * pos[jr] + 1] if pos[jr] >= 0 else 0.0
        vl1 = y_new[2 * pos[jl] + 1] if pos[jl] >= 0 else 0.0
        vr1 = y_new[2 * pos[jr] + 1] if pos[jr] >= 0 else 0.0
        de0 = ell2 * (vl0 + vr0) + nu
        de1 = ell2 * (vl1 + vr1) + nu
        for sgn in (1.0, -1.0):
            if sgn < 0.0 and not backward:
                break
            ga = sgn * (e0 - sgn * phi[j])
            gb = sgn * (e1 - sgn * phi[j])
            xb, gbb = -1.0, 0.0  # the end of the breakaway's bracket, where there is one
            if gb >= 0.0:
                if not have_dense:
                    _dense(ctx, t, h, y, y_new, ytmp, K, F, nvar)
                    have_dense = True
                xb, gbb = 1.0, gb
            elif sgn * de0 > 0.0 and sgn * de1 < 0.0:  # an extremum of the force inside
                if not have_dense:
                    _dense(ctx, t, h, y, y_new, ytmp, K, F, nvar)
                    have_dense = True
                xm = _root(G_FORCE_SLOPE, F, y, 0, 1.0, 0.0, x, j, nu, ell2, periodic, pos, t, h, 0.0, de0,
                           1.0, de1)  # fmt: skip
                gm = sgn * (_force_at(F, y, xm, x, j, nu, ell2, periodic, pos, t, h) - sgn * phi[j])
                if gm >= 0.0:
                    xb, gbb = xm, gm
            xe = -1.0
            if xb >= 0.0:
                xe = _root(G_FORCE, F, y, 0, sgn, sgn * phi[j], x, j, nu, ell2, periodic, pos, t, h, 0.0,
                           min(ga, 0.0), xb, gbb)  # fmt: skip
            if xe >= 0.0:
                ev_x[nev] = xe
                ev_k[nev] = j
                ev_kind[nev] = 1 if sgn > 0.0 else -1
                nev += 1
    return nev, have_dense


@njit(cache=True)
def _simultaneous(xs, nev, ev_x, ev_k, ev_kind):  # type: ignore[no-untyped-def]
    """Put the events at ``xs`` (within SIMULTANEOUS) first, in block order; return how many they are."""
    ns = 0
    for i in range(nev):
        if ev_x[i] <= xs + SIMULTANEOUS:
            ev_k[ns] = ev_k[i]
            ev_kind[ns] = ev_kind[i]
            ns += 1
    for i in range(1, ns):  # insertion sort: a handful
        kk = ev_k[i]
        kd = ev_kind[i]
        q = i
        while q > 0 and ev_k[q - 1] > kk:
            ev_k[q] = ev_k[q - 1]
            ev_kind[q] = ev_kind[q - 1]
            q -= 1
        ev_k[q] = kk
        ev_kind[q] = kd
    return ns
