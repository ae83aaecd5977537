"""The explorer's two-parameter diagram: a panel computed on demand, in a worker process.

Continuing the bifurcation curves of the plane of ``nu`` and a law parameter takes 0.2 s
for a built-in law and up to 15 s for a formula with a Bautin point, so the page does not
recompute it on every change of a slider: its button ("Continue the curves") computes
:func:`~.session.two_parameter_view` for the shown set-up, in a worker process on a served
page (the server keeps answering meanwhile), and the panel says that it computes until the
result arrives. The set-up's point follows the sliders over the diagram shown; a change of
the law or of its other parameters (another plane) clears the diagram.
"""

from __future__ import annotations

import concurrent.futures
import functools
import html
import warnings
from collections.abc import Callable
from typing import Any

from .session import Setup, plane_key, plane_window, two_parameter_view

__all__ = ["PlanePanel"]

#: the button's label, idle and while the curves are continued
BUTTON = "Continue the curves"
BUSY = "Continuing the curves..."
#: the notes shown under the panel (the rest are counted)
MAX_NOTES = 3


class PlanePanel:
    """The two-parameter diagram of one page: its figure, button and status line.

    Parameters
    ----------
    doc : bokeh.document.Document
        The page's document.
    shown : callable
        Returns the set-up shown and the name of the vertical axis' parameter.
    pool : callable
        Returns the executor of a served page's worker processes.

    """

    def __init__(
        self,
        doc: Any,
        shown: Callable[[], tuple[Setup, str]],
        pool: Callable[[], concurrent.futures.Executor],
    ) -> None:
        from bokeh.core.properties import field
        from bokeh.models import ColumnDataSource, HoverTool, Range1d
        from bokeh.models.widgets import Button, Div
        from bokeh.plotting import figure

        self.doc = doc
        self._shown = shown
        self._pool = pool
        self.key: tuple[Any, ...] | None = None  # the plane of the diagram shown
        self.running: tuple[Any, ...] | None = None  # the plane being computed
        self._said: tuple[Any, ...] | None = None  # the plane the status line speaks of
        self.regions = ColumnDataSource(
            data={k: [] for k in ("left", "right", "bottom", "top", "color", "regime", "attractors")},
            name="plane_regions",
        )
        self.curves = ColumnDataSource(
            data={k: [] for k in ("xs", "ys", "kind", "label", "color", "dash")}, name="plane_curves"
        )
        self.points = ColumnDataSource(
            data={k: [] for k in ("x", "y", "kind", "text", "marker", "color")}, name="plane_points"
        )
        self.point = ColumnDataSource(data={"x": [], "y": []}, name="plane_point")
        self.figure = figure(
            title="Two-parameter diagram", x_axis_type="log", x_range=Range1d(start=1e-2, end=10.0),
            y_range=Range1d(start=0.0, end=1.0), height=380, width=620,
            tools="pan,wheel_zoom,box_zoom,reset,save", name="plane_figure",
        )  # fmt: skip
        f = self.figure
        # each quad outlined in its fill's colour: no light seams between the rows' quads
        quads = f.quad(
            left="left", right="right", bottom="bottom", top="top", color="color", source=self.regions,
            legend_field="regime", line_color="color", line_width=1,
        )  # fmt: skip
        lines = f.multi_line(
            "xs", "ys", source=self.curves, line_color="color", line_dash=field("dash"), line_width=2,
            legend_field="label",
        )  # fmt: skip
        marks = f.scatter(
            "x", "y", source=self.points, marker=field("marker"), fill_color="color", line_color="black",
            size=12, legend_field="kind",
        )  # fmt: skip
        f.scatter(
            "x", "y", source=self.point, marker="x", size=16, color="black", line_width=3,
            legend_label="this set-up",
        )  # fmt: skip
        f.add_tools(
            HoverTool(renderers=[marks], tooltips=[("point", "@text")]),
            HoverTool(renderers=[lines], tooltips=[("curve", "@label")]),
            HoverTool(renderers=[quads], tooltips=[("attractors", "@attractors"), ("regime", "@regime")]),
        )
        f.legend.label_text_font_size = "8pt"
        f.legend.location = "center"
        f.add_layout(f.legend[0], "right")
        self.button = Button(label=BUTTON, name="plane_button", width=220)
        self.status = Div(text="", name="plane_status", width=220)
        self.button.on_click(self.continue_curves)

    def layout(self) -> Any:
        """Return the panel's layout: the figure, the button and its status beside it."""
        from bokeh.layouts import column, row

        return row(self.figure, column(self.button, self.status))

    # ---- the computation ---------------------------------------------------------------
    def continue_curves(self) -> None:
        """Compute the diagram of the shown set-up: in a worker on a served page, else at once."""
        if self.running is not None:
            return  # one at a time: the button is disabled meanwhile
        setup, param = self._shown()
        if param not in setup.params:
            self._error(f"two-parameter diagram: {param!r} is not a parameter of the {setup.law} law")
            return
        key = plane_key(setup, param)
        self.running = key
        self.button.disabled = True
        self.button.label = BUSY
        self.status.text = (
            f"<i>continuing the curves of nu and {html.escape(param)} (a second for a built-in law, up to "
            "15 s for a formula)...</i>"
        )
        if self.doc.session_context is None:  # not served (a test, a script): at once
            future: concurrent.futures.Future[dict[str, Any]] = concurrent.futures.Future()
            try:
                future.set_result(two_parameter_view(setup, param))
            except Exception as e:  # a user's value: shown in the panel
                future.set_exception(e)
            self._computed(future, key)
            return
        future = self._pool().submit(two_parameter_view, setup, param)
        done = functools.partial(self._computed, key=key)
        future.add_done_callback(lambda f: self.doc.add_next_tick_callback(functools.partial(done, f)))

    def _computed(self, future: concurrent.futures.Future[dict[str, Any]], key: tuple[Any, ...]) -> None:
        """Show the diagram computed for the plane ``key``, if the page still shows that plane."""
        self.running = None
        self.button.disabled = False
        self.button.label = BUTTON
        error = future.exception()
        if error is not None:
            if isinstance(error, ValueError | TypeError):
                self._error(str(error), key)
            else:  # the worker died (memory, a signal), or the continuation failed
                self._error(f"the curves could not be continued: {error or type(error).__name__}", key)
            return
        setup, param = self._shown()
        if param not in setup.params or plane_key(setup, param) != key:
            self.status.text = (
                "The law or its other parameters changed while the curves were continued: press the "
                "button again for this set-up's diagram."
            )
            return
        self.show(future.result())
        self.follow(setup, param)

    def show(self, data: dict[str, Any]) -> None:
        """Put a :func:`~.session.two_parameter_view` on the page."""
        self.doc.hold("combine")
        try:
            self.regions.data = data["regions"]
            self.curves.data = data["curves"]
            self.points.data = data["points"]
            self.point.data = data["current"]
            self.key = data["key"]
            self._frame(data["x_range"], data["y_range"], data["y_log"])
            f = self.figure
            f.title.text = f"Two-parameter diagram: {data['title']}"  # type: ignore[union-attr]
            f.xaxis.axis_label = data["x_label"]
            f.yaxis.axis_label = data["y_label"]
            n = len(data["curves"]["xs"])
            kinds = sorted(set(data["points"]["kind"]))
            text = (
                f"{n} curve piece{'s' if n != 1 else ''}, {len(set(data['regions']['attractors']))} kinds of "
                f"region, codimension-2 points: {', '.join(kinds) or 'none'} (hover for their words)"
            )
            notes = [html.escape(str(m)) for m in data["notes"]]
            if notes:
                more = f" (and {len(notes) - MAX_NOTES} more)" if len(notes) > MAX_NOTES else ""
                text += (
                    "<br><small style='color:#a05a00'>" + "<br>".join(notes[:MAX_NOTES]) + more + "</small>"
                )
            self.status.text = text
        finally:
            self.doc.unhold()

    # ---- following the page ------------------------------------------------------------
    def follow(self, setup: Setup, param: str) -> None:
        """Move the set-up's point; clear a diagram of another plane (the law or its other parameters)."""
        if param not in setup.params:
            return
        self.point.data = {"x": [float(setup.nu)], "y": [float(setup.params[param])]}
        key = plane_key(setup, param)
        if key == self.key:
            return  # the point moves over the diagram shown
        if self.key is not None:
            self.key = None
            for src in (self.regions, self.curves, self.points):
                src.data = {k: [] for k in src.data}
            if self.running is None:
                self._said = key
                self.status.text = (
                    "The diagram shown was of another law or other parameters: cleared. Press the button "
                    "for this set-up's."
                )
        elif self.running is None and key != self._said:
            self._said = key
            self.status.text = (
                f"Press the button for the bifurcation curves over nu and {html.escape(param)} about this "
                "set-up: the Hopf, fold-of-cycles and grazing curves, their codimension-2 points, and the "
                "regions between them, named by their attractors."
            )
        try:
            with warnings.catch_warnings():  # the law's own, shown by the page's update already
                warnings.simplefilter("ignore")
                nus, values = plane_window(setup, param)
        except ValueError:
            return
        self._frame(nus, values, False)

    def _frame(self, x: tuple[float, float], y: tuple[float, float], y_log: bool) -> None:
        from bokeh.models import (
            BasicTicker,
            BasicTickFormatter,
            LinearScale,
            LogScale,
            LogTicker,
            LogTickFormatter,
        )

        f = self.figure
        f.x_range.update(start=x[0], end=x[1])
        f.y_range.update(start=y[0], end=y[1])
        if y_log != isinstance(f.y_scale, LogScale):
            f.y_scale = LogScale() if y_log else LinearScale()
            f.yaxis.ticker = LogTicker() if y_log else BasicTicker()
            f.yaxis.formatter = LogTickFormatter() if y_log else BasicTickFormatter()

    def _error(self, message: str, key: tuple[Any, ...] | None = None) -> None:
        self._said = key  # the message stays until the page shows another plane
        self.status.text = f"<span style='color:#b00020'><b>error</b>: {html.escape(message)}</span>"
