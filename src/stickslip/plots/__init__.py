"""Figures for papers (matplotlib, without pyplot): labelled axes with units, PNG and vector output.

* :mod:`.figures`: the spring force, sweeps, records and rate-and-state runs;
* :mod:`.regimes`: bifurcation diagrams, regime maps and the criterion map;
* :mod:`.chains`: chain catalogues (magnitude-frequency, space-time, recurrence, Lyapunov);
* :mod:`.style`: the shared conventions (no pyplot, readable logarithmic axes).
"""

from .figures import plot_rate_state, plot_records, plot_spring_force, plot_sweep, save_figure

__all__ = ["plot_rate_state", "plot_records", "plot_spring_force", "plot_sweep", "save_figure"]
