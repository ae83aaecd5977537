"""Figures (matplotlib)."""

from .figures import plot_spring_force, save_figure

__all__ = ["plot_spring_force", "save_figure"]
