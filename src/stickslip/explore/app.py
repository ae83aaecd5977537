"""``stickslip explore``: the one-block model in the browser, updated live.

A Bokeh server application (Bokeh, not Panel: the widgets, the plots and the
server come in one library that Panel itself is built on, and an update ships
only the new numbers of the plots' data sources over the page's websocket).
Every change of a widget calls :func:`stickslip.explore.session.compute` in the
server process, that is the compiled engine, and replaces the data of the four
plots: the spring force against time, the phase portrait, the amplitude-velocity
curve with the paper's criterion, and the regime diagram. A fifth, the two-parameter
bifurcation diagram (:mod:`~.plane_panel`), is computed when its button is pressed.

The page's models carry names (``status``, ``command``, ``force``, ``nu``, ...)
so that a test or a script can read them from BokehJS.
"""

from __future__ import annotations

import concurrent.futures
import functools
import html
import math
import multiprocessing
import time
import warnings
import webbrowser
from typing import Any

import numpy as np

from ..models import PhysicalParameters
from .plane_panel import PlanePanel
from .session import (
    DEFAULT_EXPRESSION_PARAMS,
    EXPR,
    REGIMES,
    Setup,
    View,
    check_nu,
    compute,
    default_params,
    law_names,
    parse_params,
    prepare,
    regime_diagram,
    slider_range,
    view_csv,
)

__all__ = ["Explorer", "make_server", "serve"]

#: a colour per regime, in the order of :data:`REGIMES`
COLORS = ("#d95f02", "#1b9e77", "#66a61e", "#7570b3", "#bbbbbb")
TITLE = "stickslip explorer"
#: the page's HTML: Bokeh's, with a notice that shows until the document has rendered (the
#: plots arrive over the websocket after the load event; without it the page stayed blank)
LOADING_TEMPLATE_TEXT = """{% extends base %}
{% block contents %}
<div id="loading" style="font: 16px sans-serif; margin: 2em; color: #333">
<h2 style="margin: 0">stickslip explorer</h2>
<p>Loading: the page connects to stickslip's engine, which computes the plots (a few seconds;
the first page after an install compiles the engine, up to half a minute). It needs JavaScript and
the <code>stickslip explore</code> process that served it.</p>
</div>
{{ super() }}
{% endblock %}
"""


#: worker processes that compile a law's engine for served pages (:func:`_workers`)
_WORKERS: concurrent.futures.ProcessPoolExecutor | None = None
#: the laws (name, formula) whose engine this process has compiled or loaded
_PREPARED: set[tuple[str, str]] = set()


def _workers() -> concurrent.futures.ProcessPoolExecutor:
    """Return the server's pool of two worker processes, started at its first use.

    A law's first view compiles its engine for 10 to 30 s. Compiled on the server's
    event loop, it held every page, static files included, for that time; in a thread,
    numba and LLVM hold the interpreter's lock for seconds at a time. In a process of
    its own ("spawn": a fork of a server with threads is unsafe) it holds nothing.
    """
    global _WORKERS
    if _WORKERS is None:
        _WORKERS = concurrent.futures.ProcessPoolExecutor(
            max_workers=2, mp_context=multiprocessing.get_context("spawn")
        )
    return _WORKERS


def _law_key(setup: Setup) -> tuple[str, str]:
    return (setup.law, setup.expression if setup.law == EXPR else "")


class Explorer:
    """The widgets, plots and callbacks of one page (one Bokeh document).

    Parameters
    ----------
    doc : bokeh.document.Document
        The page's document.
    setup : Setup, optional
        The set-up shown first (default: the paper's F1 law, ``nu = 1``: its curve spans
        nu = 0.1 to 10, stick-slip and the slip reversal above nu = 4.5).

    """

    def __init__(self, doc: Any, setup: Setup | None = None) -> None:
        from bokeh.events import DocumentReady
        from bokeh.layouts import column, gridplot, row
        from bokeh.models import ColumnDataSource, CustomJS
        from bokeh.models.widgets import Button, Div, PreText, RadioButtonGroup, Select, Slider, TextInput
        from bokeh.plotting import figure
        from jinja2 import Template

        self.doc = doc
        self.setup = setup or Setup()
        check_nu(self.setup.nu)
        self.updates = 0
        self.last_update_s = math.nan
        self._diagram_key: tuple[Any, ...] | None = None
        s = self.setup

        self.law = Select(title="Friction law", value=s.law, options=list[Any](law_names()), name="law")
        self.expression = TextInput(
            title="f(w), dimensionless (expr)", value=s.expression, name="expression", visible=s.law == EXPR
        )
        self.expr_params = TextInput(
            title="its parameters",
            value=_params_text(s.params) if s.law == EXPR else DEFAULT_EXPRESSION_PARAMS,
            name="expr_params",
            visible=s.law == EXPR,
        )
        self.apply = Button(label="Compile and apply the formula", name="apply", visible=s.law == EXPR)
        self.param_box = column(name="param_box")
        self.law_si = Div(text="", name="law_si", width=330)  # the law in SI units, in physical units
        self.diagram_param = Select(title="The diagrams' vertical axis", name="diagram_param")
        self.nu = Slider(
            title="log10 nu (nu = beta v0)",
            start=-5.0,
            end=1.0,
            step=0.01,
            value=round(math.log10(s.nu), 2),
            name="nu",
        )
        self._nu_exact = (self.nu.value, float(s.nu))
        self.units = RadioButtonGroup(labels=["dimensionless", "physical (SI)"], active=int(s.physical))
        self.scales = {
            "mass": TextInput(title="mass (kg)", value=repr(s.mass), name="mass"),
            "stiffness": TextInput(title="stiffness (N/m)", value=repr(s.stiffness), name="stiffness"),
            "load": TextInput(title="normal load W (N)", value=repr(s.load), name="load"),
            "mu_s": TextInput(title="mu_s", value=repr(s.mu_s), name="mu_s"),
        }
        self.status = Div(text="", name="status", width=330)
        self.command = PreText(text="", name="command", width=330)
        self.csv_button = Button(label="Download the motion as CSV", name="csv_button")
        self.csv = ColumnDataSource(data={"text": [""], "n": [0]}, name="csv")
        self.csv.js_on_change(
            "data",
            CustomJS(
                args={"src": self.csv},
                code="""
                const text = src.data.text[0];
                if (!text) { return; }
                const blob = new Blob([text], {type: 'text/csv'});
                const a = document.createElement('a');
                a.href = URL.createObjectURL(blob);
                a.download = 'stickslip-explore.csv';
                document.body.appendChild(a); a.click(); a.remove();
                """,
            ),
        )

        self.force = ColumnDataSource(data={"x": [], "y": []}, name="force")
        self.force_stuck = ColumnDataSource(data={"x": [], "y": []}, name="force_stuck")
        self.phase = ColumnDataSource(data={"x": [], "y": []}, name="phase")
        self.phase_stuck = ColumnDataSource(data={"x": [], "y": []}, name="phase_stuck")
        self.curve = ColumnDataSource(data={"x": [], "y": [], "color": [], "regime": []}, name="curve")
        self.current = ColumnDataSource(data={"x": [], "y": []}, name="current")
        self.diagram = ColumnDataSource(
            data={"left": [], "right": [], "bottom": [], "top": [], "color": [], "regime": []}, name="diagram"
        )
        self.diagram_point = ColumnDataSource(data={"x": [], "y": []}, name="diagram_point")

        opts: dict[str, Any] = {"height": 300, "width": 440, "tools": "pan,wheel_zoom,box_zoom,reset,save"}
        self.f_force = figure(title="Spring force against time", **opts)
        self.f_force.line("x", "y", source=self.force, line_width=1.5, legend_label="spring force")
        self.f_force.scatter("x", "y", source=self.force_stuck, size=3, color=COLORS[0], legend_label="stuck")
        self.f_phase = figure(title="Phase portrait", **opts)
        self.f_phase.line("x", "y", source=self.phase, line_width=1.5, legend_label="motion")
        self.f_phase.scatter("x", "y", source=self.phase_stuck, size=4, color=COLORS[0], legend_label="stick")
        self.f_curve = figure(title="Amplitude against driving velocity", x_axis_type="log", **opts)
        self.f_curve.line("x", "y", source=self.curve, color="#555555", legend_label="from rest")
        self.f_curve.scatter("x", "y", source=self.curve, color="color", size=6, legend_field="regime")
        self.f_curve.scatter(
            "x", "y", source=self.current, marker="diamond", size=14, color="black", legend_label="this nu"
        )
        self.f_diag = figure(title="Regimes", x_axis_type="log", **opts)
        self.f_diag.quad(
            left="left", right="right", bottom="bottom", top="top", color="color",
            source=self.diagram, legend_field="regime", line_color=None,
        )  # fmt: skip
        self.f_diag.scatter(
            "x", "y", source=self.diagram_point, marker="x", size=16, color="black", line_width=3,
            legend_label="this set-up",
        )  # fmt: skip
        for f in (self.f_force, self.f_phase, self.f_curve, self.f_diag):
            f.legend.location = "top_right"
            f.legend.label_text_font_size = "8pt"
            f.legend.background_fill_alpha = 0.6
        self.f_curve.legend.location = "top_left"  # the amplitude rises to the right in stick-slip
        # the regimes' legend beside the map, not over it
        self.f_diag.legend.location = "center"
        self.f_diag.legend.background_fill_alpha = 1.0
        self.f_diag.add_layout(self.f_diag.legend[0], "right")
        self.f_diag.width = 560
        # the two-parameter diagram, computed on demand in a worker (``_workers`` read at the press)
        self.plane = PlanePanel(doc, self._plane_setup, lambda: _workers())

        self.law.on_change("value", self._on_law)
        self.apply.on_click(self._on_apply)
        self.nu.on_change("value", self._on_change)
        self.units.on_change("active", self._on_change)
        self.diagram_param.on_change("value", self._on_change)
        for w in self.scales.values():
            w.on_change("value", self._on_change)
        self.csv_button.on_click(self._on_csv)

        self._building = True  # no update for each widget set while the page is built
        self._build_params()
        self._building = False
        head = Div(
            text=f"<h2 style='margin:0'>{TITLE}</h2><p style='margin:0'>the one-block spring-slider, "
            "exact (no smoothing of the friction law), computed live by stickslip's engine</p>",
            width=330,
            name="title",
        )
        controls = column(
            head, self.law, self.expression, self.expr_params, self.apply, self.param_box, self.law_si,
            self.nu, self.diagram_param, self.units, *self.scales.values(), self.status, self.csv_button,
            Div(text="<b>The same set-up from the shell:</b>"), self.command, width=350,
        )  # fmt: skip
        plots = gridplot(
            [[self.f_force, self.f_phase], [self.f_curve, self.f_diag]], toolbar_location="right"
        )
        doc.title = TITLE
        doc.template = Template(LOADING_TEMPLATE_TEXT)
        doc.js_on_event(
            DocumentReady, CustomJS(code="const n = document.getElementById('loading'); if (n) n.remove();")
        )
        doc.add_root(row(controls, column(plots, self.plane.layout())))
        doc.add_root(self.csv)  # not drawn: the page downloads its text when it changes
        self.update()

    # ---- widgets -----------------------------------------------------
    def _build_params(self) -> None:
        from bokeh.models.widgets import Slider

        sliders: list[Any] = []
        # one slider per parameter name for the page's life: a new one for a name seen before
        # (weakening, cubic, weakening again) would leave two models of that name in BokehJS,
        # and get_model_by_name would find the stale one
        pool: dict[str, Any] = self.__dict__.setdefault("_slider_pool", {})
        for name, value in self.setup.params.items():
            settings = _slider_settings(self.setup.law, name, float(value))
            sl = pool.get(name)
            if sl is None:
                sl = pool[name] = Slider(title=name, name=f"param_{name}", **settings)
                sl.on_change("value", self._on_change)
            else:
                sl.update(**settings)
            sliders.append(sl)
        self.param_box.children = sliders
        self.param_sliders: list[Any] = sliders
        names: list[Any] = list(self.setup.params)
        self.diagram_param.options = names
        self.diagram_param.value = names[-1] if names else ""

    def _on_law(self, attr: str, old: Any, new: Any) -> None:
        if getattr(self, "_reverting", False):
            return
        names = law_names()
        if new not in names:  # a page's message may carry any text, not only the menu's choices
            self._error(f"law={new!r} is not one the explorer offers: expected one of {', '.join(names)}")
            self._reverting = True
            try:
                self.law.value = self.setup.law
            finally:
                self._reverting = False
            return
        is_expr = new == EXPR
        for w in (self.expression, self.expr_params, self.apply):
            w.visible = is_expr
        if is_expr:
            self._on_apply()
            return
        self.setup = self.setup.with_(law=new, params=default_params(new))
        # a law's first view compiles its engine (seconds): said before, done on the next tick
        message = f"Computing the {new} law (the first time: compiling it, about 10 s)..."
        if self._prepare(self._rebuild, message):
            return
        self._later(self._rebuild, message)

    def _on_apply(self) -> None:
        """Take the formula and its parameters; compile (once) and show it on the next tick."""
        try:
            params = parse_params(self.expr_params.value)
        except ValueError as e:
            self._error(str(e))
            return
        self.setup = self.setup.with_(law=EXPR, params=params, expression=self.expression.value)
        message = "Compiling the engine for this formula (the first time only, about 20 s)..."
        if self._prepare(self._rebuild, message):
            return
        self._set_status(message)
        self.doc.add_next_tick_callback(self._rebuild)

    def _prepare(self, work: Any, message: str) -> bool:
        """Compile the set-up's law in a worker process, then run ``work`` on the page's loop.

        Returns whether it did so: not for a document that is not served (a test, a
        script), nor for a law this process has compiled already.
        """
        key = _law_key(self.setup)
        if self.doc.session_context is None or key in _PREPARED:
            return False
        self._set_status(message)
        future = _workers().submit(prepare, self.setup)
        done = functools.partial(self._prepared, key=key, work=work)
        future.add_done_callback(lambda f: self.doc.add_next_tick_callback(functools.partial(done, f)))
        return True

    def _prepared(self, future: concurrent.futures.Future[None], key: tuple[str, str], work: Any) -> None:
        """Run ``work`` once the worker has compiled the law (or found the set-up wrong)."""
        error = future.exception()
        if error is None:
            _PREPARED.add(key)
        elif not isinstance(error, ValueError | TypeError):  # the worker died (memory, a signal)
            self._error(f"the engine could not be compiled for this law: {error or type(error).__name__}")
            return
        work()  # a wrong set-up fails again here, at once, with its message on the page

    def _rebuild(self) -> None:
        """Make the sliders of ``self.setup``'s law and show it; where it fails, keep the shown one whole.

        So a formula's parameter that is not a number (``c=nan``) is refused before its
        slider's range is made (the page would stay on "Compiling"), and one the formula does
        not have (``z=1``) before its slider is made (the sliders would no longer match the
        plots).
        """
        shown = self.view.setup if getattr(self, "view", None) is not None else None
        self._building = True
        try:
            self._build_params()
        except Exception as e:  # a user's value
            self._error(str(e))
            self._restore(shown)
            return
        finally:
            self._building = False
        if not self.update():
            self._restore(shown)

    def _restore(self, shown: Setup | None) -> None:
        """Put the sliders of the shown view back (its set-up), the error message kept."""
        if shown is None:
            return
        self.setup = shown
        self._building = True
        try:
            self._build_params()
        finally:
            self._building = False

    def _on_change(self, attr: str, old: Any, new: Any) -> None:
        if getattr(self, "_building", False):
            return
        self._later(self.update, None)

    def _later(self, work: Any, message: str | None) -> None:
        """Run ``work`` on the next tick of a served page, once however many changes ask for it.

        The page first says that it is computing (``message``, or a line under the last
        result): a slow case (a steep law, a large nu, a law's first compilation) left the
        page as it was for seconds to minutes without a word. In a document not served
        (a test, a script) ``work`` runs at once.
        """
        if self.doc.session_context is None:
            work()
            return
        pending: set[str] = self.__dict__.setdefault("_pending", set())
        key = str(getattr(work, "__name__", work))
        if key in pending:
            return  # one update, with the widgets' values when it runs
        pending.add(key)
        note = message or "<i>computing...</i>"
        self._set_status(note if message else f"{self.status.text}<br>{note}")

        def run() -> None:
            pending.discard(key)
            work()

        self.doc.add_next_tick_callback(run)

    def _on_csv(self) -> None:
        view = getattr(self, "view", None)
        if view is not None:
            self.csv.data = {"text": [view_csv(view)], "n": [self.csv.data["n"][0] + 1]}

    def _read_setup(self) -> Setup:
        params = {str(sl.name).removeprefix("param_"): float(sl.value) for sl in self.param_sliders}
        scales: dict[str, float] = {}
        for key, w in self.scales.items():
            try:
                scales[key] = float(w.value)
            except ValueError:
                raise ValueError(f"{key}={w.value!r}: expected a number ({w.title})") from None
        # the slider holds log10(nu) to 0.01: the set-up's own nu until it is moved; a value set
        # from outside the page (a script) is held to the slider's range (log10 nu = 3 ran minutes)
        log_nu = min(max(float(self.nu.value), float(self.nu.start)), float(self.nu.end))
        nu = self._nu_exact[1] if self.nu.value == self._nu_exact[0] else float(10.0**log_nu)
        read = self.setup.with_(params=params, nu=nu, physical=self.units.active == 1)
        if not (self.setup.physical and read.physical):
            return read.with_(**scales)
        # in physical units a new scale holds v0 and the law in SI: nu and the sliders follow
        return read.rescaled(**scales)

    def _sync_widgets(self, setup: Setup) -> None:
        """Set the sliders to ``setup``'s nu and law parameters (moved by a new physical scale)."""
        self._building = True
        try:
            log_nu = round(math.log10(setup.nu), 2)
            if self._nu_exact[1] != setup.nu:
                self.nu.value = log_nu
                self._nu_exact = (log_nu, float(setup.nu))
            for sl in self.param_sliders:
                name = str(sl.name).removeprefix("param_")
                value = float(setup.params[name])
                if float(sl.value) != value:
                    sl.update(**_slider_settings(setup.law, name, value))
        finally:
            self._building = False

    # ---- the update --------------------------------------------------
    def update(self) -> bool:
        """Recompute the view from the widgets and push it to the page; return whether it could.

        The warnings of the computation (a law that turns negative, a motion beyond a
        table) are shown under the result: they reached only the server's terminal.
        """
        t0 = time.perf_counter()
        try:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                setup = self._read_setup()
                view = compute(setup)
                diagram = self._diagram_data(view)
        except Exception as e:  # a user's value: shown on the page, the last view stays whole
            self._error(str(e))
            return False
        notes = list(dict.fromkeys(str(w.message) for w in caught if issubclass(w.category, UserWarning)))
        self.setup = setup
        self.view = view
        self._sync_widgets(setup)
        # one message to the page for the whole update, not one per changed property
        self.doc.hold("combine")
        try:
            self._push(view, diagram)
            self.plane.follow(setup, self.diagram_param.value)
            self.last_update_s = time.perf_counter() - t0
            self.updates += 1
            self._set_status(self._summary(view) + _warnings_html(notes))
        finally:
            self.doc.unhold()
        return True

    def _push(self, v: View, diagram: dict[str, Any] | None) -> None:
        u = v.units
        self.force.data = {"x": v.time, "y": v.spring_force}
        self.force_stuck.data = {"x": v.time[v.stuck], "y": v.spring_force[v.stuck]}
        self.phase.data = {"x": v.velocity, "y": v.spring_force}
        self.phase_stuck.data = {"x": v.velocity[v.stuck], "y": v.spring_force[v.stuck]}
        unknown = REGIMES.index("unknown")
        colors = [COLORS[REGIMES.index(r) if r in REGIMES else unknown] for r in v.curve_regime]
        self.curve.data = {
            "x": v.curve_v,
            "y": v.curve_amplitude,
            "color": colors,
            "regime": list(v.curve_regime),
        }
        self.current.data = {"x": [v.v0], "y": [v.amplitude]}
        self.f_force.xaxis.axis_label = f"time [{u['time']}]"
        self.f_force.yaxis.axis_label = f"spring force [{u['force']}]"
        self.f_phase.xaxis.axis_label = f"slip velocity [{u['velocity']}]"
        self.f_phase.yaxis.axis_label = f"spring force [{u['force']}]"
        self.f_curve.xaxis.axis_label = f"driving velocity [{u['velocity']}]"
        self.f_curve.yaxis.axis_label = f"amplitude [{u['force']}]"
        title: Any = self.f_curve.title
        title.text = f"Criterion: {v.verdict}; the model: {v.regime}"
        self._push_diagram(v, diagram)
        self.command.text = v.command
        self.nu.title = f"log10 nu (nu = beta v0 = {v.setup.nu:.4g}; v0 = {v.v0:.4g} {u['velocity']})"
        self.law_si.text = _law_si(v.setup)

    def _diagram_data(self, v: View) -> dict[str, Any] | None:
        """Return the regime diagram's new cells, or None when the shown ones still hold."""
        s = v.setup
        param = self.diagram_param.value
        if not param:
            return {"cells": {k: [] for k in self.diagram.data}, "key": None, "range": (math.inf, -math.inf)}
        if param not in s.params:  # a page's message may carry any text
            raise ValueError(
                f"regime diagram: {param!r} is not a parameter of the law: expected one of "
                f"{', '.join(s.params) or '(none)'}"
            )
        others = tuple(sorted((k, x) for k, x in s.params.items() if k != param))
        decade = round(math.log10(s.nu))
        key = (s.law, s.expression, param, others, decade, s.physical, s.mass, s.stiffness, s.load, s.mu_s)
        value = float(s.params[param])
        if key == self._diagram_key and self._diagram_range[0] <= value <= self._diagram_range[1]:
            return None
        nus, values, codes = regime_diagram(s.dimensionless_law(), param, 10.0**decade, value)
        edges_x = np.exp(_edges(np.log(nus))) * (v.v0 / s.nu)
        edges_y = _edges(values)
        jj, ii = np.meshgrid(np.arange(len(nus)), np.arange(len(values)))
        cells = {
            "left": edges_x[jj.ravel()],
            "right": edges_x[jj.ravel() + 1],
            "bottom": edges_y[ii.ravel()],
            "top": edges_y[ii.ravel() + 1],
            "color": [COLORS[c] for c in codes.ravel()],
            "regime": [REGIMES[c] for c in codes.ravel()],
        }
        return {"cells": cells, "key": key, "range": (float(edges_y[0]), float(edges_y[-1]))}

    def _push_diagram(self, v: View, diagram: dict[str, Any] | None) -> None:
        param = self.diagram_param.value
        if diagram is not None:
            self.diagram.data = diagram["cells"]
            self._diagram_key = diagram["key"]
            self._diagram_range = diagram["range"]
            self.f_diag.xaxis.axis_label = f"driving velocity [{v.units['velocity']}]"
            self.f_diag.yaxis.axis_label = param
        if param:
            self.diagram_point.data = {"x": [v.v0], "y": [float(v.setup.params[param])]}
        else:
            self.diagram_point.data = {"x": [], "y": []}

    _diagram_range: tuple[float, float] = (math.inf, -math.inf)

    def _plane_setup(self) -> tuple[Setup, str]:
        """Return the set-up shown (the last that could be computed) and the diagrams' vertical axis."""
        view = getattr(self, "view", None)
        return (view.setup if view is not None else self.setup), str(self.diagram_param.value)

    def _summary(self, v: View) -> str:
        u = v.units
        period = "-" if not math.isfinite(v.period) else f"{v.period:.5g} {u['time']}"
        ok = v.verdict == v.regime or v.verdict == "inconclusive"
        mark = "" if v.verdict == "inconclusive" else (" (right)" if ok else " (<b>wrong</b>)")
        # five significant digits shown; every digit in the span's data-value (the CSV has them too)
        return (
            f"<b>regime</b>: {v.regime}<br><b>amplitude</b>: <span id='amplitude' "
            f"data-value='{v.amplitude!r}'>{v.amplitude:.5g}</span> "
            f"{u['force']}<br><b>period</b>: {period}<br><b>stick fraction</b>: {v.stick_fraction:.4g}<br>"
            f"<b>criterion</b>: {v.verdict}{mark}<br><small>{v.verdict_reason}</small>"
            + (
                "<br><small>a formula f(w) is dimensionless: shown in units of mu_s W and sqrt(m/k)</small>"
                if v.setup.physical and v.setup.law == EXPR
                else ""
            )
        )

    def _set_status(self, html: str) -> None:
        self.status.text = html

    def _error(self, message: str) -> None:
        # escaped: a message that quotes a quantity (<Quantity(3.3e+152, 's / m')>) would lose it
        # as a tag, and read "a= , b= :"
        self.status.text = f"<span style='color:#b00020'><b>error</b>: {html.escape(message)}</span>"


def _slider_settings(law: str, name: str, value: float) -> dict[str, Any]:
    """Return a parameter slider's range, step and value (held inside the range) for ``value``."""
    start, end, step = slider_range(law, name, value)
    return {"start": start, "end": end, "step": step, "value": min(max(value, start), end)}


def _law_si(setup: Setup) -> str:
    """Return the law's physical parameters, shown under the sliders in physical units."""
    params = setup.parameters()
    if not isinstance(params, PhysicalParameters):
        return ""
    values = [f"mu_s = {params.law.mu_s:.6g}"] + [
        f"{k} = {q:.6g~P}" if hasattr(q, "units") else f"{k} = {q:.6g}" for k, q in params.law.params.items()
    ]
    return f"<small>in SI: {html.escape(', '.join(values))} (held when a scale below changes)</small>"


def _warnings_html(notes: list[str]) -> str:
    """Return the computation's warnings as HTML for under the result (empty where there are none)."""
    if not notes:
        return ""
    items = "".join(f"<br>{html.escape(n)}" for n in notes[:5])
    more = f"<br>(and {len(notes) - 5} more)" if len(notes) > 5 else ""
    return f"<br><span id='warnings' style='color:#a05a00'><b>warning</b>:{items}{more}</span>"


def _edges(centres: np.ndarray) -> np.ndarray:
    """Return the cell edges of equally spaced centres (one more than the centres)."""
    half = (centres[1] - centres[0]) / 2.0
    return np.concatenate([[centres[0] - half], (centres[1:] + centres[:-1]) / 2.0, [centres[-1] + half]])


def make_server(port: int = 5006, host: str = "127.0.0.1", setup: Setup | None = None) -> Any:
    """Return a started Bokeh server of the explorer (its io loop not yet running)."""
    if setup is not None:
        check_nu(setup.nu)  # here, not at the first page load
    from bokeh.application import Application
    from bokeh.application.handlers.function import FunctionHandler
    from bokeh.server.server import Server

    def page(doc: Any) -> None:
        Explorer(doc, setup)

    # the page's websocket is accepted from the address it was served at; listening on
    # every interface, from any (the page is then reached by this machine's name or address)
    origins = [f"*:{port}"] if host in ("0.0.0.0", "::", "") else [f"{host}:{port}", f"localhost:{port}"]
    server = Server(
        {"/": Application(FunctionHandler(page))}, port=port, address=host, allow_websocket_origin=origins
    )
    server.start()
    return server


def serve(
    port: int = 5006, host: str = "127.0.0.1", open_browser: bool = True, setup: Setup | None = None
) -> None:
    """Serve the explorer on ``http://host:port/`` until interrupted."""
    server = make_server(port, host, setup)
    url = f"http://{host}:{port}/"
    print(f"{TITLE}: {url} (Ctrl-C stops it)", flush=True)
    if open_browser:
        server.io_loop.add_callback(webbrowser.open, url)
    try:
        server.io_loop.start()
    except KeyboardInterrupt:
        pass
    finally:
        server.stop()
        if _WORKERS is not None:
            _WORKERS.shutdown(wait=False, cancel_futures=True)


def _params_text(params: Any) -> str:
    """``{'c': 2.0, 'q': 0.5}`` as the formula box's text ``'c=2, q=0.5'``, every digit kept.

    (``.15g`` showed 0.1 + 0.2 as 0.3, and Apply changed it.)
    """
    return ", ".join(f"{k}={repr(float(v)).removesuffix('.0')}" for k, v in params.items())
