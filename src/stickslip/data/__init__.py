"""Measured data: stick-slip records, the amplitude-velocity criterion, fits of the model.

:mod:`~stickslip.data.records` (cycles of force-time records, and the summary table of
several), drawing on :mod:`~stickslip.data.cleaning` (the force cleaned before it is
measured), :mod:`~stickslip.data.rests` (whether the slider rests, from its velocity) and
:mod:`~stickslip.data.motion` (slip events and the slider's motion from the force);
:mod:`~stickslip.data.synthetic` (records made by the model);
:mod:`~stickslip.data.criterion` (the paper's criterion with a confidence interval);
:mod:`~stickslip.data.fitting` (the waveform fit of the paper's law), with
:mod:`~stickslip.data.fit_stages` (its two stages), :mod:`~stickslip.data.fit_model` (the
model as a function of the fit's coordinates) and :mod:`~stickslip.data.fit_solver` (the
least-squares machinery); :mod:`~stickslip.data.model_plane` (a model's regimes on the
measured plane) and :mod:`~stickslip.data.examples` (the README's example inputs).
"""

from typing import TYPE_CHECKING

from ..lazy import exports

if TYPE_CHECKING:  # loaded on first use by __getattr__
    from .criterion import CriterionResult, classify
    from .fitting import FitResult, fit_record
    from .motion import measure_motion
    from .records import analyze_records, measure_record
    from .synthetic import synthetic_record

_HOME = {
    "analyze_records": "records",
    "measure_record": "records",
    "CriterionResult": "criterion",
    "classify": "criterion",
    "FitResult": "fitting",
    "fit_record": "fitting",
    "measure_motion": "motion",
    "synthetic_record": "synthetic",
}


__getattr__, __dir__ = exports(__name__, _HOME)

__all__ = [
    "CriterionResult",
    "FitResult",
    "analyze_records",
    "classify",
    "fit_record",
    "measure_motion",
    "measure_record",
    "synthetic_record",
]
