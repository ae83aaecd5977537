"""The reproduction report: each claim of the paper against the model's number.

Built from the reproduction dataset only; written as Markdown (figures linked)
and as one self-contained HTML file (figures embedded). The claims and their
verdicts are made in :mod:`stickslip.paper.claims` (re-exported here); this module
lays them out, with the set-up, the figures and the criterion's trial, as blocks
(headings, paragraphs, lists, tables, figures) written both ways.
"""

from __future__ import annotations

import base64
import html
import math
import os
from dataclasses import dataclass

import numpy as np
import xarray as xr

from ..io.output import OutputFolder, generator, text_writer
from .claims import GRADES, Claim, claims
from .claims import ZV_LOAD as ZV_LOAD
from .claims import _against_measured as _against_measured
from .claims import _directions as _directions
from .claims import _trend as _trend
from .claims import classify_trend as classify_trend
from .claims import grade as grade
from .figures import FIGURES

__all__ = ["Claim", "claims", "write_report"]


@dataclass(frozen=True)
class _Heading:
    level: int
    text: str


@dataclass(frozen=True)
class _Para:
    text: str


@dataclass(frozen=True)
class _Bullets:
    items: tuple[str, ...]


@dataclass(frozen=True)
class _Table:
    head: tuple[str, ...]
    rows: tuple[tuple[str, ...], ...]


@dataclass(frozen=True)
class _Figure:
    path: str
    caption: str


_Block = _Heading | _Para | _Bullets | _Table | _Figure


def _grade_counts(cl: list[Claim]) -> str:
    """Return one sentence: how many of the claims fall in each grade."""
    counts = {g: sum(c.grade == g for c in cl) for g in GRADES}
    words = {
        "agrees": "the model agrees with {}",
        "agrees in part": "agrees in part with {}",
        "disagrees": "disagrees with {}",
        "not testable": "{} cannot be tested from the paper",
        "inconsistent in the paper": "{} are inconsistencies in the paper itself",
    }
    parts = [words[g].format(n) for g, n in counts.items() if n]
    return (
        f"Of the paper's {len(cl)} claims, " + ", ".join(parts) + ". A verdict says whether the "
        "model bears out what the paper says (agrees), not whether the model matches an experiment."
    )


def _blocks(ds: xr.Dataset, figure_files: dict[str, str]) -> list[_Block]:
    cl = claims(ds)
    beta_claim = next(c.number for c in cl if c.paper.startswith("Parameters: beta"))
    beta_1kg = float(ds.attrs.get("beta_from_1kg", math.nan))
    mass_42 = float(ds.attrs.get("mass_for_beta_42", math.nan))
    blocks: list[_Block] = [
        _Heading(1, "Reproduction: How to distinguish between stick-slip and pure slip oscillations"),
        _Para(
            "J. Szkutnik and K. Kułakowski, arXiv cond-mat/0506435, reproduced with stickslip: "
            "one-block spring-slider, event-driven integration without smoothing the friction "
            "law (stick phases in closed form, slip by DOP853 with events located on its dense "
            "output). Every number below is computed from the data in reproduce.nc, which also "
            "holds every curve."
        ),
        *(
            [
                _Para(
                    f"A quick run (--quick): the curves are computed on a reduced grid "
                    f"({ds.attrs.get('grid', '')}), so numbers read off them (slopes, crossings, "
                    "the beta fitted to a slope) are rough and the figures polygonal; run without "
                    "--quick for the report's numbers."
                )
            ]
            if int(ds.attrs.get("quick", 0))
            else []
        ),
        _Heading(2, "Verdicts"),
        _Para(_grade_counts(cl)),
        _Table(
            ("#", "the paper says", "verdict"),
            tuple((str(c.number), c.paper, c.grade) for c in cl),
        ),
        _Heading(2, "Set-up and choices"),
        _Bullets(
            (
                "zv and bri are the paper's own keys for its two experiments (its bibliography is "
                "not in the source): zv, a PMMA sample scratched by a conical diamond indenter "
                "(the paper's Figs. 1, 2 and its Fig. 4 data); bri, another PMMA experiment (its "
                "Fig. 5, the paper's Fig. 3).",
                "zv experiment: W = 196 mN, mu0 = 0.46, a = 160 s/m, k = 62 N/m, v0 from 5 to "
                "1000 um/s; F1 = mu0 W/(1 + a v), F2 = mu0 W [1/(1 + a v) + b v] (b v in units of "
                "mu0 W, the only reading under which the paper's p = b/beta = 2.38 holds).",
                f"beta: the paper uses 42 s/m but says the mass is of order 1000 g, which gives "
                f"{beta_1kg:.1f} s/m. We use beta = 42 s/m, i.e. m = {mass_42:.4f} kg (claim {beta_claim}).",
                "Fig. 3 (bri): a = 250 s/m, b = 0, other parameters as zv, beta = 42, 158, 418 s/m "
                "(the mass set by beta); amplitude in units of mu0 W.",
                "No measured data points are public: measured trends are quoted as the paper states "
                "them, never as invented points.",
            )
        ),
        _Heading(2, "Claims"),
        _Table(
            ("#", "the paper says", "the model gives", "verdict"),
            tuple((str(c.number), c.paper, c.model, f"{c.grade} ({c.verdict})") for c in cl),
        ),
        _Heading(2, "Figures"),
    ]
    for name, (_, caption) in FIGURES.items():
        if name in figure_files:
            blocks.append(_Figure(figure_files[name], caption))
    blocks.append(_Heading(2, "What the criterion can and cannot tell"))
    blocks.append(
        _Para(
            "The criterion reads the sign of d log(amplitude)/d log(v0). It comes from "
            "Thomsen and Fidlin's averaging analysis of a cubic friction law, where "
            "stick-slip amplitude grows with the belt velocity and pure-slip amplitude "
            "shrinks towards the Hopf point. It is a heuristic for one law in a weakly "
            "nonlinear limit, not a theorem. The model reproduced here gives rising "
            "amplitudes in its stick-slip range at the paper's set-up (F1, F2), in agreement "
            "with it, but not everywhere: F2 with a light block (the mass dependence above, "
            "10 g and less) sticks and slips with an amplitude that falls with v0, "
            "and a falling measured amplitude can have other causes too (a different law, "
            "inertia of the set-up, several regimes within the range)."
        )
    )
    return blocks


def _md(blocks: list[_Block]) -> str:
    lines: list[str] = []
    for b in blocks:
        if isinstance(b, _Heading):
            lines += ["#" * b.level + " " + b.text, ""]
        elif isinstance(b, _Para):
            lines += [b.text, ""]
        elif isinstance(b, _Bullets):
            lines += [f"- {item}" for item in b.items] + [""]
        elif isinstance(b, _Table):
            lines.append("| " + " | ".join(b.head) + " |")
            lines.append("|" + "---|" * len(b.head))
            lines += ["| " + " | ".join(c.replace("|", "/") for c in r) + " |" for r in b.rows]
            lines.append("")
        else:
            lines += [f"![{b.caption}]({os.path.basename(b.path)})", "", f"*{b.caption}*", ""]
    return "\n".join(lines)


def _html(blocks: list[_Block]) -> str:
    e = html.escape
    body: list[str] = []
    for b in blocks:
        if isinstance(b, _Heading):
            body.append(f"<h{b.level}>{e(b.text)}</h{b.level}>")
        elif isinstance(b, _Para):
            body.append(f"<p>{e(b.text)}</p>")
        elif isinstance(b, _Bullets):
            body.append("<ul>" + "".join(f"<li>{e(i)}</li>" for i in b.items) + "</ul>")
        elif isinstance(b, _Table):
            body.append(
                "<table><thead><tr>"
                + "".join(f"<th>{e(h)}</th>" for h in b.head)
                + "</tr></thead><tbody>"
                + "".join("<tr>" + "".join(f"<td>{e(c)}</td>" for c in r) + "</tr>" for r in b.rows)
                + "</tbody></table>"
            )
        else:
            with open(b.path, "rb") as fh:
                data = base64.b64encode(fh.read()).decode("ascii")
            body.append(
                f'<figure><img alt="{e(b.caption)}" src="data:image/png;base64,{data}">'
                f"<figcaption>{e(b.caption)}</figcaption></figure>"
            )
    style = (
        "body{font-family:sans-serif;max-width:60em;margin:2em auto;line-height:1.4}"
        "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:.4em;"
        "vertical-align:top;text-align:left}img{max-width:100%}figure{margin:1.5em 0}"
    )
    return (
        "<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>"
        "<title>stickslip reproduction report</title>"
        f"<style>{style}</style></head><body>" + "\n".join(body) + "</body></html>\n"
    )


def write_report(
    ds: xr.Dataset,
    out: OutputFolder,
    figure_files: dict[str, str],
    trials: dict[str, xr.Dataset] | None = None,
) -> tuple[str, str]:
    """Write ``report.md`` and ``report.html`` into the run's output folder; return their paths.

    ``figure_files`` maps a figure's name to a readable PNG (embedded in the HTML,
    linked by its file name from the Markdown).
    """
    blocks = _blocks(ds, figure_files)
    if trials:
        blocks += _trial_blocks(trials, figure_files)
    marker = f"<!-- {generator('report')} -->\n"
    md_path = out.write("report.md", "report", text_writer(marker + _md(blocks)))
    page = _html(blocks).replace("<html", marker + "<html", 1)
    html_path = out.write("report.html", "report", text_writer(page))
    return md_path, html_path


def _trial_blocks(trials: dict[str, xr.Dataset], figure_files: dict[str, str]) -> list[_Block]:
    """Return the report section on the criterion: table, reasons read off the data, maps."""
    from .trial import trial_rows

    blocks: list[_Block] = [
        _Heading(2, "The criterion on trial"),
        _Para(
            "For each law, a grid of one parameter and of nu: the attractor reached from rest "
            "(the stick-slip orbit where the slip from breakaway stops, otherwise the stable "
            "pure-slip orbit continued from the Hopf point, otherwise steady sliding) and its "
            "amplitude; the criterion reads the sign of d log(amplitude)/d log(nu) (centred "
            "differences; points next to a change of regime are not judged) as stick-slip "
            "(rising) or pure slip (falling). 'slip-reversal' is an oscillation that never "
            "sticks but whose velocity changes sign (backward slip without a stop): the "
            "criterion is right there if it says 'no stick'. Data: criterion_*.nc."
        ),
        _Table(("map", "regime reached", "points judged", "right", "wrong"), tuple(trial_rows(trials))),
    ]
    reasons = []
    for tr in trials.values():
        param = next(d for d in tr.right.dims if d != "nu")
        wrong = tr.right.values == 0
        obs = tr.observed.values
        ss_wrong = wrong & (obs == 0)
        rev_wrong = wrong & (obs == 3)
        title = str(tr.attrs["title"])
        if ss_wrong.any():
            rows = np.flatnonzero(ss_wrong.any(axis=1))
            vals = tr[param].values[rows]
            # where, within each row's stick-slip range, the wrong points sit (0 = bottom, 1 = top)
            pos = []
            for i in rows:
                nu_ss = tr.nu.values[obs[i] == 0]
                for nu in tr.nu.values[ss_wrong[i]]:
                    pos.append(
                        (np.log(nu) - np.log(nu_ss.min())) / max(np.log(nu_ss.max() / nu_ss.min()), 1e-300)
                    )
            reasons.append(
                f"{title}: stick-slip misread as pure slip at {int(ss_wrong.sum())} points, for "
                f"{param} from {vals.min():.3g} to {vals.max():.3g}, in the top part of the stick-slip "
                f"range (median position {np.median(pos):.2f} of its log-width). There the stick-slip "
                "cycle is close to the grazing pure-slip orbit it turns into at the border, and its "
                "amplitude follows that orbit's, which falls with nu: the amplitude peaks inside the "
                "stick-slip range."
            )
        if rev_wrong.any():
            nus = tr.nu.values[np.flatnonzero(rev_wrong.any(axis=0))]
            slopes = tr.slope.values[rev_wrong]
            reasons.append(
                f"{title}: {int(rev_wrong.sum())} point(s) with slip reversal (nu from {nus.min():.3g} to "
                f"{nus.max():.3g}) read as stick-slip: the block never sticks, yet the amplitude grows "
                f"with nu (d log A / d log nu from {slopes.min():.2f} to {slopes.max():.2f}). The "
                "criterion assumes the only non-sticking oscillation is the small pure-slip cycle "
                "near a Hopf point."
            )
        if not wrong.any():
            reasons.append(f"{title}: the criterion is right wherever it is judged.")
    blocks.append(_Bullets(tuple(reasons)))
    for key, tr in trials.items():
        for kind, what in (
            ("regimes", "regimes"),
            ("criterion", "where the criterion is right (green) or wrong (red)"),
        ):
            name = f"{kind}_{key}"
            if name in figure_files:
                blocks.append(_Figure(figure_files[name], f"{tr.attrs['title']}: {what}."))
    return blocks
