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
closed form from their neighbours. The stops of slipping blocks and the
breakaways of stuck blocks next to them are located on the dense output
(:mod:`._chain_step`). A stuck block whose neighbours are stuck too feels a force
that grows at the rate ``nu``, so its breakaway time is known in closed form; the
earliest such time is kept in a binary heap (a segment tree) and a step never
passes it.

When every block sticks, the chain jumps to the next breakaway in closed form.
Events closer than :data:`SIMULTANEOUS` (in units of a step) are handled
together, in block order; a stuck block within :data:`BREAK_TOL` of its
threshold breaks with its neighbours (identical blocks move as one).

After a stop a block sticks if ``-phi_j <= e_j < phi_j``; otherwise it slips on
at once, backward if ``e_j < -phi_j`` (unless backward slip is switched off, the
convention of Carlson and Langer: friction at rest bounded only from above).

An *event* starts when a block breaks away while all stick and ends when all
stick again. Each event gives one row of the catalogue (``C_*`` columns); the
rows, the scalar state (``S_*``) and the statuses (``CH_*``) are read above this
module through :mod:`.results` (:class:`~.results.EventRows`,
:class:`~.results.ChainScalars`, :class:`~.results.ChainStatus`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ._chain_step import PROBE_MIN as PROBE_MIN  # the step's constants, importable from here too
from ._chain_step import ROUND_SPEED as ROUND_SPEED
from ._chain_step import SIMULTANEOUS as SIMULTANEOUS
from ._chain_step import (
    _dense,
    _find_breakaways,
    _find_stops,
    _left,
    _rhs,
    _right,
    _simultaneous,
    _step,
)
from .dop853 import N_STAGES, N_STAGES_EXTENDED, dense_eval
from .engine import MAX_FACTOR, MIN_FACTOR, SAFETY, _root8
from .laws import params

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

#: steps in a row that end at an event without advancing the time: the engine stops (CH_STALLED)
STALL_STEPS = 10_000
#: the cost of a step beside its slipping blocks', in blocks (the work budget of a call)
WORK_STEP = 8
#: a stuck block this close to its threshold (units of static friction, times
#: ``1 + nu tau`` for the rounding of the load) breaks away
BREAK_TOL = 1e-13
H_FIRST = 1e-3

# The compiled functions take the chain's arrays one by one, and chain_run allocates the work
# arrays of its steps itself: numba passes an array argument without counting a reference, while
# taking one out of a tuple counts one at every call, and LLVM knows that arrays allocated in
# chain_run do not overlap. A segment lasts 1 to 3 steps on chains of 100 to 1000 blocks
# (benchmarks/bench_chain.py): arrays in tuples, or allocated by a helper, made the engine 5 to
# 15 % slower there. Tuples hold scalars, and the step's interpolant ``at`` (unpacked only in
# functions compiled into their caller):
#   cfg = (nu, ell2, periodic, backward): the drive, the coupling, the ends, backward slip;
#   at  = (F, y, x, pos, nu, ell2, periodic, t0, h): the interpolant of the step from t0.
# The arrays: x, v, mode (the blocks), phi (thresholds), sc, ev_x0, ev_flag, ev_list (the
# scalar state and the event in progress), idx, pos, ws (the slipping blocks: _slip_on), tree,
# size (the closed-form breakaway times: _tree_set), and the work arrays of chain_run.


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
    """Set leaf ``j`` of the binary heap of breakaway times (``tree[1]``: the earliest)."""
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
def _far_tree(x, mode, phi, nu, ell2, periodic):  # type: ignore[no-untyped-def]
    """Return the heap of every block's closed-form breakaway time, and its number of leaves."""
    n = x.shape[0]
    size = 1
    while size < n:
        size *= 2
    tree = np.full(2 * size, math.inf)
    for j in range(n):
        _tree_set(tree, size, j, _far_time(x, mode, phi, j, nu, ell2, periodic))
    return tree, size


@njit(cache=True)
def _tree_refresh(tree, size, x, mode, phi, j, nu, ell2, periodic):  # type: ignore[no-untyped-def]
    """Recompute the closed-form breakaway times of block ``j`` and its neighbours."""
    n = x.shape[0]
    for jj in (_left(j, n, periodic), j, _right(j, n, periodic)):
        _tree_set(tree, size, jj, _far_time(x, mode, phi, jj, nu, ell2, periodic))


@njit(cache=True)
def _event_begin(sc, x, t, j, nu, ell2, periodic):  # type: ignore[no-untyped-def]
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
def _slipping_set(x, mode):  # type: ignore[no-untyped-def]
    """Return the set of slipping blocks of the state: ``idx``, ``pos`` and ``ws`` of :func:`_slip_on`."""
    n = x.shape[0]
    idx = np.empty(n, dtype=np.int64)
    pos = np.full(n, -1, dtype=np.int64)
    ws = np.zeros(2)  # slipping blocks, sum of the stuck blocks' positions
    for j in range(n):
        if mode[j] != STUCK:
            idx[int(ws[0])] = j
            pos[j] = int(ws[0])
            ws[0] += 1.0
        else:
            ws[1] += x[j]
    return idx, pos, ws


@njit(cache=True)
def _start_slip(j, d, x, v, mode, sc, ev_x0, ev_flag, ev_list, idx, pos, ws):  # type: ignore[no-untyped-def]
    """Set block ``j`` slipping in direction ``d`` from rest; count it in the event in progress."""
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
    """Write the event that ends at ``t`` to row ``row`` of ``cat`` (and its slips, where kept)."""
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
def _break_near(j0, t, cfg, phi, x, v, mode, tree, size, sc, ev_x0, ev_flag, ev_list, idx, pos, ws, stack):  # type: ignore[no-untyped-def]
    """Break away the stuck blocks at (or within BREAK_TOL of) their threshold around block ``j0``.

    A change of block ``j0`` can only bring its neighbours to their threshold; a
    breakaway moves nothing at once, so the cascade goes on from each block that
    breaks (in index order of the neighbours). Then every closed-form breakaway
    time already reached is taken. Returns the number of blocks that broke away.
    """
    nu, ell2, periodic, backward = cfg
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
                    _start_slip(j, d, x, v, mode, sc, ev_x0, ev_flag, ev_list, idx, pos, ws)
                    _tree_refresh(tree, size, x, mode, phi, j, nu, ell2, periodic)
                    count += 1
                    stack[top] = j
                    top += 1
        if tree[1] > t:
            break
        # a closed-form time reached (rounding aside)
        j = _tree_argmin(tree, size)
        _start_slip(j, 1, x, v, mode, sc, ev_x0, ev_flag, ev_list, idx, pos, ws)
        _tree_refresh(tree, size, x, mode, phi, j, nu, ell2, periodic)
        count += 1
        stack[0] = j
        top = 1
    return count


@njit(cache=True)
def _backward_at_start(t, cfg, phi, x, ws):  # type: ignore[no-untyped-def]
    """Return the blocks beyond their backward threshold while every block sticks, their count, the worst.

    While all stick the forces only grow (``nu t``), and the stops of an event check
    their blocks themselves, so only the start of a call holds such blocks (random
    positions with a large ``ell``), and they are looked for once a call. Each of them
    slips back at once: the worst starts the event (its epicentre), the others start
    with it at the same instant (ten blocks, ``ell = 30``, seed 5 start with two of them
    far apart); a block left stuck there would make every later event come early.
    """
    nu, ell2, periodic, backward = cfg
    n = x.shape[0]
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
    return back, n_back, j_back


@njit(cache=True)
def _event_start(  # type: ignore[no-untyped-def]
    t, j_back, back, n_back, cfg, phi, x, v, mode, tree, size, sc, ev_x0, ev_flag, ev_list, idx, pos, ws,
    stack,
):  # fmt: skip
    """Start an event while every block sticks; return its time.

    Its epicentre is ``j_back`` slipping backward where there is one (the other
    blocks of ``back`` beyond their backward threshold start with it: see
    :func:`_backward_at_start`), else the block of the earliest closed-form breakaway.
    """
    nu, ell2, periodic, _ = cfg
    j0 = j_back
    d0 = -1 if j_back >= 0 else 1
    if j0 < 0:
        tb = tree[1]
        if tb > t:
            t = tb
        j0 = _tree_argmin(tree, size)
    _event_begin(sc, x, t, j0, nu, ell2, periodic)
    q = 0
    while True:
        _start_slip(j0, d0, x, v, mode, sc, ev_x0, ev_flag, ev_list, idx, pos, ws)
        _tree_refresh(tree, size, x, mode, phi, j0, nu, ell2, periodic)
        _break_near(j0, t, cfg, phi, x, v, mode, tree, size, sc, ev_x0, ev_flag, ev_list, idx, pos, ws, stack)
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
    return t


@njit(cache=True)
def _segment_begin(  # type: ignore[no-untyped-def]
    t, cfg, phi, x, v, mode, idx, pos, m, adj, e_adj, slot, nbl, nbr, dk, phk, y, y_new, ytmp
):
    """Gather a segment's variables (the ``m`` slipping blocks, then their stuck neighbours) into ``y``.

    Fills the watched stuck blocks (``adj``) and their forces (``e_adj``), the places
    of each slipping block's neighbours in ``y`` (``nbl``, ``nbr``), its direction and
    threshold (``dk``, ``phk``); returns the number of watched blocks.
    """
    nu, ell2, periodic, _ = cfg
    n = x.shape[0]
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
    return na


@njit(cache=True, inline="always")
def _segment_end(x, v, y, idx, m, sc):  # type: ignore[no-untyped-def]
    """Copy the ``m`` slipping blocks' positions and velocities from ``y``; add the segment's works."""
    for k in range(m):
        x[idx[k]] = y[2 * k]
        v[idx[k]] = y[2 * k + 1]
    sc[S_EV_WD] += y[2 * m]
    sc[S_EV_WF] += y[2 * m + 1]


@njit(cache=True)
def _apply_events(  # type: ignore[no-untyped-def]
    t, ns, ev_k, ev_kind, cfg, phi, x, v, mode, tree, size, sc, ev_x0, ev_flag, ev_list, idx, pos, ws
):
    """Apply the first ``ns`` events (blocks ``ev_k``, kinds ``ev_kind``) at time ``t``, in order.

    A stop (kind 0) leaves the block stuck where its force is within its thresholds,
    else slipping on (backward below ``-phi``); a breakaway (kind +1 or -1) starts a
    stuck block slipping in that direction.
    """
    nu, ell2, periodic, backward = cfg
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
            _start_slip(j, ev_kind[i], x, v, mode, sc, ev_x0, ev_flag, ev_list, idx, pos, ws)
        _tree_refresh(tree, size, x, mode, phi, j, nu, ell2, periodic)


@njit(cache=True)
def chain_run(  # type: ignore[no-untyped-def]
    law, lp, nu, ell2, periodic, backward, phi, x, v, mode, sc, ev_x0, ev_flag, ev_list,
    max_events, t_max, rtol, atol, max_steps, max_work, max_event, cat, slips,
):  # fmt: skip
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

    The loop has two phases. While every block sticks, the event in progress ends
    (:func:`_event_end`) and the next one starts at the earliest breakaway
    (:func:`_event_start`). While some slip, a *segment* (the same blocks slip) is
    integrated: its variables gathered (:func:`_segment_begin`), then DOP853 steps
    (:func:`~._chain_step._step`) with the stops and breakaways found in each
    (:func:`~._chain_step._find_stops`, :func:`~._chain_step._find_breakaways`) until
    the earliest of them, applied (:func:`_apply_events`), or a closed-form breakaway
    or the time limit; the blocks it brings to their threshold break away
    (:func:`_break_near`).

    Returns ``(events_written, status)`` with a ``CH_*`` status.
    """
    n = x.shape[0]
    P = params(lp)
    cfg = (nu, ell2, periodic, backward)
    tree, size = _far_tree(x, mode, phi, nu, ell2, periodic)
    idx, pos, ws = _slipping_set(x, mode)
    # a segment's stuck blocks watched, their forces at the start and at the end of a step, a
    # stuck neighbour's place in adj; its slipping blocks' neighbours in y, directions, thresholds
    adj = np.empty(n, dtype=np.int64)
    e_adj = np.empty(n)
    e_end = np.empty(n)
    slot = np.full(n, -1, dtype=np.int64)
    nbl = np.empty(n, dtype=np.int64)
    nbr = np.empty(n, dtype=np.int64)
    dk = np.empty(n, dtype=np.int64)
    phk = np.empty(n)
    nv = 2 * n + 2  # (x, v) of m slipping blocks, two works, at most n - m stuck neighbours: <= n + m + 2
    y = np.empty(nv)
    y_new = np.empty(nv)
    ytmp = np.empty(nv)
    K = np.empty((N_STAGES_EXTENDED, nv))
    F = np.empty((7, nv))
    ev_x = np.empty(2 * n)  # a step's events (fraction of the step, block, kind), its speed maxima
    ev_k = np.empty(2 * n, dtype=np.int64)
    ev_kind = np.empty(2 * n, dtype=np.int64)
    pk_x = np.empty(n)
    pk_v = np.empty(n)
    stack = np.empty(n + 1, dtype=np.int64)
    written = 0
    steps = 0
    work_start = sc[S_NWORK]
    stalled = int(sc[S_STALL])
    t = sc[S_T]
    back, n_back, j_back = _backward_at_start(t, cfg, phi, x, ws)
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
            if j_back < 0 and tree[1] > t_max:
                sc[S_T] = t_max
                return written, CH_T_MAX
            t = _event_start(
                t, j_back, back, n_back, cfg, phi, x, v, mode, tree, size, sc, ev_x0, ev_flag, ev_list, idx,
                pos, ws, stack,
            )  # fmt: skip
            j_back = -1
            n_back = 0
            continue
        s_stuck = n_stuck * nu * t - ws[1]
        na = _segment_begin(
            t, cfg, phi, x, v, mode, idx, pos, m, adj, e_adj, slot, nbl, nbr, dk, phk, y, y_new, ytmp
        )
        nvar = 2 * m + 2
        nctl = 2 * m
        ctx = (law, P, nu, ell2, nbl, nbr, dk, phk, m, s_stuck, n_stuck, t)
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
                _segment_end(x, v, y, idx, m, sc)
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
            err = _step(ctx, t, h, y, y_new, ytmp, K, nvar, nctl, rtol, atol)
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
            at = (F, y, x, pos, nu, ell2, periodic, t, h)
            peak = sc[S_EV_PEAK]
            nev, have_dense = _find_stops(
                ctx, at, y_new, ytmp, K, nvar, idx, mode, ev_x, ev_k, ev_kind, pk_x, pk_v
            )
            nev, have_dense = _find_breakaways(
                ctx, at, y_new, ytmp, K, nvar, na, nev, have_dense, phi, backward, adj, e_adj, e_end, ev_x,
                ev_k, ev_kind,
            )  # fmt: skip
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
                _dense(ctx, t, h, y, y_new, ytmp, K, F, nvar)
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
            _segment_end(x, v, y, idx, m, sc)
            done = True
            nev = _simultaneous(xs, nev, ev_x, ev_k, ev_kind)
            _apply_events(
                t, nev, ev_k, ev_kind, cfg, phi, x, v, mode, tree, size, sc, ev_x0, ev_flag, ev_list, idx,
                pos, ws,
            )  # fmt: skip
            break
        # the segment ended: events, a closed-form breakaway, or the time limit
        if not done:
            _segment_end(x, v, y, idx, m, sc)
        sc[S_T] = t
        if t >= t_max:
            return written, CH_T_MAX
        if done:
            for i in range(nev):
                _break_near(
                    ev_k[i], t, cfg, phi, x, v, mode, tree, size, sc, ev_x0, ev_flag, ev_list, idx, pos, ws,
                    stack,
                )  # fmt: skip
        else:
            _break_near(-1, t, cfg, phi, x, v, mode, tree, size, sc, ev_x0, ev_flag, ev_list, idx, pos, ws,
                        stack)  # fmt: skip
