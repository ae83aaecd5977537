"""Figures (matplotlib)."""

from .figures import plot_rate_state, plot_records, plot_spring_force, plot_sweep, save_figure

__all__ = ["plot_rate_state", "plot_records", "plot_spring_force", "plot_sweep", "save_figure"]
