"""The explorer's two-parameter diagram: its data (no browser) and its panel on an in-process page.

References: the weakening law ``f(w) = 1/(1 + c w) + p w`` has ``f'(nu) = -c/(1 + c nu)^2 + p``,
so steady sliding is stable for ``nu > nu_H = (sqrt(c/p) - 1)/c`` and its Hopf curve is that
closed form; ``f''' = -6 c^3/(1 + c nu)^4 < 0``: subcritical everywhere. The formula
``1 + w + g w^3 + w^5/4`` has its Hopf curve ``g = -(1 + 5 nu^4/4)/(3 nu^2)`` and a Bautin
point where ``f'''(nu) = 6 g + 15 nu^2 = 0`` on it: ``nu = sqrt(0.4)``, ``g = -1``.
"""

from __future__ import annotations

import concurrent.futures
import math
import multiprocessing
import pickle
import warnings

import numpy as np
import pytest

from stickslip.explore import Setup
from stickslip.explore.session import plane_key, plane_window, two_parameter_view
from stickslip.plots.regimes import REGIME_COLORS

F2 = Setup(law="weakening", params={"c": 5.0, "p": 0.5}, nu=0.3)
BAUTIN = Setup(law="expr", expression="1 + w + g*w**3 + 0.25*w**5", params={"g": -1.0}, nu=0.63)


@pytest.fixture(scope="module")
def f2_c():
    return two_parameter_view(F2, "c")


def _hopf(view):
    pieces = [i for i, k in enumerate(view["curves"]["kind"]) if k == "hopf"]
    assert pieces, view["curves"]["kind"]
    return pieces


def _quads_in_unit_square(view, window):
    """The quads' corners as fractions of the axes (log x, linear y)."""
    (x0, x1), (y0, y1) = window
    r = view["regions"]
    u = [np.log(np.asarray(r[k]) / x0) / math.log(x1 / x0) for k in ("left", "right")]
    v = [(np.asarray(r[k]) - y0) / (y1 - y0) for k in ("bottom", "top")]
    return u, v


@pytest.mark.fast
def test_the_window_about_the_set_up_and_bad_axes():
    # two decades of nu each side, inside the slider's range 1e-5 .. 10; a factor 4 each way
    assert plane_window(F2, "c") == ((0.003, 10.0), (1.25, 20.0))
    assert plane_window(F2, "p") == ((0.003, 10.0), (0.125, 2.0))
    assert plane_window(Setup(nu=1e-5), "c")[0] == (1e-5, 1e-3)
    # p = 0 (F1): from the included bound 0 to 1; an excluded bound approached to a quarter of
    # its distance from the value (sigma < 1), an included one reached (kinetic <= 1); a
    # negative value mirrored
    assert plane_window(Setup(params={"c": 3.8, "p": 0.0}), "p")[1] == (0.0, 1.0)
    coulomb = Setup(law="coulomb", params={"kinetic": 0.999})
    assert plane_window(coulomb, "kinetic")[1] == pytest.approx((0.999 / 4, 1.0), rel=1e-15)
    near = Setup(law="carlson-langer", params={"alpha": 2.5, "sigma": 0.999})
    assert plane_window(near, "sigma")[1] == pytest.approx((0.999 / 4, 1.0 - 0.001 / 4), rel=1e-15)
    cl = Setup(law="carlson-langer", params={"alpha": 2.5, "sigma": 0.5})
    assert plane_window(cl, "sigma")[1] == (0.125, 0.875)
    expr = Setup(law="expr", params={"c": 3.8, "q": -0.5})
    with pytest.warns(UserWarning, match="turns negative"):  # the formula's own choice
        assert plane_window(expr, "q")[1] == (-2.0, -0.125)
    assert plane_window(expr.with_(params={"c": 3.8, "q": 0.0}), "q")[1] == (-1.0, 1.0)
    # the key: the law and its other parameters, not nu nor the axis' own value
    assert plane_key(F2, "c") == plane_key(F2.with_(nu=2.0, params={"c": 9.0, "p": 0.5}), "c")
    assert plane_key(F2, "c") != plane_key(F2.with_(params={"c": 5.0, "p": 0.6}), "c")
    with pytest.raises(ValueError, match="'zz' is not a parameter of the weakening law"):
        plane_window(F2, "zz")
    with pytest.raises(
        ValueError, match="two-parameter diagram: 'zz' is not a parameter of the weakening law"
    ):
        two_parameter_view(F2, "zz")
    with pytest.raises(ValueError, match="a plane of the coulomb law runs over"):
        two_parameter_view(coulomb, "kinetic")


def test_the_weakening_view_has_the_closed_form_hopf_curve_and_named_regions(f2_c):
    v = f2_c
    assert v["x_range"] == (0.003, 10.0) and v["y_range"] == (1.25, 20.0)
    assert v["x_log"] and not v["y_log"] and v["y_label"] == "c"
    assert v["current"] == {"x": [0.3], "y": [5.0]} and v["key"] == plane_key(F2, "c")
    (i,) = _hopf(v)  # subcritical along the whole curve: one piece, dashed
    nu, c = np.asarray(v["curves"]["xs"][i]), np.asarray(v["curves"]["ys"][i])
    assert np.max(np.abs(nu - (np.sqrt(c / 0.5) - 1) / c)) < 1e-9
    assert c.min() == pytest.approx(1.25, abs=1e-12) and c.max() == pytest.approx(20.0, abs=1e-12)
    assert v["curves"]["dash"][i] == "dashed" and v["curves"]["color"][i] == "#000000"
    assert v["curves"]["label"][i] == "Hopf (steady sliding), subcritical"
    assert "grazing" in v["curves"]["kind"] and not v["points"]["x"]  # no codimension-2 point
    # the regions: named, coloured by regime, and tiling the plane once
    r = v["regions"]
    assert set(zip(r["regime"], r["attractors"], strict=True)) == {
        ("stick-slip", "stick-slip"),
        ("bistable", "stick-slip + steady-sliding"),
        ("steady-sliding", "steady-sliding"),
    }
    assert r["color"] == [REGIME_COLORS[g] for g in r["regime"]]
    (u0, u1), (v0, v1) = _quads_in_unit_square(v, (v["x_range"], v["y_range"]))
    assert np.sum((u1 - u0) * (v1 - v0)) == pytest.approx(1.0, abs=1e-12)
    assert np.all(u1 > u0) and np.all(v1 > v0)
    # steady sliding is an attractor exactly where f'(nu) = -c/(1 + c nu)^2 + p > 0: judged on a
    # grid of points three raster cells or more off the Hopf curve (a cell on a curve takes its
    # nearest region's colour)
    uu, vv = np.meshgrid(np.linspace(0.01, 0.99, 45), np.linspace(0.01, 0.99, 45))
    nu, c = 0.003 * (10.0 / 0.003) ** uu.ravel(), 1.25 + (20.0 - 1.25) * vv.ravel()
    off = np.abs(np.log(nu * c / (np.sqrt(c / 0.5) - 1))) / math.log(10.0 / 0.003) > 3.0 / 120
    left, right, bottom, top = (np.asarray(r[k]) for k in ("left", "right", "bottom", "top"))
    inside = (left <= nu[:, None]) & (nu[:, None] < right) & (bottom <= c[:, None]) & (c[:, None] < top)
    assert np.all(inside.sum(axis=1) == 1)  # each point in one quad
    quad = np.argmax(inside, axis=1)
    steady = np.array(["steady-sliding" in r["attractors"][q] for q in quad])
    assert off.sum() > 1500
    np.testing.assert_array_equal(steady[off], (-c / (1 + c * nu) ** 2 + 0.5 > 0)[off])
    # the page's data cross a process: a served page computes it in a worker
    assert pickle.loads(pickle.dumps(v))["curves"]["xs"] == v["curves"]["xs"]
    pickle.dumps((two_parameter_view, F2, "c"))


def test_the_p_axis_and_its_closed_form():
    v = two_parameter_view(F2.with_(params={"c": 3.8, "p": 0.5}), "p")
    (i,) = _hopf(v)
    nu, p = np.asarray(v["curves"]["xs"][i]), np.asarray(v["curves"]["ys"][i])
    assert np.max(np.abs(nu - (np.sqrt(3.8 / p) - 1) / 3.8)) < 1e-9
    assert p.min() == pytest.approx(0.125, abs=1e-12) and p.max() == pytest.approx(2.0, abs=1e-12)


@pytest.mark.slow  # 30 s: the explorer's window spans three decades of nu and a factor 16 in g
def test_a_bautin_point_cuts_the_hopf_curve_and_has_its_words():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the formula turns negative far out (the view keeps it as a note)
        v = two_parameter_view(BAUTIN)
    assert v["y_label"] == "g" and v["y_range"] == (-4.0, -0.25)
    assert any("turns negative" in n for n in v["notes"])
    pts = v["points"]
    (b,) = [i for i, k in enumerate(pts["kind"]) if k == "bautin"]
    assert pts["x"][b] == pytest.approx(math.sqrt(0.4), abs=1e-8)
    assert pts["y"][b] == pytest.approx(-1.0, abs=1e-8)
    assert pts["marker"][b] == "star" and pts["text"][b].startswith("bautin at nu = 0.63246, g = -1: Bautin")
    assert "fold-grazing" in pts["kind"]
    # the Hopf curve: its closed form at every point, solid (supercritical, f''' > 0, nu > sqrt(0.4))
    # and dashed below, the two pieces meeting at the Bautin point
    pieces = _hopf(v)
    assert sorted(v["curves"]["dash"][i] for i in pieces) == ["dashed", "solid"]
    for i in pieces:
        nu, g = np.asarray(v["curves"]["xs"][i]), np.asarray(v["curves"]["ys"][i])
        assert np.max(np.abs(g + (1 + 1.25 * nu**4) / (3 * nu**2))) < 1e-9
        above = nu[1:-1] > math.sqrt(0.4)  # the end points are shared with the other piece
        assert np.all(above) if v["curves"]["dash"][i] == "solid" else not np.any(above)
    assert {v["curves"]["color"][i] for i, k in enumerate(v["curves"]["kind"]) if k == "fold"} == {"#2166ac"}


# ---- the panel on a page -------------------------------------------------------------


def test_the_button_computes_in_process_and_the_point_follows():
    from bokeh.document import Document
    from bokeh.events import ButtonClick

    from stickslip.explore import Explorer

    ex = Explorer(Document(), F2)
    pn = ex.plane
    assert pn.regions.data["left"] == [] and pn.status.text.startswith("Press the button")
    assert pn.point.data == {"x": [0.3], "y": [0.5]}  # the last parameter, p, as the regime diagram's
    assert (pn.figure.x_range.start, pn.figure.y_range.end) == (0.003, 2.0)  # the window, before any curve
    ex.diagram_param.value = "c"
    assert pn.point.data == {"x": [0.3], "y": [5.0]} and pn.figure.y_range.start == 1.25
    pn.button._trigger_event(ButtonClick(pn.button))
    ref = two_parameter_view(F2, "c")
    assert pn.curves.data["xs"] == ref["curves"]["xs"]
    assert pn.regions.data["attractors"] == ref["regions"]["attractors"]
    assert pn.points.data["x"] == [] and pn.key == plane_key(F2, "c")
    assert pn.status.text.startswith("2 curve pieces, 3 kinds of region") and not pn.button.disabled
    assert pn.figure.yaxis[0].axis_label == "c" and "over (nu, c)" in pn.figure.title.text
    # nu and c move the point over the same diagram; another p is another plane: cleared
    ex.param_sliders[0].value = 6.0
    assert pn.point.data == {"x": [0.3], "y": [6.0]} and pn.curves.data["xs"] == ref["curves"]["xs"]
    ex.param_sliders[1].value = 0.6
    assert pn.key is None and pn.regions.data["left"] == [] and "cleared" in pn.status.text
    # a law a plane cannot run over: its error in the panel, the page's view kept
    ex.law.value = "coulomb"
    shown = ex.command.text
    pn.continue_curves()
    assert "error" in pn.status.text and "a plane of the coulomb law runs over" in pn.status.text
    assert ex.command.text == shown and pn.running is None and not pn.button.disabled


class _Held(concurrent.futures.Executor):
    """An executor that holds each submitted call until the test runs it (a worker that computes)."""

    def __init__(self) -> None:
        self.calls: list[tuple[concurrent.futures.Future, object, tuple]] = []

    def submit(self, fn, /, *args, **kwargs):  # type: ignore[override]
        pickle.dumps((fn, args))  # what a process pool sends
        fut: concurrent.futures.Future = concurrent.futures.Future()
        self.calls.append((fut, fn, args))
        return fut

    def run(self) -> None:
        fut, fn, args = self.calls.pop(0)
        fut.set_result(pickle.loads(pickle.dumps(fn(*args))))  # type: ignore[operator]


def _ticks(doc):
    for cb in list(doc.session_callbacks):
        doc.remove_next_tick_callback(cb)
        cb.callback()


def test_a_served_page_computes_in_a_worker_and_says_so(monkeypatch):
    from bokeh.document import Document

    from stickslip.explore import Explorer, app

    held = _Held()
    monkeypatch.setattr(app, "_workers", lambda: held)
    ex = Explorer(Document(), F2)
    ex.doc._session_context = lambda: object()  # as the Bokeh server's
    pn = ex.plane
    pn.continue_curves()
    # at once: the panel says it computes, the button waits; a second press asks nothing more
    assert "continuing the curves of nu and p" in pn.status.text and pn.button.disabled
    assert pn.button.label == "Continuing the curves..." and len(held.calls) == 1
    pn.continue_curves()
    assert len(held.calls) == 1 and pn.regions.data["left"] == []
    held.run()  # the worker's answer comes back on the page's next tick
    assert pn.regions.data["left"] == []
    _ticks(ex.doc)
    assert len(pn.regions.data["left"]) > 0 and pn.key == plane_key(F2, "p") and not pn.button.disabled
    # the law's other parameter changed while it computed: the answer is not shown, the page says why
    pn.continue_curves()  # again, the same plane
    ex.param_sliders[0].value = 4.0  # c: another plane of (nu, p)
    _ticks(ex.doc)  # the page's update clears the diagram shown
    assert pn.key is None and pn.regions.data["left"] == [] and pn.button.disabled
    held.run()
    _ticks(ex.doc)
    assert pn.key is None and pn.regions.data["left"] == [] and "changed while" in pn.status.text


@pytest.mark.slow
def test_a_worker_process_computes_the_view():
    """The served page's path: the view computed in a spawned process equals the one computed here."""
    ctx = multiprocessing.get_context("spawn")
    with concurrent.futures.ProcessPoolExecutor(max_workers=1, mp_context=ctx) as pool:
        there = pool.submit(two_parameter_view, F2, "c").result(timeout=300)
    here = two_parameter_view(F2, "c")
    assert there["curves"]["xs"] == here["curves"]["xs"] and there["regions"] == here["regions"]
