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
