"""Rows of the engine that keep some fields only (``run_attractors(..., fields=...)``).

On a GPU only the kept columns cross back to the host (tests/test_cuda.py checks that
path in the simulator); here: the same numbers as the full rows on the CPU, the rows'
operations, and the errors of a field not kept or not known.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from stickslip.core.api import run_attractors
from stickslip.core.results import AttractorRows
from stickslip.laws import WeakeningLaw
from stickslip.orbits.attractors import POLISH_FIELDS, polish_rows

KW: dict[str, Any] = {
    "from_breakaway": True, "rtol": 1e-10, "atol": 1e-12, "max_slip_time": 1e4, "conv_tol": 1e-8,
}  # fmt: skip


def _rows(fields: Any = None) -> AttractorRows:
    c = np.linspace(0.5, 8.0, 12)
    nu = np.geomspace(1e-3, 5.0, 12)  # stick-slip, then pure slip
    return run_attractors(WeakeningLaw(c=1.0).kernel, c[:, None], nu, fields=fields, **KW)


def test_kept_fields_are_the_full_rows_columns_in_the_layouts_order() -> None:
    full = _rows()
    kept = _rows(["w_max", "status", "amplitude", "status"])  # any order, once each
    assert kept.fields == ("status", "amplitude", "w_max")
    assert kept.raw.shape == (12, 3)
    for name in kept.fields:
        np.testing.assert_array_equal(getattr(kept, name), getattr(full, name))
    assert set(full.regime.tolist()) == {0, 1}
    assert full.fields is None and full.keeps("period") and not kept.keeps("period")
    assert not hasattr(kept, "period")  # an AttributeError: hasattr says no


def test_a_field_not_kept_or_not_known_is_named() -> None:
    kept = _rows(("status", "amplitude"))
    said = r"AttractorRows.period: not kept by these rows \(they keep status, amplitude\)"
    with pytest.raises(AttributeError, match=said):
        _ = kept.period
    with pytest.raises(AttributeError, match="s_max: not kept"):
        kept.s_max = 1.0
    said = r"fields='amplitudes': expected names of AttractorRows's fields \(status, regime"
    with pytest.raises(ValueError, match=said):
        _rows(["amplitudes"])
    with pytest.raises(ValueError, match=r"fields=\[\]: expected names"):
        _rows([])


def test_kept_rows_slice_copy_assign_and_concatenate_with_their_fields() -> None:
    kept = _rows(POLISH_FIELDS)
    one = kept[3]
    assert one.fields == POLISH_FIELDS and one.raw.shape == (1, len(POLISH_FIELDS))
    assert one.amplitude[0] == kept.amplitude[3]
    copy = kept.copy()
    copy.amplitude = 0.0  # a copy shares nothing
    assert kept.amplitude.min() > 0.0
    out = AttractorRows.empty(12, POLISH_FIELDS)
    out[2:5] = kept[2:5]
    np.testing.assert_array_equal(out.raw[2:5], kept.raw[2:5])
    assert np.isnan(out.raw[:2]).all()
    both = AttractorRows.concat([kept[:4], kept[4:]])
    np.testing.assert_array_equal(both.raw, kept.raw)
    with pytest.raises(ValueError, match="rows of other fields"):
        out[0:1] = _rows()[0:1]
    with pytest.raises(ValueError, match="rows of different fields"):
        AttractorRows.concat([kept[:1], _rows()[:1]])
    with pytest.raises(ValueError, match="not each once in the layout's order"):
        AttractorRows(np.zeros((1, 2)), ("amplitude", "status"))


def test_a_polish_of_kept_rows_equals_the_full_rows_polish() -> None:
    """A sweep keeps POLISH_FIELDS; its polish (shooting the pure-slip orbits) gives the same numbers."""
    c = np.linspace(0.5, 8.0, 12)
    nu = np.geomspace(1e-3, 5.0, 12)
    law = (WeakeningLaw(c=1.0).kernel, c[:, None])
    full, m_full = polish_rows(law, nu, _rows())
    kept, m_kept = polish_rows(law, nu, _rows(POLISH_FIELDS))
    assert kept.fields == POLISH_FIELDS
    for name in POLISH_FIELDS:
        np.testing.assert_array_equal(getattr(kept, name), getattr(full, name))
    np.testing.assert_array_equal(m_kept, m_full)
    assert np.isfinite(m_full).sum() == 12 and (m_full > 0).any()  # pure-slip orbits were shot
    with pytest.raises(ValueError, match="polish_rows: the rows do not keep regime"):
        polish_rows(law, nu, _rows(("status", "amplitude", "period")))
    with pytest.raises(ValueError, match="do not keep drive_work, friction_work"):
        polish_rows(law, nu, _rows(POLISH_FIELDS), rerun=True)


def test_rows_keeping_every_field_are_the_full_rows() -> None:
    every = _rows(list(AttractorRows.layout()))
    assert every.fields is None  # they mix with full rows
    both = AttractorRows.concat([every, _rows()])
    np.testing.assert_array_equal(both.raw[:12], both.raw[12:])
    one = AttractorRows.empty(3, "status")  # one name, a string
    assert one.fields == ("status",) and one.raw.shape == (3, 1)
    assert AttractorRows.empty(2, tuple(AttractorRows.layout())).fields is None
