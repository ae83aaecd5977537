"""Event-driven integration of a chain of blocks (numbers only).

Dimensionless Burridge-Knopoff chain (``docs/chain.md``): blocks ``j = 0..N-1`` at
positions ``x_j`` with velocities ``v_j`` obey, while block ``j`` slips in
direction ``d_j``,

    x_j'' = ell2 (x_{j+1} - 2 x_j + x_{j-1}) + (nu tau - x_j) - phi_j d_j f_+(d_j x_j'),

with free ends (``x_{-1} = x_0``, ``x_N = x_{N-1}``) or periodic ones. A block
sticks (``v_j = 0``) while its elastic force
``e_j = ell2 (x_{j+1} - 2 x_j + x_{j-1}) + nu tau - x_j`` stays in
``[-phi_j, phi_j)``; ``phi_j`` is its static threshold (1 for a uniform chain).
For ``N = 1`` this is the one-block model of :mod:`.engine` with ``s = nu tau - x``.

Only the slipping blocks are integrated, by the DOP853 step of :mod:`.dop853`
(adaptive, 7th-order dense output); the forces of the stuck blocks are known in
closed form from their neighbours. Events are located by the Illinois iteration
of :mod:`.dop853` on the dense output:

* stop of a slipping block: ``d_j v_j`` reaches 0 (a dip to zero inside a step
  included: the minimum of the interpolant is located first);
* breakaway of a stuck block next to a slipping one: ``e_j`` reaches ``phi_j``
  (forward) or ``-phi_j`` (backward), maxima inside a step included;
* breakaway of a stuck block whose neighbours are stuck too: its force grows
  at the rate ``nu``, so its time is known in closed form; the earliest such time
  is kept in a binary heap (a segment tree) and a step never passes it.

When every block sticks, the chain jumps to the next breakaway in closed form.
Events closer than :data:`SIMULTANEOUS` (in units of a step) are handled
together, in block order; a stuck block within :data:`BREAK_TOL` of its
threshold breaks with its neighbours (identical blocks move as one).

After a stop a block sticks if ``-phi_j <= e_j < phi_j``; otherwise it slips on
at once, backward if ``e_j < -phi_j`` (unless backward slip is switched off, the
convention of Carlson and Langer: friction at rest bounded only from above).

An *event* starts when a block breaks away while all stick and ends when all
stick again. Each event gives one row of the catalogue (``C_*`` columns).
"""

from __future__ import annotations

import math

import numpy as np
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
from .engine import MAX_FACTOR, MIN_FACTOR, SAFETY, _root8
from .laws import friction_scalar, params

# modes of a block
STUCK = 0
# (+1: slipping forward, -1: slipping backward)

# statuses of a call
CH_EVENTS = 0  # the requested number of events is complete
CH_T_MAX = 1  # the time limit is reached
CH_PAUSED = 2  # the step budget of this call is spent; call again to go on
CH_STEP_TOO_SMALL = 3
CH_NONFINITE = 4
CH_STALLED = 5  # events at the same time again and again: no progress (a state the engine cannot resolve)

# scalar state (``sc``)
S_T = 0
S_H = 1
S_IN_EVENT = 2
S_EV_T0 = 3
S_EV_EPI = 4
S_EV_PEAK = 5
S_EV_WD = 6
S_EV_WF = 7
S_EV_E0 = 8
S_NSTEP = 9
S_NREJ = 10
S_EV_N = 11
S_EV_LO = 12
S_EV_HI = 13
S_STALL = 14  # events in a row without progress in time, counted over calls
S_NWORK = 15  # work done, counted as WORK_STEP plus the slipping blocks per step (the calls' budget)
NSC = 16

# catalogue columns
C_T0 = 0
C_T1 = 1
C_EPI = 2
C_NB = 3
C_MOMENT = 4
C_PEAK = 5
C_WD = 6
C_WF = 7
C_DE = 8
C_LO = 9
C_HI = 10
NCAT = 11

#: events closer than this fraction of a step are simultaneous
SIMULTANEOUS = 1e-12
#: the shortest slip from rest sought inside a step (a fraction of the step)
PROBE_MIN = 2.0**-40
#: the rounding of a speed integrated over a step, per unit step and unit force (64 ulps): a block
#: started from rest whose speed stays within it while it is pushed forward has not stopped
ROUND_SPEED = 64 * 2.220446049250313e-16
#: steps in a row that end at an event without advancing the time: the engine stops (CH_STALLED)
STALL_STEPS = 10_000
#: the cost of a step beside its slipping blocks', in blocks (the work budget of a call)
WORK_STEP = 8
#: a stuck block this close to its threshold (units of static friction, times
#: ``1 + nu tau`` for the rounding of the load) breaks away
BREAK_TOL = 1e-13
H_FIRST = 1e-3


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
def elastic_energy(x, t, nu, ell2, periodic):  # type: ignore[no-untyped-def]
    """Return the elastic energy of loading and coupling springs at time ``t``."""
    n = x.shape[0]
    e = 0.0
    for j in range(n):
        s = nu * t - x[j]
        e += 0.5 * s * s
    nb = n if periodic else n - 1
    for j in range(nb):
        dx = x[(j + 1) % n] - x[j]
        e += 0.5 * ell2 * dx * dx
    return e


@njit(cache=True, inline="always")
def _coupling(x, j, n, periodic, ell2):  # type: ignore[no-untyped-def]
    xj = x[j]
    return ell2 * ((x[_left(j, n, periodic)] - xj) + (x[_right(j, n, periodic)] - xj))


@njit(cache=True)
def stuck_force(x, j, t, nu, ell2, periodic):  # type: ignore[no-untyped-def]
    """Return the elastic force on block ``j`` with every position taken from ``x``."""
    n = x.shape[0]
    return _coupling(x, j, n, periodic, ell2) + (nu * t - x[j])


@njit(cache=True)
def _tree_set(tree, size, j, value):  # type: ignore[no-untyped-def]
    i = size + j
    tree[i] = value
    i //= 2
    while i >= 1:
        a = tree[2 * i]
        b = tree[2 * i + 1]
        tree[i] = a if a <= b else b
        i //= 2


@njit(cache=True)
def _tree_argmin(tree, size):  # type: ignore[no-untyped-def]
    i = 1
    while i < size:
        i = 2 * i if tree[2 * i] <= tree[2 * i + 1] else 2 * i + 1
    return i - size


@njit(cache=True)
def _far_time(x, mode, phi, j, nu, ell2, periodic):  # type: ignore[no-untyped-def]
    """Closed-form breakaway time of stuck block ``j`` whose neighbours stick (inf otherwise)."""
    n = x.shape[0]
    if mode[j] != STUCK or mode[_left(j, n, periodic)] != STUCK or mode[_right(j, n, periodic)] != STUCK:
        return math.inf
    # e_j(t) = coupling + nu t - x_j reaches phi_j
    return (phi[j] - _coupling(x, j, n, periodic, ell2) + x[j]) / nu


@njit(cache=True)
def _tree_refresh(tree, size, x, mode, phi, j, nu, ell2, periodic):  # type: ignore[no-untyped-def]
    n = x.shape[0]
    for jj in (_left(j, n, periodic), j, _right(j, n, periodic)):
        _tree_set(tree, size, jj, _far_time(x, mode, phi, jj, nu, ell2, periodic))


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
def _dense(ctx, t, y, y_new, h, K, F, ytmp, nvar):  # type: ignore[no-untyped-def]
    """Fill ``F`` with the interpolant of the step just taken (3 more stages in ``K``)."""
    for j in range(N_STAGES + 1, N_STAGES_EXTENDED):
        vec_stage(y, K, h, j, nvar, ytmp)
        _rhs(ctx, t + C[j] * h, ytmp, K[j])
    vec_dense_coeffs(y, y_new, h, K, F, nvar)


@njit(cache=True)
def _event_begin(sc, x, v, t, j, nu, ell2, periodic):  # type: ignore[no-untyped-def]
    sc[S_IN_EVENT] = 1.0
    sc[S_EV_T0] = t
    sc[S_EV_EPI] = j
    sc[S_EV_PEAK] = 0.0
    sc[S_EV_WD] = 0.0
    sc[S_EV_WF] = 0.0
    sc[S_EV_N] = 0.0
    sc[S_EV_LO] = j
    sc[S_EV_HI] = j
    sc[S_EV_E0] = elastic_energy(x, t, nu, ell2, periodic)


@njit(cache=True)
def _slip_on(j, x, idx, pos, ws):  # type: ignore[no-untyped-def]
    """Insert block ``j`` into the sorted set of slipping blocks (``ws = [m, sum of stuck x]``)."""
    if pos[j] >= 0:
        return
    k = int(ws[0])
    while k > 0 and idx[k - 1] > j:
        idx[k] = idx[k - 1]
        pos[idx[k]] = k
        k -= 1
    idx[k] = j
    pos[j] = k
    ws[0] += 1.0
    ws[1] -= x[j]


@njit(cache=True)
def _slip_off(j, x, idx, pos, ws):  # type: ignore[no-untyped-def]
    """Remove block ``j`` (now stuck at ``x[j]``) from the set of slipping blocks."""
    k = pos[j]
    if k < 0:
        return
    m = int(ws[0])
    for i in range(k, m - 1):
        idx[i] = idx[i + 1]
        pos[idx[i]] = i
    pos[j] = -1
    ws[0] -= 1.0
    ws[1] += x[j]


@njit(cache=True)
def _start_slip(j, d, t, x, v, mode, sc, ev_x0, ev_flag, ev_list, idx, pos, ws):  # type: ignore[no-untyped-def]
    mode[j] = d
    v[j] = 0.0
    _slip_on(j, x, idx, pos, ws)
    if ev_flag[j] == 0:
        ev_flag[j] = 1
        nb = int(sc[S_EV_N])
        ev_list[nb] = j
        ev_x0[j] = x[j]
        sc[S_EV_N] = nb + 1
        if j < sc[S_EV_LO]:
            sc[S_EV_LO] = j
        if j > sc[S_EV_HI]:
            sc[S_EV_HI] = j


@njit(cache=True)
def _event_end(sc, x, t, nu, ell2, periodic, ev_x0, ev_flag, ev_list, cat, row, slips):  # type: ignore[no-untyped-def]
    nb = int(sc[S_EV_N])
    moment = 0.0
    record = row < slips.shape[0]
    if record:
        for j in range(slips.shape[1]):
            slips[row, j] = 0.0
    for i in range(nb):
        j = ev_list[i]
        dx = x[j] - ev_x0[j]
        moment += dx
        if record:
            slips[row, j] = dx
        ev_flag[j] = 0
    cat[row, C_T0] = sc[S_EV_T0]
    cat[row, C_T1] = t
    cat[row, C_EPI] = sc[S_EV_EPI]
    cat[row, C_NB] = nb
    cat[row, C_MOMENT] = moment
    cat[row, C_PEAK] = sc[S_EV_PEAK]
    cat[row, C_WD] = sc[S_EV_WD]
    cat[row, C_WF] = sc[S_EV_WF]
    cat[row, C_DE] = elastic_energy(x, t, nu, ell2, periodic) - sc[S_EV_E0]
    cat[row, C_LO] = sc[S_EV_LO]
    cat[row, C_HI] = sc[S_EV_HI]
    sc[S_IN_EVENT] = 0.0
    sc[S_EV_N] = 0.0


@njit(cache=True)
def _break_near(  # type: ignore[no-untyped-def]
    j0,
    t,
    x,
    v,
    mode,
    phi,
    nu,
    ell2,
    periodic,
    backward,
    tree,
    size,
    sc,
    ev_x0,
    ev_flag,
    ev_list,
    idx,
    pos,
    ws,
    stack,
):
    """Break away the stuck blocks at (or within BREAK_TOL of) their threshold around block ``j0``.

    A change of block ``j0`` can only bring its neighbours to their threshold; a
    breakaway moves nothing at once, so the cascade goes on from each block that
    breaks (in index order of the neighbours). Then every closed-form breakaway
    time already reached is taken. Returns the number of blocks that broke away.
    """
    n = x.shape[0]
    tol = BREAK_TOL * (1.0 + abs(nu * t))
    count = 0
    top = 0
    if j0 >= 0:
        stack[0] = j0
        top = 1
    while True:
        while top > 0:
            top -= 1
            jc = stack[top]
            for j in (_left(jc, n, periodic), jc, _right(jc, n, periodic)):
                if mode[j] != STUCK:
                    continue
                e = stuck_force(x, j, t, nu, ell2, periodic)
                d = 0
                if e >= phi[j] - tol:
                    d = 1
                elif backward and e <= -phi[j] + tol:
                    d = -1
                if d != 0:
                    _start_slip(j, d, t, x, v, mode, sc, ev_x0, ev_flag, ev_list, idx, pos, ws)
                    _tree_refresh(tree, size, x, mode, phi, j, nu, ell2, periodic)
                    count += 1
                    stack[top] = j
                    top += 1
        if tree[1] > t:
            break
        # a closed-form time reached (rounding aside)
        j = _tree_argmin(tree, size)
        _start_slip(j, 1, t, x, v, mode, sc, ev_x0, ev_flag, ev_list, idx, pos, ws)
        _tree_refresh(tree, size, x, mode, phi, j, nu, ell2, periodic)
        count += 1
        stack[0] = j
        top = 1
    return count


@njit(cache=True)
def chain_run(  # type: ignore[no-untyped-def]
    law,
    lp,
    nu,
    ell2,
    periodic,
    backward,
    phi,
    x,
    v,
    mode,
    sc,
    ev_x0,
    ev_flag,
    ev_list,
    max_events,
    t_max,
    rtol,
    atol,
    max_steps,
    max_work,
    max_event,
    cat,
    slips,
):
    """Advance the chain until ``max_events`` events are complete, ``t_max``, ``max_steps`` or ``max_work``.

    The state (``x``, ``v``, ``mode``, ``sc`` and the event work arrays) is
    updated in place, so that calling again continues exactly where this call
    stopped. Complete events are written to the rows of ``cat`` (``NCAT``
    columns) and, for the first ``slips.shape[0]`` of them, each block's slip
    to the rows of ``slips``.

    A call pauses (``CH_PAUSED``) after ``max_steps`` steps or ``max_work`` units of
    work (a step counts ``WORK_STEP`` plus its slipping blocks: about proportional to
    its time), and as soon as the event in progress has lasted longer than
    ``max_event`` (time units: the caller's mark of a chain that slides for ever,
    seen at the step that passes it); where it pauses changes nothing but the
    rounding of the events' works (summed per segment, and a pause starts a segment).

    Returns ``(events_written, status)`` with a ``CH_*`` status.
    """
    n = x.shape[0]
    P = params(lp)
    size = 1
    while size < n:
        size *= 2
    tree = np.full(2 * size, math.inf)
    for j in range(n):
        _tree_set(tree, size, j, _far_time(x, mode, phi, j, nu, ell2, periodic))
    idx = np.empty(n, dtype=np.int64)
    pos = np.full(n, -1, dtype=np.int64)
    adj = np.empty(n, dtype=np.int64)
    e_adj = np.empty(n)  # their forces at the start of the step
    e_end = np.empty(n)  # and at its end
    slot = np.full(n, -1, dtype=np.int64)  # a stuck neighbour's place in adj
    nbl = np.empty(n, dtype=np.int64)
    nbr = np.empty(n, dtype=np.int64)
    dk = np.empty(n, dtype=np.int64)
    phk = np.empty(n)
    stack = np.empty(n + 1, dtype=np.int64)
    ws = np.zeros(2)  # slipping blocks, sum of the stuck blocks' positions
    for j in range(n):
        if mode[j] != STUCK:
            idx[int(ws[0])] = j
            pos[j] = int(ws[0])
            ws[0] += 1.0
        else:
            ws[1] += x[j]
    nv = 2 * n + 2  # (x, v) of m slipping blocks, two works, at most n - m stuck neighbours: <= n + m + 2
    y = np.empty(nv)
    y_new = np.empty(nv)
    ytmp = np.empty(nv)
    K = np.empty((N_STAGES_EXTENDED, nv))
    F = np.empty((7, nv))
    ev_x = np.empty(2 * n)
    ev_k = np.empty(2 * n, dtype=np.int64)
    ev_kind = np.empty(2 * n, dtype=np.int64)
    pk_x = np.empty(n)
    pk_v = np.empty(n)
    written = 0
    steps = 0
    work_start = sc[S_NWORK]
    stalled = int(sc[S_STALL])
    t = sc[S_T]
    # a block beyond its backward threshold while every block sticks slips back at once. While
    # all stick the forces only grow (nu t), and the stops of an event check it themselves, so
    # only a start holds one (random positions with a large ell): looked for once a call, not
    # at every jump. It was left stuck, and every later event came early (the chain audit);
    # every such block starts, the worst first (the event's epicentre), the others with it at
    # the same instant: one far from the first was left stuck until a neighbour moved (the
    # second chain audit, helper-38: ten blocks, ell 30, seed 5)
    j_back = -1
    n_back = 0
    back = np.empty(n, dtype=np.int64)
    if backward and ws[0] == 0.0:
        worst = BREAK_TOL * (1.0 + abs(nu * t))
        for j in range(n):
            beyond = -phi[j] - stuck_force(x, j, t, nu, ell2, periodic)
            if beyond > BREAK_TOL * (1.0 + abs(nu * t)):
                back[n_back] = j
                n_back += 1
            if beyond > worst:
                worst = beyond
                j_back = j
    while True:
        if stalled > STALL_STEPS:
            sc[S_T] = t
            return written, CH_STALLED
        m = int(ws[0])
        n_stuck = n - m
        if m == 0:
            if sc[S_IN_EVENT] != 0.0:
                _event_end(sc, x, t, nu, ell2, periodic, ev_x0, ev_flag, ev_list, cat, written, slips)
                written += 1
            if written >= max_events:
                sc[S_T] = t
                sc[S_STALL] = stalled
                return written, CH_EVENTS
            j0 = j_back  # a start's block beyond its backward threshold (see above the loop)
            d0 = -1 if j_back >= 0 else 1
            j_back = -1
            if j0 < 0:
                tb = tree[1]
                if tb > t_max:
                    sc[S_T] = t_max
                    return written, CH_T_MAX
                if tb > t:
                    t = tb
                j0 = _tree_argmin(tree, size)
            _event_begin(sc, x, v, t, j0, nu, ell2, periodic)
            q = 0
            while True:
                _start_slip(j0, d0, t, x, v, mode, sc, ev_x0, ev_flag, ev_list, idx, pos, ws)
                _tree_refresh(tree, size, x, mode, phi, j0, nu, ell2, periodic)
                _break_near(
                    j0,
                    t,
                    x,
                    v,
                    mode,
                    phi,
                    nu,
                    ell2,
                    periodic,
                    backward,
                    tree,
                    size,
                    sc,
                    ev_x0,
                    ev_flag,
                    ev_list,
                    idx,
                    pos,
                    ws,
                    stack,
                )
                # the start's other blocks beyond their backward threshold, at this instant
                j0 = -1
                while q < n_back and j0 < 0:
                    jb = back[q]
                    q += 1
                    beyond = -phi[jb] - stuck_force(x, jb, t, nu, ell2, periodic)
                    if mode[jb] == STUCK and beyond > BREAK_TOL * (1.0 + abs(nu * t)):
                        j0 = jb
                if j0 < 0:
                    break
                d0 = -1
            n_back = 0
            continue
        s_stuck = n_stuck * nu * t - ws[1]
        # stuck blocks next to slipping ones: their forces are watched step by step
        na = 0
        for k in range(m):
            j = idx[k]
            for jj in (_left(j, n, periodic), _right(j, n, periodic)):
                if mode[jj] == STUCK and slot[jj] < 0:
                    slot[jj] = na
                    adj[na] = jj
                    na += 1
        for k in range(m):
            j = idx[k]
            y[2 * k] = x[j]
            y[2 * k + 1] = v[j]
        nvar = 2 * m + 2
        nctl = 2 * m
        y[2 * m] = 0.0
        y[2 * m + 1] = 0.0
        for i in range(na):  # constant over the segment: in every stage's state
            xa = x[adj[i]]
            y[nvar + i] = xa
            ytmp[nvar + i] = xa
            y_new[nvar + i] = xa
        for k in range(m):
            j = idx[k]
            dk[k] = mode[j]
            phk[k] = phi[j]
            for side in range(2):
                jj = _left(j, n, periodic) if side == 0 else _right(j, n, periodic)
                q = 2 * pos[jj] if pos[jj] >= 0 else nvar + slot[jj]
                if side == 0:
                    nbl[k] = q
                else:
                    nbr[k] = q
        for i in range(na):
            slot[adj[i]] = -1
            e_adj[i] = stuck_force(x, adj[i], t, nu, ell2, periodic)
        t_ref = t
        ctx = (law, P, nu, ell2, nbl, nbr, dk, phk, m, s_stuck, n_stuck, t_ref)
        _rhs(ctx, t, y, K[0])
        h = sc[S_H] if sc[S_H] > 0.0 else H_FIRST
        done = False
        nev = 0
        # ------------------------------------------------------------- steps
        while True:
            if (
                steps >= max_steps
                or sc[S_NWORK] - work_start >= max_work
                or (sc[S_IN_EVENT] != 0.0 and t - sc[S_EV_T0] > max_event)
            ):
                for k in range(m):
                    x[idx[k]] = y[2 * k]
                    v[idx[k]] = y[2 * k + 1]
                sc[S_EV_WD] += y[2 * m]
                sc[S_EV_WF] += y[2 * m + 1]
                sc[S_T] = t
                sc[S_H] = h
                sc[S_STALL] = stalled
                return written, CH_PAUSED
            t_far = tree[1]
            limit = min(t_far, t_max) - t
            hit = False
            if h >= limit:
                h = limit
                hit = True
            if h <= 0.0:
                break  # a closed-form breakaway (or the time limit) now
            for s in range(1, N_STAGES):
                vec_stage(y, K, h, s, nvar, ytmp)
                _rhs(ctx, t + C[s] * h, ytmp, K[s])
            vec_advance(y, K, h, nvar, y_new)
            _rhs(ctx, t + h, y_new, K[N_STAGES])
            err = vec_error(y, y_new, K, h, nctl, rtol, atol)
            steps += 1
            sc[S_NSTEP] += 1.0
            sc[S_NWORK] += WORK_STEP + m
            if not math.isfinite(err) or err > 1.0:
                sc[S_NREJ] += 1.0
                if math.isfinite(err):
                    h *= max(MIN_FACTOR, SAFETY / _root8(err))
                else:
                    h *= MIN_FACTOR
                if h < 1e-14 * max(1.0, abs(t)):
                    for k in range(m):
                        x[idx[k]] = y[2 * k]
                        v[idx[k]] = y[2 * k + 1]
                    sc[S_T] = t
                    return written, CH_STEP_TOO_SMALL if math.isfinite(err) else CH_NONFINITE
                continue
            # ------------------------------------------------- events in the step
            nev = 0
            have_dense = False
            peak = sc[S_EV_PEAK]
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
                    _dense(ctx, t, y, y_new, h, K, F, ytmp, nvar)
                    have_dense = True
                xm = 2.0
                if peak_in or dip_in:
                    xm = _root(
                        G_VEL_SLOPE,
                        F,
                        y,
                        k,
                        1.0,
                        0.0,
                        x,
                        j,
                        nu,
                        ell2,
                        periodic,
                        pos,
                        t,
                        h,
                        0.0,
                        d * a0 * h,
                        1.0,
                        d * a1 * h,
                    )
                if peak_in:
                    pk_x[k] = xm
                    pk_v[k] = abs(dense_eval(F, y, xm, 2 * k + 1))
                if g1 <= 0.0:
                    if g0 > 0.0:
                        xe = _root(
                            G_VEL, F, y, k, d, 0.0, x, j, nu, ell2, periodic, pos, t, h, 0.0, g0, 1.0, g1
                        )
                    else:
                        # started at rest: the stop is where the speed, grown first, returns to 0;
                        # a slip shorter than half the step is sought closer to its start (a force
                        # that touches the threshold and turns back: a slip of a few 1e-5 inside a
                        # step of 4e-4 was taken for none, and the block slipped on at once, again
                        # and again, at the same time)
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
                            xe = _root(
                                G_VEL, F, y, k, d, 0.0, x, j, nu, ell2, periodic, pos, t, h, xs, gs, xb, gb_
                            )
                        elif a1 > 0.0 and -g_low <= ROUND_SPEED * h * (1.0 + ell2 + abs(nu * t)):
                            # pushed forward at the end of the step, with a speed that never left
                            # the rounding of its increments: no stop. Three blocks at threshold
                            # together (c = 0.05, rtol 1e-11): one's step was cut to 6.7e-14 by its
                            # twin's breakaway, its speed came out -7e-30 for +2e-29, and it stopped
                            # at once and broke away again at the same time 10000 times (stalled)
                            y_new[2 * k + 1] = 0.0
                        else:
                            xe = 0.0
                elif dip_in:
                    gm = d * dense_eval(F, y, xm, 2 * k + 1)
                    if gm <= 0.0 and g0 > 0.0:
                        xe = _root(
                            G_VEL, F, y, k, d, 0.0, x, j, nu, ell2, periodic, pos, t, h, 0.0, g0, xm, gm
                        )
                if xe >= 0.0:
                    ev_x[nev] = xe
                    ev_k[nev] = j
                    ev_kind[nev] = 0
                    nev += 1
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
                    xe = -1.0
                    if gb >= 0.0:
                        if not have_dense:
                            _dense(ctx, t, y, y_new, h, K, F, ytmp, nvar)
                            have_dense = True
                        xe = _root(
                            G_FORCE,
                            F,
                            y,
                            0,
                            sgn,
                            sgn * phi[j],
                            x,
                            j,
                            nu,
                            ell2,
                            periodic,
                            pos,
                            t,
                            h,
                            0.0,
                            min(ga, 0.0),
                            1.0,
                            gb,
                        )
                    elif sgn * de0 > 0.0 and sgn * de1 < 0.0:  # an extremum of the force inside
                        if not have_dense:
                            _dense(ctx, t, y, y_new, h, K, F, ytmp, nvar)
                            have_dense = True
                        xm = _root(
                            G_FORCE_SLOPE,
                            F,
                            y,
                            0,
                            1.0,
                            0.0,
                            x,
                            j,
                            nu,
                            ell2,
                            periodic,
                            pos,
                            t,
                            h,
                            0.0,
                            de0,
                            1.0,
                            de1,
                        )
                        gm = sgn * (_force_at(F, y, xm, x, j, nu, ell2, periodic, pos, t, h) - sgn * phi[j])
                        if gm >= 0.0:
                            xe = _root(
                                G_FORCE,
                                F,
                                y,
                                0,
                                sgn,
                                sgn * phi[j],
                                x,
                                j,
                                nu,
                                ell2,
                                periodic,
                                pos,
                                t,
                                h,
                                0.0,
                                min(ga, 0.0),
                                xm,
                                gm,
                            )
                    if xe >= 0.0:
                        ev_x[nev] = xe
                        ev_k[nev] = j
                        ev_kind[nev] = 1 if sgn > 0.0 else -1
                        nev += 1
            xs = 2.0
            for i in range(nev):
                if ev_x[i] < xs:
                    xs = ev_x[i]
            for k in range(m):  # the speed's maxima before the first event
                if pk_x[k] <= xs and pk_v[k] > peak:
                    peak = pk_v[k]
            if nev == 0:
                for i in range(na):
                    e_adj[i] = e_end[i]
                for k in range(m):
                    vk = abs(y_new[2 * k + 1])
                    if vk > peak:
                        peak = vk
                sc[S_EV_PEAK] = peak
                for c in range(nvar):
                    y[c] = y_new[c]
                    K[0, c] = K[N_STAGES, c]
                t = t + h
                if not hit:
                    fac = MAX_FACTOR if err == 0.0 else min(MAX_FACTOR, max(MIN_FACTOR, SAFETY / _root8(err)))
                    sc[S_H] = h * fac
                    h = sc[S_H]
                    continue
                break  # a closed-form breakaway or the time limit: the controller's size is kept
            # ------------------------------------------------- the earliest events
            if not have_dense:
                _dense(ctx, t, y, y_new, h, K, F, ytmp, nvar)
                have_dense = True
            for c in range(nvar):
                y[c] = dense_eval(F, y, xs, c) if xs < 1.0 else y_new[c]
            for k in range(m):
                vk = abs(y[2 * k + 1])
                if vk > peak:
                    peak = vk
            sc[S_EV_PEAK] = peak
            if not hit and err > 0.0:
                sc[S_H] = h * min(MAX_FACTOR, max(MIN_FACTOR, SAFETY / _root8(err)))
            t_was = t
            t = t + xs * h if xs < 1.0 else t + h
            stalled = stalled + 1 if t == t_was else 0
            for k in range(m):
                x[idx[k]] = y[2 * k]
                v[idx[k]] = y[2 * k + 1]
            sc[S_EV_WD] += y[2 * m]
            sc[S_EV_WF] += y[2 * m + 1]
            done = True
            # the simultaneous events, in block order (insertion sort: a handful)
            ns = 0
            for i in range(nev):
                if ev_x[i] <= xs + SIMULTANEOUS:
                    ev_k[ns] = ev_k[i]
                    ev_kind[ns] = ev_kind[i]
                    ns += 1
            for i in range(1, ns):
                kk = ev_k[i]
                kd = ev_kind[i]
                q = i
                while q > 0 and ev_k[q - 1] > kk:
                    ev_k[q] = ev_k[q - 1]
                    ev_kind[q] = ev_kind[q - 1]
                    q -= 1
                ev_k[q] = kk
                ev_kind[q] = kd
            for i in range(ns):
                j = ev_k[i]
                if ev_kind[i] == 0:  # a stop
                    v[j] = 0.0
                    e = stuck_force(x, j, t, nu, ell2, periodic)
                    if backward and e < -phi[j]:
                        mode[j] = -1
                    elif e >= phi[j]:
                        mode[j] = 1
                    else:
                        mode[j] = STUCK
                        _slip_off(j, x, idx, pos, ws)
                elif mode[j] == STUCK:
                    _start_slip(j, ev_kind[i], t, x, v, mode, sc, ev_x0, ev_flag, ev_list, idx, pos, ws)
                _tree_refresh(tree, size, x, mode, phi, j, nu, ell2, periodic)
            nev = ns
            break
        # the segment ended: events, a closed-form breakaway, or the time limit
        if not done:
            for k in range(m):
                x[idx[k]] = y[2 * k]
                v[idx[k]] = y[2 * k + 1]
            sc[S_EV_WD] += y[2 * m]
            sc[S_EV_WF] += y[2 * m + 1]
        sc[S_T] = t
        if t >= t_max:
            return written, CH_T_MAX
        if done:
            for i in range(nev):
                _break_near(
                    ev_k[i],
                    t,
                    x,
                    v,
                    mode,
                    phi,
                    nu,
                    ell2,
                    periodic,
                    backward,
                    tree,
                    size,
                    sc,
                    ev_x0,
                    ev_flag,
                    ev_list,
                    idx,
                    pos,
                    ws,
                    stack,
                )
        else:
            _break_near(
                -1,
                t,
                x,
                v,
                mode,
                phi,
                nu,
                ell2,
                periodic,
                backward,
                tree,
                size,
                sc,
                ev_x0,
                ev_flag,
                ev_list,
                idx,
                pos,
                ws,
                stack,
            )
