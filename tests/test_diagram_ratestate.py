"""The inertial rate-and-state slider's (V, k) diagram against its closed forms.

Rice and Ruina (J. Appl. Mech. 50, 343, 1983): steady sliding of the spring-slider with mass
per area M loses stability at k_c = sigma (b - a)/D_c [1 + M V^2/(sigma a D_c)] (aging and
slip laws alike: their linearisations coincide at steady state).
"""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from stickslip.ratestate.inertia import InertialSlider
from stickslip.ratestate.inertia_diagram import inertial_diagram

LAB = {"a": 0.01, "b": 0.015, "dc": "10 um", "sigma": "10 MPa", "mass": "1e5 kg/m^2"}


@pytest.mark.parametrize("law", ["aging", "slip"])
def test_hopf_curve_is_the_inertial_critical_stiffness(law):
    s = InertialSlider(**LAB, law=law)
    d = inertial_diagram(s, (1e-6, 1e-1), (1e9, 1e13))
    (h,) = d.curves_of("hopf")
    kc = s.sigma * (s.b - s.a) / s.dc * (1 + s.mass * (h.x * 1e-6) ** 2 / (s.sigma * s.a * s.dc))
    assert np.max(np.abs(h.y / kc - 1)) < 1e-8
    assert h.ends == ("edge", "edge")
    assert h.x.min() == pytest.approx(1.0) and h.x.max() == pytest.approx(1e5)  # edge to edge
    # Bautin points: the continuation's zeros of l1 are the closed-form curve's (Brent on k_c(V))
    found = [p.x * 1e-6 for p in d.points_of("bautin")]
    expected = [b.velocity for b in s.bautin_points(1e-6, 1e-1)]
    assert found == pytest.approx(expected, rel=1e-8)
    for p in d.points_of("bautin"):
        assert p.y == pytest.approx(s.critical_stiffness(p.x * 1e-6), rel=1e-10)
    assert d.regime_at(10.0, 1e12) == "steady-sliding"
    assert d.regime_at(1e5, 1e10).startswith("undetermined")


def test_aging_bautin_point_at_its_closed_form():
    """Aging law with inertia: l1 has the sign of -mu((3 + 4 beta) mu^2 + 6 mu - 1), mu = m/a,
    beta = b/a (derived for ratestate.inertia): one Bautin point at
    mu* = (2 sqrt(3 + beta) - 3)/(3 + 4 beta)."""
    s = InertialSlider(**LAB, law="aging")
    d = inertial_diagram(s, (1e-6, 1e-1), (1e9, 1e13))
    (p,) = d.points_of("bautin")
    beta = s.b / s.a
    mu = (2 * np.sqrt(3 + beta) - 3) / (3 + 4 * beta)
    assert p.nu / s.a == pytest.approx(mu, rel=1e-8)  # nu holds the inertia number M V^2/(sigma D_c)
    assert p.value < 0  # l2 < 0: the subcritical side's unstable cycle has a stable one around it
    (h,) = d.curves_of("hopf")
    low = h.x * 1e-6 < p.x * 1e-6 * 0.99
    assert np.all(h.data["l1"][low] > 0) and np.all(h.data["l1"][h.x > p.x * 1.01] < 0)


def test_slip_law_is_supercritical_along_the_whole_curve():
    s = InertialSlider(**LAB, law="slip")
    d = inertial_diagram(s, (1e-6, 1e-1), (1e9, 1e13))
    (h,) = d.curves_of("hopf")
    assert np.all(h.data["l1"] < 0) and d.points == []


def test_quasi_static_slider_has_no_bautin_point():
    """Without mass the Hopf point is a centre (l1 = 0 identically): no isolated Bautin point."""
    s = InertialSlider(**{**LAB, "mass": 0.0})
    d = inertial_diagram(s, (1e-6, 1e-1), (1e9, 1e11))
    (h,) = d.curves_of("hopf")
    assert np.allclose(h.y, s.sigma * (s.b - s.a) / s.dc, rtol=1e-12)
    assert d.points == []


def test_command(tmp_path):
    r = subprocess.run(
        [sys.executable, "-m", "stickslip", "diagram", "--ratestate",
         "law=aging, a=0.01, b=0.015, dc=10 um, sigma=10 MPa, mass=1e5 kg/m^2",
         "--x", "V=1e-6..1e-1", "--y", "k=1e9..1e13", "--json"],
        capture_output=True, text=True, check=False,
    )  # fmt: skip
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert [c["kind"] for c in d["curves"]] == ["hopf"]
    assert [p["kind"] for p in d["points"]] == ["bautin"]
    bad = subprocess.run(
        [sys.executable, "-m", "stickslip", "diagram", "--ratestate", "law=aging, a=0.01", "--y", "k=1..2"],
        capture_output=True, text=True, check=False,
    )  # fmt: skip
    assert bad.returncode == 2 and "give b, dc, sigma, mass" in bad.stderr
