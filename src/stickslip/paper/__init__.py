"""Reproduction of the paper this project starts from (``stickslip reproduce``).

J. Szkutnik and K. Kułakowski, "How to distinguish between stick-slip and pure
slip oscillations", arXiv cond-mat/0506435.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import time
from collections.abc import Callable
from dataclasses import dataclass
from multiprocessing.pool import Pool
from typing import Any

from ..dynamics.sweep import load_sweep, save_sweep
from ..io.output import OutputFolder
from ..plots.figures import save_figure, save_figure_bytes
from .appendix import APPENDIX_PARTS, appendix_part, merge_appendix
from .compute import PaperConfig, compute_paper, with_appendix
from .figures import FIGURES, TRIAL_PLOTS, make_figures, render_figures, render_trial_figures
from .report import Claim, claims, write_report

#: the criterion's trials computed in the second process of ``reproduce(parallel=True)``: the
#: cubic law's (its engine compiles there while this process compiles the weakening law's)
REMOTE_TRIALS = ("cubic_alpha",)
#: the parts of the appendix this process computes after its own trials (the others: the second,
#: after its trial: the critical stiffness, which compiles the quasi-static integrator, then the
#: quasi-static runaway, which uses it; balanced on a cold start, docs/benchmarks.md)
LOCAL_APPENDIX_PARTS = ("inertia", "portraits")

__all__ = ["STAGES", "Claim", "PaperConfig", "ReproduceResult", "claims", "compute_paper", "reproduce"]


@dataclass(frozen=True)
class ReproduceResult:
    """Files written by :func:`reproduce`."""

    netcdf: str
    figures: dict[str, list[str]]
    report_md: str
    report_html: str
    claims: list[Claim]


def reproduce(
    out_dir: str | os.PathLike[str],
    *,
    quick: bool = False,
    progress: bool | None = False,
    overwrite: bool = False,
    parallel: bool = False,
    notify: Callable[[str], None] | None = None,
) -> ReproduceResult:
    """Compute every curve of the paper, write the data, the figures and the report.

    The figures are drawn from the data as read back from ``reproduce.nc``. The
    files are staged and published together when all are written
    (:class:`~stickslip.io.output.OutputFolder`): an interrupted run leaves the
    previous complete set.

    Parameters
    ----------
    out_dir : str or path-like
        Output folder (created).
    quick : bool, optional
        Fewer points per curve (for tests).
    progress : bool, optional
        Progress bars on the sweeps.
    overwrite : bool, optional
        Replace files in ``out_dir`` that stickslip did not write (otherwise an error).
    parallel : bool, optional
        Compute the criterion's trial on the cubic law (:data:`REMOTE_TRIALS`: its
        engine compiles there while this process compiles the weakening law's) and
        two of the appendix's four parts (the critical stiffness and the quasi-static
        slider's runaway, both on the quasi-static integrator) in a second process
        while this one computes the rest, the inertial slider and the phase
        portraits, and render half the figures
        there: the same files, in about half the time on two cores. The second process is started by
        ``multiprocessing`` (spawn), so the calling program's main module must be
        safe to import (an ``if __name__ == "__main__":`` guard); ``stickslip
        reproduce`` uses it. Where no process can be started, everything runs in
        this one. Default False.
    notify : callable, optional
        Called with one line as each of the :data:`STAGES` starts (``[2/5] the paper's
        curves ...``), with the seconds elapsed.

    """
    from .trial import TRIAL_MAPS, run_trials

    with OutputFolder(out_dir, "reproduce", overwrite=overwrite) as out:
        # every target checked before the computation starts
        out.expect(
            {
                "reproduce.nc": "reproduce",
                "report.md": "report",
                "report.html": "report",
                **{f"{name}.{ext}": "figure" for name in FIGURES for ext in ("png", "svg")},
                **{f"criterion_{m.key}.nc": "criterion-trial" for m in TRIAL_MAPS},
                **{
                    f"{kind}_{m.key}.{ext}": "figure"
                    for kind, _ in TRIAL_PLOTS
                    for m in TRIAL_MAPS
                    for ext in ("png", "svg")
                },
            }
        )
        config = PaperConfig.quick() if quick else PaperConfig()
        stage = _Stages(notify)
        with contextlib.ExitStack() as stack:
            pool = _second_process() if parallel else None
            remote_trial_figures: dict[str, Any] = {}
            if pool is not None:
                # stopped at once on any error or Ctrl-C here, not after the appendix finishes
                stack.callback(pool.join)
                stack.callback(pool.terminate)
                # the second process takes the trial on the cubic law (an engine of its own to
                # compile, on the second core; this process finds it compiled when it needs it
                # for the regime sequences) and two of the appendix's four parts
                other_trial = pool.apply_async(run_trials, kwds={"quick": quick, "keys": REMOTE_TRIALS})
                remote_parts = {
                    name: pool.apply_async(appendix_part, (name, config.quick_appendix))
                    for name in APPENDIX_PARTS
                    if name not in LOCAL_APPENDIX_PARTS
                }
            # the criterion's trials (regime maps on both cores) while the second process works
            here = None if pool is None else tuple(m.key for m in TRIAL_MAPS if m.key not in REMOTE_TRIALS)
            stage(0)
            computed_trials = run_trials(quick=quick, progress=progress, keys=here)
            stage(1)
            ds = compute_paper(config, progress=progress, appendix=pool is None)
            stage(2)
            trials: dict[str, Any] = {}

            def hand_over_trials() -> None:
                # the second process draws the figures of its trial from the file written here
                assert pool is not None
                for key, tr in other_trial.get().items():
                    trials[key] = _save_trial(key, tr, out)
                    remote_trial_figures[key] = pool.apply_async(
                        render_trial_figures, (out.staged_path(f"criterion_{key}.nc"), key)
                    )

            if pool is not None:
                parts = {name: appendix_part(name, config.quick_appendix) for name in LOCAL_APPENDIX_PARTS}
                if other_trial.ready():
                    hand_over_trials()
            # this process draws its own trials' figures (meanwhile, with a second process)
            trial_files: dict[str, list[str]] = {}
            for key, tr in computed_trials.items():
                trials[key] = _save_trial(key, tr, out)
                for kind, plot in TRIAL_PLOTS:
                    trial_files[f"{kind}_{key}"] = save_figure(plot(trials[key]), f"{kind}_{key}", out=out)
            if pool is not None:
                if not remote_trial_figures:
                    hand_over_trials()
                parts.update({name: task.get() for name, task in remote_parts.items()})
                ds = with_appendix(ds, merge_appendix(parts))
            trials = {m.key: trials[m.key] for m in TRIAL_MAPS}
            stage(3)
            nc = save_sweep(ds, "reproduce.nc", kind="reproduce", out=out)
            data = load_sweep(out.staged_path("reproduce.nc"))
            figures = make_figures(data)
            # with a second process, it renders every other figure meanwhile (the same bytes)
            remote = list(figures)[1::2] if pool is not None else []
            rendered = pool.apply_async(render_figures, (data, remote)) if pool is not None else None
            files: dict[str, list[str]] = {}
            for name, fig in figures.items():
                if name not in remote:
                    files[name] = save_figure(fig, name, formats=("png", "svg"), out=out)
            for task in remote_trial_figures.values():
                for name, blobs in task.get().items():
                    trial_files[name] = save_figure_bytes(blobs, name, out=out)
            if rendered is not None:
                for name, blobs in rendered.get().items():
                    files[name] = save_figure_bytes(blobs, name, out=out)
            for m in TRIAL_MAPS:
                for kind, _ in TRIAL_PLOTS:
                    files[f"{kind}_{m.key}"] = trial_files[f"{kind}_{m.key}"]
        files = {name: files[name] for name in [*figures, *(k for k in files if k not in figures)]}
        staged_png = {k: out.staged_path(os.path.basename(v[0])) for k, v in files.items()}
        stage(4)
        md, html_path = write_report(data, out, staged_png, trials)
    return ReproduceResult(nc, files, md, html_path, claims(data))


#: the stages of :func:`reproduce`, as :func:`reproduce`'s ``notify`` names them
STAGES = (
    "the criterion on trial: regime maps of F1, F2 and the cubic law, 16 rows each",
    "the paper's curves: Figs. 1-3, period, load and mass dependences",
    "the appendix: Dulac's criterion, phase portraits, critical stiffness, inertia",
    "reproduce.nc and the figures (PNG and SVG)",
    "the report (report.md, report.html)",
)


class _Stages:
    """Say, through ``notify``, which of :data:`STAGES` starts and how long the run has taken."""

    def __init__(self, notify: Callable[[str], None] | None) -> None:
        self.notify = notify
        self.t0 = time.perf_counter()

    def __call__(self, i: int) -> None:
        if self.notify is not None:
            took = time.perf_counter() - self.t0
            self.notify(f"[{i + 1}/{len(STAGES)}] {STAGES[i]} ({took:.0f} s so far)")


def _save_trial(key: str, trial: Any, out: OutputFolder) -> Any:
    """Write a criterion trial's file; return it as read back (its figures are drawn from that)."""
    save_sweep(trial, f"criterion_{key}.nc", kind="criterion-trial", out=out)
    return load_sweep(out.staged_path(f"criterion_{key}.nc"))


def _second_process() -> Pool | None:
    """Start one spawned worker process; None where processes cannot be started here."""
    try:
        return multiprocessing.get_context("spawn").Pool(1)
    except (OSError, NotImplementedError, ImportError):  # no semaphores, a sandbox
        return None
