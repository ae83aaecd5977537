"""Reproduction of the paper this project starts from (``stickslip reproduce``).

J. Szkutnik and K. Kułakowski, "How to distinguish between stick-slip and pure
slip oscillations", arXiv cond-mat/0506435.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import xarray as xr

from ..analysis.sweep import load_sweep, save_sweep
from ..plots.figures import save_figure
from .compute import PaperConfig, compute_paper
from .figures import make_figures
from .report import Claim, claims, write_report

__all__ = ["Claim", "PaperConfig", "ReproduceResult", "claims", "compute_paper", "reproduce"]


@dataclass(frozen=True)
class ReproduceResult:
    """Files written by :func:`reproduce`."""

    netcdf: str
    figures: dict[str, list[str]]
    report_md: str
    report_html: str
    claims: list[Claim]


def reproduce(
    out_dir: str | os.PathLike[str], *, quick: bool = False, progress: bool | None = False
) -> ReproduceResult:
    """Compute every curve of the paper, write the data, the figures and the report.

    The figures are drawn from the data as read back from ``reproduce.nc``.

    Parameters
    ----------
    out_dir : str or path-like
        Output folder (created).
    quick : bool, optional
        Fewer points per curve (for tests).
    progress : bool, optional
        Progress bars on the sweeps.

    """
    out = os.fspath(out_dir)
    os.makedirs(out, exist_ok=True)
    ds = compute_paper(PaperConfig.quick() if quick else PaperConfig(), progress=progress)
    nc = os.path.join(out, "reproduce.nc")
    save_sweep(ds, nc)
    data = load_sweep(nc)
    files: dict[str, list[str]] = {}
    for name, fig in make_figures(data).items():
        files[name] = save_figure(fig, os.path.join(out, name), formats=("png", "svg"))
    from ..plots.regimes import plot_criterion_map, plot_regime_map
    from .trial import run_trials

    trials = {}
    for key, tr in run_trials(quick=quick, progress=progress).items():
        path = os.path.join(out, f"criterion_{key}.nc")
        tr.to_netcdf(path)
        trials[key] = xr.load_dataset(path)
        files[f"regimes_{key}"] = save_figure(
            plot_regime_map(trials[key]), os.path.join(out, f"regimes_{key}")
        )
        files[f"criterion_{key}"] = save_figure(
            plot_criterion_map(trials[key]), os.path.join(out, f"criterion_{key}")
        )
    md, html_path = write_report(data, out, {k: v[0] for k, v in files.items()}, trials)
    return ReproduceResult(nc, files, md, html_path, claims(data))
