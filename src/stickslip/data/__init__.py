"""Measured data: stick-slip records, the amplitude-velocity criterion, fits of the model.

:mod:`~stickslip.data.records` (cycles of force-time records),
:mod:`~stickslip.data.criterion` (the paper's criterion with a confidence
interval) and :mod:`~stickslip.data.fitting` (the waveform fit of the paper's law).
"""
