"""Synthetic records: the model's spring force sampled uniformly, with noise and drift."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..errors import ArgumentTypeError
from ..io.records import Record

__all__ = ["synthetic_record"]


def synthetic_record(
    params: Any,
    *,
    duration: Any,
    rate: Any,
    noise: Any = "0 N",
    drift: Any = "0 N/s",
    seed: int = 0,
    name: str = "synthetic",
    with_velocity: bool = False,
    start: Any = "0 s",
) -> Record:
    """Make a record from the model: uniform samples of the spring force, plus noise and drift.

    Parameters
    ----------
    params : PhysicalParameters
        The set-up (starts at rest; the first cycle is a transient).
    duration : time
        Record length, e.g. ``"300 s"``.
    rate : frequency
        Sampling rate, e.g. ``"100 Hz"``.
    noise : force, optional
        Standard deviation of white noise added to the force.
    drift : force/time, optional
        Linear drift added to the force.
    seed : int, optional
        Random seed of the noise.
    name : str, optional
        Record name.
    with_velocity : bool, optional
        Include the (noise-free) slider velocity.
    start : time, optional
        Simulated time discarded before the record starts (to skip the transient).

    """
    from ..core.api import run_trajectory
    from ..core.memory import check_memory
    from ..core.results import Status
    from ..laws import law_arrays
    from ..models.parameters import PhysicalParameters
    from ..units import check_seed, parse_quantity

    if not isinstance(params, PhysicalParameters):
        raise ArgumentTypeError(f"params={params!r}: expected PhysicalParameters")
    dur = parse_quantity(duration, "duration", "[time]", "300 s").to("s").magnitude
    fs = parse_quantity(rate, "rate", "1 / [time]", "100 Hz").to("Hz").magnitude
    sigma = parse_quantity(noise, "noise", "[force]", "1 mN", allow_zero=True).to("N").magnitude
    import pint

    from ..units import ureg

    per_time = f"drift={drift!r}: expected a force per time such as '0.1 mN/s' (may be negative)"
    if not isinstance(drift, str | pint.Quantity):  # a plain number has no unit to read
        raise ArgumentTypeError(per_time)
    try:
        dq = ureg.Quantity(drift.strip()) if isinstance(drift, str) else drift
        ok = dq.check("[force] / [time]") and np.isfinite(float(dq.magnitude))
    except Exception:
        ok = False
    if not ok:
        raise ValueError(per_time)
    k_drift = float(dq.to("N/s").magnitude)
    t0 = parse_quantity(start, "start", "[time]", "100 s", allow_zero=True).to("s").magnitude
    seed_ = check_seed(seed)
    n = round(dur * fs) + 1
    # time, the engine's states, force and velocity: about 8 arrays of n floats
    check_memory(8.0 * 8 * n, f"duration * rate = {n} samples", "a shorter record or a lower rate")
    t = t0 + np.arange(n) / fs
    sc = params.scales
    d = params.dimensionless()
    tau = t / sc.time.to("s").magnitude
    kernel, lp = law_arrays(d.law)
    y, _, _, status = run_trajectory(kernel, lp, d.nu, 0.0, 0.0, tau, rtol=1e-10, atol=1e-12)
    if status != Status.OK:
        raise RuntimeError("synthetic_record: the integration failed")
    rng = np.random.default_rng(seed_)
    force = y[:, 0] * sc.force.to("N").magnitude + sigma * rng.standard_normal(n) + k_drift * (t - t0)
    vel = y[:, 1] * sc.velocity.to("m/s").magnitude if with_velocity else None
    return Record(name, t - t0, force, None, vel, params.v0, params.load, {}, params.stiffness, params.mass)
