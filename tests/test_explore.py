"""``stickslip explore``: the set-up's view and command (no browser), then the page in headless Chromium.

The browser test starts ``stickslip explore --port P --no-browser`` as a user
would, drives Debian's ``chromium`` through ``chromedriver`` (Selenium), moves the
driving-velocity slider with the mouse, and checks that the plots' numbers and
the screenshot changed, that the exported command reproduces the shown cycle,
and that the browser console holds no error. ``.ci/run`` installs the browser;
elsewhere the test is skipped, saying why.
"""

from __future__ import annotations

import json
import math
import os
import shlex
import shutil
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from stickslip import DimensionlessParameters, WeakeningLaw, cycle, simulate
from stickslip.cli import main
from stickslip.explore import Setup, command, compute, parse_params, view_csv
from stickslip.explore.session import slider_range

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
CHROMEDRIVER = shutil.which("chromedriver")


def _run_command(cmd: str) -> dict:
    args = shlex.split(cmd)
    assert args[:2] == ["stickslip", "cycle"]
    res = CliRunner().invoke(main, [*args[1:], "--json"])
    assert res.exit_code == 0, res.output
    return json.loads(res.output)


# ---- the computation behind the page ------------------------------------------------


def test_view_is_the_engine_and_the_command_reproduces_it():
    setup = Setup(law="weakening", params={"c": 3.8, "p": 0.0}, nu=0.02)
    v = compute(setup)
    ref = cycle(DimensionlessParameters(nu=0.02, law=WeakeningLaw(c=3.8)))
    assert v.regime == ref.regime == "stick-slip"
    assert v.amplitude == ref.amplitude
    tr = simulate(DimensionlessParameters(nu=0.02, law=WeakeningLaw(c=3.8)), cycles=3, n_points=1500)
    np.testing.assert_array_equal(v.spring_force, tr.spring_force)
    assert v.stuck.any() and not v.stuck.all()
    # the paper's criterion on the amplitude-velocity curve: F1 is stick-slip and the criterion says so
    assert v.verdict == "stick-slip"
    out = _run_command(v.command)
    assert out["regime"] == v.regime
    assert out["amplitude"] == pytest.approx(v.amplitude, rel=1e-12)
    assert out["period"] == pytest.approx(v.period, rel=1e-12)


def test_physical_units_and_their_command():
    setup = Setup(law="weakening", params={"c": 3.8, "p": 0.5}, nu=0.3, physical=True)
    v = compute(setup)
    assert v.units["force"] == "N"
    dimless = compute(setup.with_(physical=False))
    # the same motion: force scaled by mu_s W
    assert v.amplitude == pytest.approx(dimless.amplitude * setup.mu_s * setup.load, rel=1e-9)
    assert "--v0" in v.command and "--a" in v.command and "--nu" not in v.command
    out = _run_command(v.command)
    assert out["regime"] == v.regime
    assert out["amplitude"] == pytest.approx(v.amplitude, rel=1e-12)


@pytest.mark.slow
def test_a_formula_law_and_its_command():
    setup = Setup(law="expr", expression="1/(1 + c*w) + q*w", params={"c": 3.8, "q": 0.5}, nu=0.3)
    v = compute(setup)
    assert "--law expr" in v.command and "--param c=3.8" in v.command
    out = _run_command(v.command)
    assert out["regime"] == v.regime
    assert out["amplitude"] == pytest.approx(v.amplitude, rel=1e-12)


@pytest.mark.fast
def test_csv_and_bad_input():
    v = compute(Setup(nu=0.05))
    text = view_csv(v).splitlines()
    assert text[0] == f"# {v.command}"
    assert text[1].startswith("time [sqrt(m/k)],spring_force [mu_s W]")
    assert len(text) == 2 + v.time.size
    assert parse_params("c=3.8, q=0.5") == {"c": 3.8, "q": 0.5}
    with pytest.raises(ValueError, match=r"'q' is not name=number"):
        parse_params("c=3.8, q")
    with pytest.raises(ValueError, match="nu"):
        compute(Setup(nu=-1.0))
    with pytest.raises(ValueError, match="c"):
        compute(Setup(params={"c": -2.0, "p": 0.0}))
    assert command(Setup(nu=0.05)).startswith("stickslip cycle --law weakening --nu 0.05")
    # a bad scale was blamed on beta; an unknown parameter was a StopIteration or a list error
    with pytest.raises(ValueError, match=r"mass=-1\.0 must be positive"):
        Setup(physical=True, mass=-1.0)
    with pytest.raises(ValueError, match="'zz' is not a parameter of the weakening law"):
        slider_range("weakening", "zz", 1.0)
    with pytest.raises(ValueError, match="c=nan: expected a finite value"):
        slider_range("weakening", "c", float("nan"))
    # a formula's nan slider, spaces, None, an unknown built-in parameter: each named
    with pytest.raises(ValueError, match="c=inf: expected a finite value"):
        slider_range("expr", "c", float("inf"))
    assert parse_params("c = 3.8 , q= -0.5") == {"c": 3.8, "q": -0.5}
    with pytest.raises(ValueError, match="parameters=None"):
        parse_params(None)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"\['bogus'\] are not parameters of the weakening law"):
        compute(Setup(params={"c": 3.8, "p": 0.0, "bogus": 1.0}))


@pytest.mark.slow
def test_a_slider_holds_the_value_given_and_a_negative_parameter_its_diagram():
    """A slider holds the value given, even within one step of an excluded bound (sigma 0.999,
    not 0.9975; c = 0.001, not 0.0025) and reaches an included one (kinetic 1: equal static and
    kinetic friction); a negative formula parameter's regime diagram spans negative values and
    shows the current point."""
    from stickslip import ExpressionLaw
    from stickslip.explore import regime_diagram

    for law, name, value in (("carlson-langer", "sigma", 0.999), ("weakening", "c", 0.001)):
        start, end, step = slider_range(law, name, value)
        assert start <= value <= end and step > 0
    assert slider_range("carlson-langer", "sigma", 0.5)[1] == pytest.approx(1.0 - 1.0 / 400)
    assert slider_range("coulomb", "kinetic", 0.5)[1] == 1.0
    law = ExpressionLaw("1/(1 + c*w) + q*w", c=3.8, q=-0.05)
    _, q, codes = regime_diagram(law, "q", 0.1, -0.05)
    assert q.min() == pytest.approx(-0.15) and q.max() < 0 and codes.shape[0] == q.size
    _, c, _ = regime_diagram(law, "c", 0.1, 3.8)
    assert c.max() == pytest.approx(11.4) and c.min() > 0
    # the diagram includes a value near an excluded bound (sigma 0.999, not rows to 0.958),
    # reaches an included one (kinetic 1), and a formula parameter at 0 (not rows 0.04 .. 1),
    # and the page does not redraw it on every change; nan and inf are named by their
    # argument, before numpy sees them
    near = Setup(law="carlson-langer", params={"alpha": 2.5, "sigma": 0.999}).dimensionless_law()
    _, k, _ = regime_diagram(near, "sigma", 0.1, 0.999)
    assert k.min() >= 0 and k.max() == pytest.approx(0.999)
    _, k, _ = regime_diagram(near, "sigma", 0.1, 0.5)
    assert k.max() == pytest.approx(1.0 - 1.0 / 24)  # one 24th inside the excluded bound
    coulomb = Setup(law="coulomb", params={"kinetic": 0.999}).dimensionless_law()
    _, k, _ = regime_diagram(coulomb, "kinetic", 0.1, 0.5)
    assert k.max() == 1.0
    with pytest.warns(UserWarning, match="turns negative"):  # q = -1 is the formula's own choice
        _, q, _ = regime_diagram(ExpressionLaw("1/(1 + c*w) + q*w", c=3.8, q=0.0), "q", 0.1, 0.0)
    assert q.min() == -1.0 and q.max() == 1.0
    for args, message in (
        ((coulomb, "kinetic", math.nan, 0.5), "nu=nan"),
        ((coulomb, "kinetic", 0.0, 0.5), "nu=0.0"),
        ((coulomb, "kinetic", 0.1, math.inf), "kinetic=inf"),
    ):
        with pytest.raises(ValueError, match=message):
            regime_diagram(*args)
    for law_name, name in (("expr", "q"), ("weakening", "c")):  # 4 x 1e308 was inf, its step nan
        start, end, step = slider_range(law_name, name, 1e308)
        assert all(math.isfinite(x) for x in (start, end, step)) and start <= 1e308 <= end
    with pytest.raises(ValueError, match="'c' is given twice"):
        parse_params("c=1, c=2")  # the last was kept, unsaid


def test_a_diagram_at_the_largest_value_has_a_finite_grid(monkeypatch):
    """A diagram at the largest value has a finite grid: 3 x 1e308 overflows to a grid of
    nan .. inf (the sweep is stubbed: the engine refuses such a parameter itself, by name)."""
    import xarray as xr

    from stickslip.explore import regime_diagram, session

    def grid_only(params, axes, progress=False):
        shape = [len(v) for v in axes.values()]
        return xr.Dataset({"regime": (list(axes), np.full(shape, "unknown"))}, coords=axes)

    monkeypatch.setattr(session, "sweep", grid_only)
    law = Setup(law="weakening").dimensionless_law()  # its own c: the grid comes from the value
    _, c, _ = regime_diagram(law, "c", 1.0, 1e308)
    assert np.all(np.isfinite(c)) and c.min() <= 1e308 <= c.max() and np.all(np.diff(c) > 0)


def test_the_formula_box_keeps_every_digit_and_a_flat_slope_is_flat():
    """The formula box shows 0.1 + 0.2 with every digit (as 0.3, Apply would change the value),
    and the paper's claim says a slope of 0 stays flat (not 'falls x1.00 per decade') and nan
    is not measured (not 'falls xnan')."""
    from stickslip.explore.app import _params_text
    from stickslip.paper.report import _trend

    params = {"c": 0.1 + 0.2, "q": 2.0, "r": -1e-300}
    assert parse_params(_params_text(params)) == params
    assert _params_text({"c": 2.0}) == "c=2"
    assert _trend(0.0) == "stays flat" and _trend(math.nan) == "is not measured"
    assert _trend(0.30103) == "rises x2.00 per decade" and _trend(-0.30103) == "falls x0.50 per decade"


@pytest.mark.fast
def test_explore_option_errors():
    res = CliRunner().invoke(main, ["explore", "--law", "nonsense", "--no-browser"])
    assert res.exit_code == 2 and "--law" in res.output and "weakening" in res.output
    res = CliRunner().invoke(main, ["explore", "--port", "0", "--no-browser"])
    assert res.exit_code == 2 and "--port" in res.output
    # the slider's range, the same check as the page's (explore.check_nu)
    for nu in ("20", "1e-6", "nan"):
        res = CliRunner().invoke(main, ["explore", "--nu", nu, "--no-browser"])
        assert res.exit_code == 2 and "--nu" in res.output and "from 1e-5 to 10" in res.output, res.output


# ---- the page in a real browser -----------------------------------------------------


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _start_explorer(log_path):  # type: ignore[no-untyped-def]
    """Start ``stickslip explore`` on a free port; return the process and its URL once it listens.

    The port is free when chosen but may be taken before the server binds it (another
    test, another program): the server then exits, and another port is tried.
    """
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    for _ in range(3):
        port = _free_port()
        with open(log_path, "w") as log:
            proc = subprocess.Popen(
                [sys.executable, "-m", "stickslip.cli", "explore", "--port", str(port), "--no-browser"],
                stdout=log,
                stderr=subprocess.STDOUT,
                env=env,
            )
        url = f"http://127.0.0.1:{port}/"
        # the server says where it listens once it does (the engine compiled on a cold
        # cache: a long timeout)
        deadline = time.time() + 180
        while f"stickslip explorer: {url}" not in log_path.read_text():
            if proc.poll() is not None:
                break
            if time.time() > deadline:
                proc.kill()
                pytest.fail(f"explore did not start on {url}: {log_path.read_text()}")
            time.sleep(0.2)
        else:
            return proc, url
        if "in use" not in log_path.read_text().lower():
            pytest.fail(f"explore did not start on {url}: {log_path.read_text()}")
    pytest.fail(f"explore found no free port in three tries: {log_path.read_text()}")


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    proc, url = _start_explorer(tmp_path_factory.mktemp("explore") / "server.log")
    try:
        # one request, which builds the first page (a long timeout, a single try)
        with urllib.request.urlopen(url, timeout=300) as r:
            html = r.read().decode()
        yield url, html
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            proc.kill()


# the tests of one server on one worker (`.ci/run`: --dist loadgroup): it starts once
@pytest.mark.xdist_group("explore_server")
def test_serves_a_page_that_names_stickslip(server):
    url, html = server
    assert url.startswith("http://127.0.0.1:")
    assert "<title>stickslip explorer</title>" in html
    # a notice until the plots arrive over the websocket (a page without it stayed blank)
    assert "Loading: the page connects to stickslip's engine" in html


@pytest.fixture(scope="module")
def browser(tmp_path_factory):
    if CHROMIUM is None or CHROMEDRIVER is None:
        if os.environ.get("STICKSLIP_REQUIRE_BROWSER"):
            pytest.fail(
                "STICKSLIP_REQUIRE_BROWSER is set (.ci/run sets it) and chromium/chromedriver are missing"
            )
        pytest.skip(
            "no browser: the browser test needs Debian's chromium and chromium-driver "
            "(apt-get install chromium chromium-driver; .ci/run installs them)"
        )
    webdriver = pytest.importorskip("selenium.webdriver", reason="selenium is in the test extras")
    from selenium.webdriver.chrome.service import Service

    opts = webdriver.ChromeOptions()
    opts.binary_location = CHROMIUM
    for flag in (
        "--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--no-first-run",
        "--disable-background-networking", "--disable-component-update", "--disable-sync",
        "--window-size=1400,1000",
    ):  # fmt: skip
        opts.add_argument(flag)
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    # the CSV export downloads a file: into a temporary folder, not the user's
    downloads = tmp_path_factory.mktemp("downloads")
    opts.add_experimental_option("prefs", {"download.default_directory": str(downloads)})
    driver = webdriver.Chrome(service=Service(CHROMEDRIVER), options=opts)
    yield driver
    driver.quit()


JS_MODEL = (
    "return Bokeh.documents.length ? Bokeh.documents[0].get_model_by_name(arguments[0]) !== null : false;"
)


def _wait(driver, predicate, timeout=120.0, what="the page"):
    from selenium.common.exceptions import JavascriptException

    t0 = time.time()
    while time.time() - t0 < timeout:
        try:
            if predicate():
                return time.time() - t0
        except JavascriptException:  # BokehJS not there yet; a dead browser raises
            pass
        time.sleep(0.05)
    raise AssertionError(f"timed out waiting for {what}")


def _model(driver, name, attr):
    return driver.execute_script(
        "const m = Bokeh.documents[0].get_model_by_name(arguments[0]); return m[arguments[1]];", name, attr
    )


def _force(driver):
    return driver.execute_script(
        "const d = Bokeh.documents[0].get_model_by_name('force').data;"
        "return [Array.from(d.x), Array.from(d.y)];"
    )


def _ink(png: bytes) -> float:
    """Return the share of a screenshot's pixels that are not (nearly) white."""
    import io

    from PIL import Image

    a = np.asarray(Image.open(io.BytesIO(png)).convert("L"))
    return float((a < 235).mean())


@pytest.mark.xdist_group("explore_server")
def test_browser_slider_updates_plots_and_export(server, browser, tmp_path):
    url, _ = server
    d = browser
    d.get(url)  # returns after the page's load event
    at_load = _ink(d.get_screenshot_as_png())
    assert at_load > 0.002, f"the page is blank after its load event ({at_load:.2%} of it drawn)"
    _wait(d, lambda: d.execute_script(JS_MODEL, "force") and len(_force(d)[0]) > 0, what="the first plots")
    assert d.execute_script("return document.getElementById('loading') === null;")  # the notice went
    assert "stickslip" in d.title
    status0 = _model(d, "status", "text")
    assert "stick-slip" in status0
    _, y0 = _force(d)
    shot0 = d.get_screenshot_as_png()
    nu0 = _model(d, "nu", "value")

    # move the driving-velocity slider with the mouse: its handle, in the slider's shadow DOM
    from selenium.webdriver.common.action_chains import ActionChains

    view = d.execute_script(
        "const m = Bokeh.documents[0].get_model_by_name('nu');return Bokeh.index.get_one(m).el;"
    )
    handle = d.execute_script("return arguments[0].shadowRoot.querySelector('.noUi-handle');", view)
    assert handle is not None, "the slider has no handle"
    t_move = time.time()
    ActionChains(d).click_and_hold(handle).move_by_offset(60, 0).release().perform()
    _wait(d, lambda: _model(d, "nu", "value") != nu0, timeout=10, what="the slider to move")
    latency = _wait(d, lambda: _force(d)[1] != y0, timeout=30, what="the plots to change")
    latency_total = time.time() - t_move
    nu1 = _model(d, "nu", "value")
    assert nu1 > nu0
    # the server has answered the last position of the slider: its title names that nu
    _wait(
        d, lambda: f"nu = beta v0 = {10**nu1:.4g};" in _model(d, "nu", "title"), timeout=30, what="the title"
    )
    _, y1 = _force(d)
    assert y1 != y0
    status1 = _model(d, "status", "text")
    assert status1 != status0
    shot1 = d.get_screenshot_as_png()
    assert shot1 != shot0
    (tmp_path / "before.png").write_bytes(shot0)
    (tmp_path / "after.png").write_bytes(shot1)
    if os.environ.get("STICKSLIP_SCREENSHOT"):
        Path(os.environ["STICKSLIP_SCREENSHOT"]).write_bytes(shot1)
    print(
        f"plots changed {1e3 * latency:.0f} ms after the slider's value ({latency_total:.2f} s with the drag)"
    )

    # the exported command reproduces the shown cycle
    cmd = _model(d, "command", "text")
    out = _run_command(cmd)
    shown = float(status1.split("data-value='")[1].split("'")[0])
    assert math.isclose(out["amplitude"], shown, rel_tol=1e-12)
    assert out["regime"] in status1
    # the shown motion is the engine's, at the shown nu
    tr = simulate(DimensionlessParameters(nu=10**nu1, law=WeakeningLaw(c=3.8)), cycles=3, n_points=1500)
    np.testing.assert_allclose(y1, tr.spring_force, rtol=1e-12, atol=1e-12)

    # the CSV export reaches the page
    button = d.execute_script(
        "const m = Bokeh.documents[0].get_model_by_name('csv_button');"
        "return Bokeh.index.get_one(m).el.shadowRoot.querySelector('button');"
    )
    button.click()
    _wait(
        d,
        lambda: (
            d.execute_script("return Bokeh.documents[0].get_model_by_name('csv').data.text[0].length;") > 1000
        ),
        timeout=20,
        what="the CSV",
    )
    csv_text = d.execute_script("return Bokeh.documents[0].get_model_by_name('csv').data.text[0];")
    assert csv_text.startswith(f"# {cmd}\n")

    # no error in the browser console
    errors = [e for e in d.get_log("browser") if e.get("level") == "SEVERE"]
    assert not errors, errors


def test_the_page_in_process_switches_laws_and_shows_errors():
    from bokeh.document import Document

    from stickslip.explore import Explorer

    ex = Explorer(Document(), Setup(nu=0.05))
    assert ex.updates == 1 and len(ex.force.data["y"]) > 0
    assert [s.name for s in ex.param_sliders] == ["param_c", "param_p"]
    # another built-in law: its parameters' sliders, a new view
    ex.law.value = "cubic"
    assert ex.setup.law == "cubic" and [s.name for s in ex.param_sliders] == ["param_alpha", "param_gamma"]
    assert ex.view.setup.law == "cubic" and "--law cubic" in ex.command.text
    # a bad value: an error on the page, the last view kept whole
    shown = ex.command.text
    ex.scales["mass"].value = "heavy"
    ex.units.active = 1
    assert "error" in ex.status.text and "mass" in ex.status.text and ex.command.text == shown
    ex.scales["mass"].value = "0.231"
    assert "error" not in ex.status.text and "--v0" in ex.command.text
    # a formula: applied on the next tick (compiled once), then shown with its own sliders
    ex.units.active = 0
    ex.expression.value = "1/(1 + c*w) + p*w"
    ex.expr_params.value = "c=3.8, p=0.5"
    ex.law.value = "expr"
    assert "Compiling" in ex.status.text
    ex._rebuild()
    assert ex.view.setup.law == "expr" and "--law expr" in ex.command.text
    ex.units.active = 1  # SI asked for: a formula stays dimensionless, and the page says so
    assert "dimensionless" in ex.status.text and ex.view.units["force"] == "mu_s W"
    out = _run_command(ex.command.text)
    assert out["amplitude"] == pytest.approx(ex.view.amplitude, rel=1e-12)

    # the set-up's values as given (not moved by the sliders), a formula set-up's own
    # parameters in its box (not the default formula's), nu in range
    ex = Explorer(Document(), Setup(law="coulomb", params={"kinetic": 0.999}, nu=0.1))
    assert ex.setup.params == {"kinetic": 0.999} and ex.param_sliders[0].value == 0.999
    ex = Explorer(Document(), Setup(law="expr", expression="1/(1 + c*w)", params={"c": 2.0}, nu=0.1))
    assert ex.expr_params.value == "c=2"
    ex._on_apply()
    ex._rebuild()
    assert "error" not in ex.status.text and ex.view.setup.params == {"c": 2.0}
    for nu in (100.0, 1e-7):
        with pytest.raises(ValueError, match=f"nu={nu!r}: expected a driving velocity from 1e-5 to 10"):
            Explorer(Document(), Setup(nu=nu))


@pytest.mark.slow
def test_the_page_keeps_its_view_whole_says_its_warnings_and_that_it_computes():
    """The page stays whole: a formula's parameter 'nan' is named on the page (not a traceback
    on the server with the page stuck on 'Compiling'), and one the formula lacks leaves sliders
    that match the plots; a law's warnings reach the page, not only the server's terminal; a
    served page says that it computes (seconds to minutes); log10 nu set past the slider is
    held to its range (beyond it a run takes minutes)."""
    from bokeh.document import Document

    from stickslip.explore import Explorer

    # the formula of the test above: compiled once for both
    ex = Explorer(Document(), Setup(law="expr", expression="1/(1 + c*w) + p*w", params={"c": 3.8, "p": 0.5}))
    shown = ex.command.text
    for bad, why in (("c=nan, p=0.5", "c=nan"), ("c=3.8, p=0.5, z=1", "z")):
        ex.expr_params.value = bad
        ex._on_apply()
        ex._rebuild()  # the next tick
        assert "error" in ex.status.text and why in ex.status.text, ex.status.text
        assert "Compiling" not in ex.status.text and ex.command.text == shown
        assert [s.name for s in ex.param_sliders] == ["param_c", "param_p"]  # the shown view's
    # an error that quotes a quantity keeps it, escaped ('<Quantity(...)>' would read as a tag)
    ex = Explorer(Document(), Setup(nu=0.05))
    ex.scales["mass"].value = "1e300"  # dimensionless: not used yet
    ex.units.active = 1
    assert "error" in ex.status.text and "a=&lt;Quantity(3.3" in ex.status.text, ex.status.text
    # a law's warning on the page, under the result
    ex = Explorer(Document(), Setup(nu=0.05))
    ex.law.value = "cubic"
    assert "warning" not in ex.status.text
    ex.param_sliders[0].value = ex.param_sliders[0].end  # alpha 1.995: the friction turns negative
    assert "<b>warning</b>" in ex.status.text and "the friction turns negative" in ex.status.text
    assert f"<b>period</b>: {ex.view.period:.5g} " in ex.status.text  # five digits, as the amplitude
    # a log10 nu past the slider's end is held to it (F1: the cubic law there takes a minute)
    ex = Explorer(Document(), Setup(nu=0.05))
    ex.nu.value = 3.0
    assert ex.view.setup.nu == pytest.approx(10.0**ex.nu.end)
    # a served page: "computing" at once, the work on the next tick, once for many changes
    ex = Explorer(Document(), Setup(nu=0.05))
    ex.doc._session_context = lambda: object()  # as the Bokeh server's
    before = ex.updates
    ex.param_sliders[0].value = 2.0
    ex.param_sliders[0].value = 2.5
    assert ex.status.text.endswith("<i>computing...</i>") and ex.updates == before
    ticks = list(ex.doc.session_callbacks)
    assert len(ticks) == 1
    ticks[0].callback()
    assert ex.updates == before + 1 and ex.view.setup.params["c"] == 2.5
    assert "computing" not in ex.status.text


def test_a_new_physical_scale_holds_v0_and_the_law_in_si():
    """In physical units a new scale (a new mass) holds v0 and the law in SI (a and b), not nu
    and the law's dimensionless parameters: nu = beta v0 and the sliders follow, and the
    command shown still reproduces the view."""
    from bokeh.document import Document

    from stickslip.explore import Explorer

    ex = Explorer(Document(), Setup(nu=0.05))
    ex.units.active = 1
    v0, law = ex.view.v0, ex.view.setup.parameters().law
    assert "in SI: mu_s = " in ex.law_si.text and " s/m" in ex.law_si.text
    mass = 4.0 * ex.setup.mass
    ex.scales["mass"].value = repr(mass)
    assert "error" not in ex.status.text, ex.status.text
    s = ex.view.setup
    assert s.mass == mass and ex.view.v0 == pytest.approx(v0, rel=1e-12)  # beta doubled
    assert s.nu == pytest.approx(0.1, rel=1e-12)
    assert s.params == {"c": pytest.approx(3.8 / 2, rel=1e-12), "p": 0.0}
    held = s.parameters().law
    for (name, q), q0 in zip(held.params.items(), law.params.values(), strict=True):
        assert q.to(q0.units).magnitude == pytest.approx(q0.magnitude, rel=1e-12), name
    assert [sl.value for sl in ex.param_sliders] == [s.params["c"], s.params["p"]]
    assert ex.nu.value == pytest.approx(-1.0) and ex._nu_exact[1] == s.nu
    out = _run_command(ex.command.text)
    assert out["amplitude"] == pytest.approx(ex.view.amplitude, rel=1e-12)
    # a v0 that the new scales put beyond the slider: an error that says how out, the view kept
    shown = ex.command.text
    ex.scales["mass"].value = repr(1e6 * mass)
    assert "error" in ex.status.text and "outside the driving-velocity slider" in ex.status.text
    assert "lower v0" in ex.status.text  # nu above the range; below it, raise
    ex.scales["mass"].value = repr(1e-12 * mass)
    assert "raise v0" in ex.status.text and ex.command.text == shown
    assert ex.command.text == shown
    ex.scales["mass"].value = repr(mass)
    assert "error" not in ex.status.text and ex.view.v0 == pytest.approx(v0, rel=1e-12)
    # mu_k held above a new mu_s cannot be: the dimensionless kinetic is kept, and the page says so
    ex = Explorer(Document(), Setup(law="coulomb", params={"kinetic": 0.6}, nu=0.05))
    ex.units.active = 1
    ex.scales["mu_s"].value = repr(0.5 * ex.setup.mu_s)
    assert "<b>warning</b>" in ex.status.text and "cannot be held" in ex.status.text, ex.status.text
    assert ex.view.setup.params == {"kinetic": 0.6}
    # the dimensionless view keeps its values whatever the scales
    ex = Explorer(Document(), Setup(nu=0.05))
    ex.scales["mass"].value = "1.0"
    assert ex.view.setup.nu == 0.05 and ex.view.setup.params == {"c": 3.8, "p": 0.0}


def test_a_law_switched_back_keeps_one_slider_per_parameter_name():
    """A parameter name's slider is made once and reused, with the new law's range and value:
    new sliders at each law switch (weakening, cubic, weakening) leave two 'param_c' models in
    BokehJS, and get_model_by_name finds the stale one."""
    from bokeh.document import Document

    from stickslip.explore import Explorer

    ex = Explorer(Document(), Setup(nu=0.05))
    first = list(ex.param_sliders)
    ex.param_sliders[0].value = 2.0
    ex.law.value = "cubic"
    ex.law.value = "weakening"
    assert ex.param_sliders == first and len(first[0]._callbacks["value"]) == 1
    assert [sl.value for sl in ex.param_sliders] == [3.8, 0.5] == list(ex.view.setup.params.values())
    assert ex.updates == 4 and "--c 3.8" in ex.command.text


def test_crafted_messages_get_their_error_on_the_page():
    """A page's messages may carry any value: an unknown law or diagram parameter is named."""
    from bokeh.document import Document

    from stickslip.explore import Explorer

    ex = Explorer(Document(), Setup(nu=0.05))
    shown = ex.command.text
    ex.law.value = "zzz"
    assert "error" in ex.status.text
    assert "law=&#x27;zzz&#x27; is not one the explorer offers" in ex.status.text
    assert "weakening" in ex.status.text and ex.law.value == "weakening" and ex.command.text == shown
    ex.diagram_param.value = "zzz"
    assert "regime diagram: &#x27;zzz&#x27; is not a parameter of the law" in ex.status.text, ex.status.text
    assert "expected one of c, p" in ex.status.text and ex.command.text == shown


@pytest.mark.slow
@pytest.mark.xdist_group("explore_server")
def test_a_formula_compiles_in_a_worker_while_the_server_serves_others(server, browser):
    """A formula's first view compiles its engine (15 to 30 s cold): in a worker process, so
    that the server answers a second client meanwhile, and the page shows the formula after."""
    url, _ = server
    d = browser
    d.get(url)
    _wait(d, lambda: d.execute_script(JS_MODEL, "force") and len(_force(d)[0]) > 0, what="the first plots")
    # a formula no cache holds: its engine is compiled now
    formula = f"1/(1 + c*w) + q*w + 1e-9*sin({time.time_ns() % 10**9 + 1}*w)"
    d.execute_script(
        "const doc = Bokeh.documents[0];"
        "doc.get_model_by_name('expression').value = arguments[0];"
        "doc.get_model_by_name('law').value = 'expr';",
        formula,
    )
    _wait(d, lambda: "Compiling" in _model(d, "status", "text"), timeout=30, what="the compiling notice")
    t0 = time.time()
    with urllib.request.urlopen(url, timeout=60) as r:  # a second client: a page of its own
        assert "<title>stickslip explorer</title>" in r.read().decode()
    served = time.time() - t0
    still = "Compiling" in _model(d, "status", "text")
    assert still, "the formula compiled before the second client was served: nothing was shown"
    assert served < 15.0, f"the second client waited {served:.1f} s"
    _wait(d, lambda: "--law expr" in _model(d, "command", "text"), timeout=240, what="the formula's view")
    status = _model(d, "status", "text")
    assert "Compiling" not in status and "error" not in status, status
    print(f"second client served in {served:.2f} s while the formula compiled")
