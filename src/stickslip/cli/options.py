"""The options that define a parameter set, built from the law registry.

Every registered law's parameters become options (``--c``, ``--alpha``,
``--mu-k``, ...), with help saying which law each belongs to; a law registered
after import (a test's, a plug-in's) gets its options too, because commands
built with :class:`LawCommand` ask the registry when they parse. A user's own
law: ``--law expr --f FORMULA`` (dimensionless), ``--law expr --mu FORMULA``
(physical) with ``--param NAME=VALUE``, or ``--law table --table FILE``.

Parameters are given either dimensionless (``--nu`` and the law's dimensionless
options) or physical (``--v0 --mass --stiffness --load``, ``--mu-s`` and the
law's physical options, values with units such as ``"196 mN"``), or from the
paper's zv set-up (``--preset zv``, each option overridable).
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import click
import numpy as np

from .. import defaults
from ..laws import registry
from ..laws.spec import STATIC, Parameter
from ..laws.table import INTERPOLATIONS
from ..models.parameters import DimensionlessParameters, PhysicalParameters, mass_of_beta
from ..models.presets import PRESETS
from ..units import Q_, parse_quantity, ureg

__all__ = [
    "SETUP",
    "LawCommand",
    "OnceCommand",
    "build_parameters",
    "describe_parameters",
    "law_option_names",
    "opt",
    "out_dir_option",
    "overwrite_option",
    "parse_axis",
    "scale_options",
    "scale_report",
]

#: the set-up's options (physical), besides the law's
SETUP = ("v0", "mass", "stiffness", "load")
#: the options of a user's own law
USER_LAW = ("f", "mu", "static", "param", "table", "interpolation")


def opt(name: str) -> str:
    """Return the option of a parameter name: ``mu_k`` -> ``--mu-k``."""
    return "--" + name.replace("_", "-")


# ----------------------------------------------------------------------------- options from the registry


@dataclass(frozen=True)
class _LawOption:
    name: str
    parameter: Parameter
    kind: str  # "dimensionless" or "physical"
    laws: tuple[str, ...]


def _law_options() -> dict[str, _LawOption]:
    """Every law parameter of the registry, by name (shared names merged, their laws listed)."""
    out: dict[str, _LawOption] = {}
    for entry in registry.entries():
        spec = entry.spec
        for kind, params in (("dimensionless", spec.parameters), ("physical", spec.physical)):
            for p in params:
                have = out.get(p.name)
                if have is not None and have.kind != kind:
                    raise click.ClickException(
                        f"law {spec.name!r}: parameter {p.name!r} is {kind} but {have.kind} in {have.laws}"
                    )
                laws = (*have.laws, spec.name) if have else (spec.name,)
                out[p.name] = _LawOption(p.name, p, kind, laws)
    return out


def law_option_names() -> dict[str, tuple[str, ...]]:
    """Return each law option's laws (for messages and the docs)."""
    return {k: v.laws for k, v in _law_options().items()}


def _static_aliases() -> dict[str, tuple[str, ...]]:
    out: dict[str, tuple[str, ...]] = {}
    for entry in registry.entries():
        for a in entry.spec.static_aliases:
            out[a] = (*out.get(a, ()), entry.spec.name)
    return out


class _LawChoice(click.ParamType):
    """``--law``: a registered law, ``expr`` or ``table`` (checked against the registry when parsing)."""

    name = "law"

    def get_metavar(self, param: click.Parameter, ctx: click.Context | None = None) -> str:
        return "[" + "|".join([*registry.names(), "expr", "table"]) + "]"

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> str:
        choices = [*registry.names(), "expr", "table"]
        if value not in choices:
            self.fail(f"{value!r} is not one of {', '.join(choices)}", param, ctx)
        return str(value)


def _option_decorators(text: bool, default_law: str = "weakening") -> list[Any]:
    """Return the options of a parameter set, from the registry as it is now."""
    num: Any = str if text else float
    laws = _law_options()
    opts: list[Any] = [
        click.option(
            "--law",
            type=_LawChoice(),
            default=default_law,
            show_default=True,
            help="Friction law: a registered law, 'expr' (a formula: --f or --mu) or 'table' (--table FILE).",
        ),
        click.option(
            "--preset",
            type=click.Choice(sorted(PRESETS)),
            default=None,
            help="Physical set-up of the paper's zv experiment (beta = 42 s/m); other options override it.",
        ),
        click.option("--nu", type=num, default=None, help="Dimensionless driving velocity beta*v0."),
    ]
    for o in laws.values():
        p = o.parameter
        owner = "/".join(o.laws)
        if o.kind == "dimensionless":
            opts.append(click.option(opt(p.name), p.name, type=num, default=None, help=f"{owner}: {p.help}."))
        else:
            example = f", e.g. '{p.example}'" if p.example else ""
            typ: Any = str if (p.unit or text) else float
            opts.append(
                click.option(opt(p.name), p.name, type=typ, default=None, help=f"{owner}: {p.help}{example}.")
            )
    opts += [
        click.option("--v0", default=None, help="Driving velocity, e.g. '5 um/s'."),
        click.option("--mass", default=None, help="Mass, e.g. '1 kg'."),
        click.option(
            "--beta", default=None, help="Instead of --mass: beta = sqrt(k m)/(mu_s W), e.g. '42 s/m'."
        ),
        click.option("--stiffness", default=None, help="Spring constant, e.g. '62 N/m'."),
        click.option("--load", default=None, help="Normal load W, e.g. '196 mN'."),
        click.option("--mu-s", "mu_s", type=num, default=None, help=f"Every physical law: {STATIC.help}."),
    ]
    for alias, owners in _static_aliases().items():
        opts.append(
            click.option(
                opt(alias),
                alias,
                type=num,
                default=None,
                help=f"{'/'.join(owners)}: the same as --mu-s (the paper's name).",
            )
        )
    opts += [
        click.option(
            "--f",
            "f",
            default=None,
            help="expr: dimensionless f(w), e.g. '1/(1 + 3.8*w) + 0.5*w' (f(0+) = 1).",
        ),
        click.option(
            "--mu", "mu", default=None, help="expr: physical mu(v), v in m/s, e.g. '0.46/(1 + 160*v)'."
        ),
        click.option(
            "--param",
            "param",
            multiple=True,
            metavar="NAME=VALUE",
            help="expr: a value of the formula's other names, e.g. 'c=3.8' or 'a=160 s/m' (repeatable); "
            "a plain number in a --mu formula is in SI units.",
        ),
        click.option(
            "--static",
            type=float,
            default=None,
            help="expr/table: the static threshold where it differs from f(0+) (a drop at onset of slip).",
        ),
        click.option(
            "--table", default=None, help="table: CSV of 'velocity [unit]' and 'friction coefficient [1]'."
        ),
        click.option(
            "--interpolation",
            type=click.Choice(INTERPOLATIONS),
            default="pchip",
            show_default=True,
            help="table: pchip (monotone, C1), cubic (C2 spline) or smoothing (C2, for noisy tables).",
        ),
        click.option(
            "--rtol",
            type=float,
            default=defaults.RTOL,
            show_default=True,
            help="Relative tolerance of the integration.",
        ),
        click.option(
            "--atol",
            type=float,
            default=defaults.ATOL,
            show_default=True,
            help="Absolute tolerance of the integration.",
        ),
    ]
    return opts


class OnceCommand(click.Command):
    """A command that refuses an option given twice unless it can be repeated.

    click keeps the last of ``--c 3 --c 4`` without a word, and runs a set-up the user
    did not ask for; options that take several values say so (``multiple``).
    """

    def parse_args(self, ctx: click.Context, args: list[str]) -> list[str]:
        """Refuse a repeated single-valued option, by name; then parse as click does."""
        if args and not ctx.resilient_parsing:  # before a missing option is reported
            _, _, order = self.make_parser(ctx).parse_args(args=list(args))
            seen: set[click.Parameter] = set()
            for param in order:
                if param in seen and _single(param):
                    names = "/".join(param.opts + param.secondary_opts)
                    raise click.UsageError(
                        f"option {names} is given more than once; it takes one value: give it once",
                        ctx,
                    )
                seen.add(param)
        return super().parse_args(ctx, args)


def _single(param: click.Parameter) -> bool:
    """Whether a second use of ``param`` would replace the first without a word."""
    if not isinstance(param, click.Option) or param.multiple or param.count:
        return False
    return not param.is_flag or bool(param.secondary_opts)  # a repeated --quiet changes nothing


class LawCommand(OnceCommand):
    """A command whose parameter-set options come from the law registry, at parse time."""

    def __init__(self, *args: Any, text: bool = False, default_law: str = "weakening", **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._text = text
        self._default_law = default_law
        self._built_for = -1
        self._law_params: list[click.Parameter] = []

    def _law_params_now(self) -> list[click.Parameter]:
        if self._built_for != registry.version:

            def holder() -> None:  # pragma: no cover - only collects the options
                return None

            for d in reversed(_option_decorators(self._text, self._default_law)):
                holder = d(holder)
            self._law_params = list(getattr(holder, "__click_params__", []))[::-1]
            self._built_for = registry.version
        return self._law_params

    def get_params(self, ctx: click.Context) -> list[click.Parameter]:
        """Return the command's own options followed by the parameter-set options."""
        own = super().get_params(ctx)
        help_opt = [p for p in own if p.name == "help"]
        rest = [p for p in own if p.name != "help"]
        return rest + self._law_params_now() + help_opt


def law_command(
    group: click.Group | None = None,
    name: str | None = None,
    *,
    text: bool = False,
    default_law: str = "weakening",
) -> Callable[[Callable[..., Any]], click.Command]:
    """Return a decorator that makes a :class:`LawCommand`; ``--law`` defaults to ``default_law``.

    With ``group``, the command is also added to it; without (``law_command()``), the
    command stands alone, importable and invocable, and a group adds it with
    :meth:`click.Group.add_command`. ``text=True`` keeps the parameter-set options as
    text (a sweep's ranges ``'A..B'``).
    """
    if group is None:
        return click.command(name, cls=LawCommand, text=text, default_law=default_law)
    return group.command(name, cls=LawCommand, text=text, default_law=default_law)


class OutPath(click.Path):
    """A path to write to: as :class:`click.Path`, and an empty one is refused.

    click alone reads ``--out ''`` as no option at all (a sweep would write
    ``results/sweep.nc``), ``--store ''`` as the current folder, and ``reproduce --out ''``
    would fail naming no folder.
    """

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> Any:
        if isinstance(value, str) and not value.strip():
            self.fail(f"{value!r} is empty: expected the path of a {self.name}", param, ctx)
        return super().convert(value, param, ctx)


def default_out(command: str) -> str:
    """Return a command's own default output folder, ``results/COMMAND``.

    One folder a command: the README's examples, run one after another, never write
    over each other's files.
    """
    return os.path.join("results", command)


def _own_folder(ctx: click.Context, param: click.Parameter, value: str | None) -> str:
    return value if value is not None else default_out(str(ctx.info_name))


def out_dir_option(help_text: str) -> Any:
    """Return the ``--out`` option (an output folder, default ``results/COMMAND``) of a command."""
    return click.option(
        "--out",
        "out_dir",
        type=OutPath(file_okay=False),
        default=None,
        callback=_own_folder,
        show_default="results/COMMAND",
        help=help_text,
    )


def scale_options(func: Callable[..., Any]) -> Any:
    """Add ``--store``, ``--scheduler``, ``--workers``: a resumable store and a Dask backend."""
    for deco in reversed(
        [
            click.option(
                "--store",
                default=None,
                type=OutPath(dir_okay=True, file_okay=False),
                help="Zarr store (PATH.zarr): results written block by block as they finish; "
                "run the same command again after an interruption and only the missing blocks run.",
            ),
            click.option(
                "--scheduler",
                default=None,
                metavar="ADDRESS",
                callback=_scheduler,
                help="Run on an existing Dask distributed cluster, e.g. tcp://10.0.0.1:8786.",
            ),
            click.option(
                "--workers",
                type=click.IntRange(min=1),
                default=None,
                help="Run on a Dask LocalCluster of this many worker processes.",
            ),
        ]
    ):
        func = deco(func)
    return func


def _scheduler(ctx: click.Context, param: click.Parameter, value: str | None) -> str | None:
    """Check ``--scheduler``'s address before the command starts (and before a store is made)."""
    if value is None:
        return None
    from ..scale.backend import check_scheduler

    try:
        check_scheduler(value)
    except ValueError as exc:
        raise click.BadParameter(str(exc).removeprefix(f"scheduler={value!r}: "), param=param) from None
    return value


def scale_report(ds: Any) -> None:
    """Print (on standard error) what a run with a store did: blocks reused and computed."""
    import json

    run = ds.attrs.get("run")
    if run:
        r = json.loads(run)
        click.echo(
            f"store: {r['blocks']} blocks, {r['reused']} already there, {r['computed']} computed "
            f"({r['points']} points in {r['seconds']:.3g} s, {r['backend']})",
            err=True,
        )


def figure_names(stem: str) -> dict[str, str]:
    """Return the files of a figure saved as ``stem`` (PNG and SVG), for ``OutputFolder.expect``."""
    return {f"{stem}.png": "figure", f"{stem}.svg": "figure"}


def overwrite_option(func: Callable[..., Any]) -> Any:
    """Add ``--overwrite``: replace existing outputs that stickslip did not write."""
    return click.option(
        "--overwrite",
        is_flag=True,
        help="Replace existing output files even if stickslip did not write them.",
    )(func)


def warn_unwritten(flags: Sequence[str], why: str) -> None:
    """Warn that those of ``flags`` (parameter names) given on the command line do nothing.

    ``--overwrite`` and ``--no-plot`` act on files; where a command writes none (no ``--out``),
    they reach nothing, and saying so beats dropping them without a word.
    """
    ctx = click.get_current_context()
    given = [
        "--" + f.replace("_", "-")
        for f in flags
        if ctx.get_parameter_source(f) is click.core.ParameterSource.COMMANDLINE
    ]
    if given:
        click.echo(
            f"warning: {' and '.join(given)} {'does' if len(given) == 1 else 'do'} nothing {why}", err=True
        )


# ----------------------------------------------------------------------------- building a parameter set


def _to_float(name: str, value: Any) -> Any:
    if value is None or isinstance(value, float):
        return value
    if hasattr(value, "magnitude"):  # a quantity from a sweep axis
        return value
    try:
        return float(value)
    except ValueError:
        raise ValueError(f"{name}={value!r}: expected a number") from None


def _require(opts: dict[str, Any], names: Sequence[str], context: str, hint: str = "") -> None:
    missing = [n for n in names if opts.get(n) is None]
    if missing:
        raise click.UsageError(f"{context} needs {', '.join(map(opt, missing))}{hint}")


def params_of(opts: dict[str, Any]) -> dict[str, Any]:
    """Return ``--param NAME=VALUE`` options as a dict (texts; values where a sweep set them)."""
    out: dict[str, Any] = {}
    for item in opts.get("param") or ():
        if isinstance(item, tuple):
            out[item[0]] = item[1]
            continue
        name, sep, value = str(item).partition("=")
        if not sep or not name.strip() or not value.strip():
            raise click.UsageError(f"--param {item!r}: expected NAME=VALUE, e.g. 'c=3.8' or 'a=160 s/m'")
        if name.strip() in out:  # a second value would replace the first silently
            raise click.UsageError(
                f"--param {item!r}: {name.strip()} is already given ({name.strip()}={out[name.strip()]}); "
                "give each parameter once"
            )
        out[name.strip()] = value.strip()
    return out


def _param_value(name: str, text: Any, physical: bool) -> Any:
    if not isinstance(text, str):
        return text  # a value a sweep put there
    try:
        return float(text)
    except ValueError:
        if not physical:
            raise click.UsageError(
                f"--param {name}={text!r}: expected a number (the formula is dimensionless)"
            ) from None
        return text  # a quantity with units, parsed by the law


def build_parameters(
    opts: dict[str, Any], *, default_preset: bool = False
) -> DimensionlessParameters | PhysicalParameters:
    """Build a parameter set from command-line options.

    Raises
    ------
    click.UsageError
        For a missing, conflicting or invalid option.

    """
    law = opts.get("law") or "weakening"
    user = [k for k in USER_LAW if opts.get(k) not in (None, (), "pchip")]
    if law not in ("expr", "table") and user:
        raise click.UsageError(
            f"{', '.join(map(opt, user))} belong{'s' if len(user) == 1 else ''} to --law expr / --law table"
        )
    try:
        if law == "expr":
            return _expression(opts)
        if law == "table":
            return _table(opts)
        return _registered(law, opts, default_preset)
    except click.UsageError:
        raise
    except ValueError as exc:
        raise click.UsageError(f"invalid value: {exc}") from None


def _law_values_given(opts: dict[str, Any]) -> tuple[list[str], list[str]]:
    laws = _law_options()
    dim = ["nu", *(k for k, o in laws.items() if o.kind == "dimensionless")]
    phys = [*SETUP, "beta", "mu_s", *_static_aliases(), *(k for k, o in laws.items() if o.kind == "physical")]
    return [k for k in dim if opts.get(k) is not None], [k for k in phys if opts.get(k) is not None]


def _registered(
    law: str, opts: dict[str, Any], default_preset: bool
) -> DimensionlessParameters | PhysicalParameters:
    entry = registry.get(law)
    spec = entry.spec
    dim_given, phys_given = _law_values_given(opts)
    preset = opts.get("preset")
    if dim_given and (phys_given or preset):
        raise click.UsageError(
            f"options {', '.join(map(opt, dim_given))} are dimensionless and "
            f"{', '.join(map(opt, phys_given)) or '--preset'} physical: give one kind only"
        )
    laws = _law_options()
    own = {p.name for p in (*spec.parameters, *spec.physical)} | {"mu_s", *spec.static_aliases}
    for k in (*dim_given, *phys_given):
        if k in laws and k not in own:
            raise click.UsageError(f"{opt(k)} belongs to --law {'/'.join(laws[k].laws)}, not --law {law}")
        if k in _static_aliases() and k not in spec.static_aliases:
            raise click.UsageError(f"{opt(k)} belongs to --law {'/'.join(_static_aliases()[k])}; use --mu-s")
    if not dim_given and not phys_given and not preset:
        if not default_preset:
            example = " ".join(f"{opt(p.name)} ..." for p in spec.parameters if p.default is None)
            raise click.UsageError(
                "no parameters: give --nu with the law's dimensionless options "
                f"(e.g. --nu 0.01 {example}), or --v0 --mass --stiffness --load with the law's "
                "physical options, or --preset zv"
            )
        preset = "zv"
    if dim_given:
        o = {k: _to_float(k, opts.get(k)) for k in ("nu", *(p.name for p in spec.parameters))}
        _require(o, ("nu",), "a dimensionless set-up")
        _require(o, [p.name for p in spec.parameters if p.default is None], f"--law {law}")
        values = {p.name: o[p.name] for p in spec.parameters if o.get(p.name) is not None}
        return DimensionlessParameters(nu=o["nu"], law=entry.dimensionless(**values))
    o = dict(opts)
    static_name = "mu_s"  # the name the user gave it, for messages
    for alias in spec.static_aliases:
        if o.get(alias) is not None:
            if o.get("mu_s") is not None:
                raise click.UsageError(f"give --mu-s or {opt(alias)}, not both")
            o["mu_s"] = o[alias]
            static_name = alias
    if preset:
        o = PRESETS[preset].fill(o, law)
    # physical options alone (--v0 "20 um/s") are not the zv set-up the command runs with none:
    # say how to take it for the rest
    rest = "" if preset else " (or add --preset zv: the paper's set-up for the options not given)"
    _require(o, ("mu_s",), f"a physical set-up of --law {law}", rest)
    _require(o, [p.name for p in spec.physical if p.default is None], f"--law {law}", rest)
    values = {
        p.name: _to_float(p.name, o[p.name]) if not p.unit else o[p.name]
        for p in spec.physical
        if o.get(p.name) is not None
    }
    plaw = entry.physical(**{static_name: _to_float(static_name, o["mu_s"])}, **values)
    _setup_mass(o, plaw.mu_s)
    _require(o, SETUP, "a physical set-up", rest)
    return PhysicalParameters(mass=o["mass"], stiffness=o["stiffness"], load=o["load"], v0=o["v0"], law=plaw)


def _setup_mass(o: dict[str, Any], mu_s: Any) -> None:
    """Turn ``--beta`` into the mass (with the law's static coefficient)."""
    if o.get("beta") is None:
        return
    if o.get("mass") is not None:
        raise click.UsageError("give --mass or --beta, not both: beta sets the mass")
    _require(o, ("stiffness", "load"), "--beta")
    beta = parse_quantity(o["beta"], "beta", "[time] / [length]", "42 s/m")
    k = parse_quantity(o["stiffness"], "stiffness", "[mass] / [time] ** 2", "62 N/m")
    w = parse_quantity(o["load"], "load", "[force]", "196 mN")
    o["mass"] = Q_(mass_of_beta(o["beta"], beta, k, w, float(mu_s)), "kg")


def _physical_setup(opts: dict[str, Any], what: str) -> dict[str, Any]:
    o = dict(opts)
    if o.get("preset"):
        o = PRESETS[o["preset"]].fill(o)
    dim_given, phys_given = _law_values_given(o)
    # a registered law's options (--a, --mu-s, --mu0, ...) set nothing here: refused, not dropped
    stray = [k for k in dim_given if k != "nu"] + [k for k in phys_given if k not in (*SETUP, "beta")]
    if stray:
        static = any(k == "mu_s" or k in _static_aliases() for k in stray)
        hint = " (the static coefficient is --static)" if static else ""
        raise click.UsageError(f"{', '.join(map(opt, stray))}: not options of {what}{hint}")
    return o


def _expression(opts: dict[str, Any]) -> DimensionlessParameters | PhysicalParameters:
    f, mu = opts.get("f"), opts.get("mu")
    if (f is None) == (mu is None):
        raise click.UsageError(
            "--law expr needs one formula: --f (dimensionless f(w)) or --mu (physical mu(v), v in m/s)"
        )
    for k in ("table",):
        if opts.get(k) is not None:
            raise click.UsageError(f"{opt(k)} belongs to --law table")
    ctx = click.get_current_context(silent=True)
    source = None if ctx is None else ctx.get_parameter_source("interpolation")
    if source is click.core.ParameterSource.COMMANDLINE:
        raise click.UsageError("--interpolation belongs to --law table (a formula is not interpolated)")
    given = params_of(opts)
    static = opts.get("static")
    if f is not None:
        dim_given, phys_given = _law_values_given(opts)
        stray = [k for k in (*dim_given, *phys_given) if k != "nu"]
        if stray or opts.get("preset"):
            raise click.UsageError(
                f"{', '.join(map(opt, stray)) or '--preset'}: "
                "a dimensionless formula (--f) takes --nu and --param only"
            )
        _require(opts, ("nu",), "--f (a dimensionless formula)")
        from ..laws.expression import ExpressionLaw  # sympy: loaded by a formula's command only

        law = ExpressionLaw(f, static=static, **{k: _param_value(k, v, False) for k, v in given.items()})
        return DimensionlessParameters(nu=_to_float("nu", opts["nu"]), law=law)
    o = _physical_setup(opts, "--mu (a physical formula)")
    if o.get("nu") is not None:
        raise click.UsageError("--nu: a physical formula (--mu) takes --v0 --mass --stiffness --load")
    from ..laws.expression import PhysicalExpressionLaw

    plaw = PhysicalExpressionLaw(
        str(mu), static=static, **{k: _param_value(k, v, True) for k, v in given.items()}
    )
    _setup_mass(o, plaw.mu_s)
    _require(o, SETUP, "a physical set-up")
    return PhysicalParameters(mass=o["mass"], stiffness=o["stiffness"], load=o["load"], v0=o["v0"], law=plaw)


def _table(opts: dict[str, Any]) -> PhysicalParameters:
    if opts.get("table") is None:
        raise click.UsageError(
            "--law table needs --table FILE (columns 'velocity [unit]', 'friction coefficient [1]')"
        )
    for k in ("f", "mu"):
        if opts.get(k) is not None:
            raise click.UsageError(f"{opt(k)} belongs to --law expr")
    if opts.get("param"):
        raise click.UsageError("--param belongs to --law expr: a table has no parameters (its points)")
    o = _physical_setup(opts, "--law table (a physical law)")
    if o.get("nu") is not None:
        raise click.UsageError("--nu: a table is physical: give --v0 --mass --stiffness --load")
    from ..laws.table import TabulatedLaw

    plaw = TabulatedLaw.from_csv(
        o["table"], load=o.get("load"), static=o.get("static"), interpolation=o["interpolation"]
    )
    _setup_mass(o, plaw.mu_s)
    _require(o, SETUP, "a physical set-up")
    return PhysicalParameters(mass=o["mass"], stiffness=o["stiffness"], load=o["load"], v0=o["v0"], law=plaw)


def describe_parameters(params: DimensionlessParameters | PhysicalParameters) -> dict[str, Any]:
    """Return a JSON-ready description of a parameter set (with the dimensionless form)."""
    if isinstance(params, DimensionlessParameters):
        return {
            "nu": params.nu,
            "law": params.law.name,
            **params.law.params,
            "description": params.law.describe(),
        }
    d = params.dimensionless()
    law = params.law
    out: dict[str, Any] = {
        "v0": f"{params.v0:~P}",
        "mass": f"{params.mass:~P}",
        "stiffness": f"{params.stiffness:~P}",
        "load": f"{params.load:~P}",
        "law": law.name,
        "mu_s": law.mu_s,
    }
    for k, v in law.params.items():
        out[k] = v if isinstance(v, float) else f"{v:~P}"
    out["description"] = law.describe()
    out["beta"] = f"{params.beta:.6g~P}"
    out["dimensionless"] = {"nu": d.nu, "law": d.law.name, **d.law.params}
    return out


# ----------------------------------------------------------------------------- sweep axes


def parse_axis(p: Parameter, name: str, text: str, num: int, log: bool) -> Any:
    """Parse a sweep axis of parameter ``p``: a range ``'A..B'`` (``num`` points) or a list ``'A,B,C'``.

    Physical values keep units (``'5 um/s..1000 um/s'``, or ``'5..1000 um/s'``) and come back as
    one quantity array; numbers as a list of floats. The ends of a range are checked against the
    parameter's bounds. Raises ValueError for a malformed axis.
    """
    checked = dataclasses.replace(p, name=name)
    example = p.example or f"1 {p.unit}"
    if ".." in text:
        parts = [t.strip() for t in text.split("..")]
        # 'A...B' splits as 'A', '.B' and would read as A..0.1B, silently: refused
        if len(parts) != 2 or not all(parts) or "..." in text:
            raise ValueError(f"{name}={text!r}: expected a range 'A..B' (two dots)")
        if num < 2:
            raise ValueError(f"--num={num}: a range needs at least 2 points")
        if not p.unit:
            lo, hi = (float(_to_float(name, t)) for t in parts)
            unit = None
        else:
            qhi = parse_quantity(parts[1], name, p.dimension, example, allow_zero=True, allow_negative=True)
            lo_text = parts[0]
            try:
                float(lo_text)
                lo_text = f"{lo_text} {qhi.units:~}"
            except ValueError:
                pass
            for end in (lo_text, parts[1]):
                checked.check(end)
            qlo = parse_quantity(lo_text, name, p.dimension, example, allow_zero=True, allow_negative=True)
            lo, hi, unit = float(qlo.to(qhi.units).magnitude), float(qhi.magnitude), qhi.units
        if log:
            if lo <= 0 or hi <= 0:
                raise ValueError(f"{name}={text!r}: a --log range needs positive ends")
            vals = np.geomspace(lo, hi, num)
        else:
            vals = np.linspace(lo, hi, num)
        return [float(v) for v in vals] if unit is None else Q_(vals, unit)
    items = [t.strip() for t in text.split(",")]
    if not any(items):
        raise ValueError(f"{name}={text!r}: expected values separated by commas")
    if not all(items):  # an empty value ('0.1,,0.2') is a typo: said, not dropped
        i = items.index("")
        raise ValueError(
            f"{name}={text!r}: value {i + 1} of {len(items)} is empty: expected values separated by "
            "single commas, e.g. '0.1,0.2'"
        )
    if not p.unit:
        return [float(_to_float(name, t)) for t in items]
    qs = [parse_quantity(t, name, p.dimension, example, allow_zero=True, allow_negative=True) for t in items]
    unit = qs[0].units
    return Q_(np.array([q.to(unit).magnitude for q in qs]), unit)


def axis_parameter(key: str, text: str) -> Parameter:
    """Return the parameter a sweep axis ``key`` stands for (a formula's: from the values' unit)."""
    from ..dynamics.sweep import NU
    from ..dynamics.sweep import SETUP as SWEEP_SETUP

    if key in SWEEP_SETUP:
        return SWEEP_SETUP[key]
    if key == "nu":
        return NU
    if key == "mu_s" or key in _static_aliases():
        return STATIC
    laws = _law_options()
    if key in laws:
        return laws[key].parameter
    last = text.replace("..", ",").split(",")[-1].strip()
    try:
        float(last)
        return Parameter(key, "parameter of the formula", lower=-np.inf)
    except ValueError:
        try:
            q: Any = ureg.Quantity(last)
        except Exception:  # pint raises several unrelated types
            raise ValueError(f"{key}={text!r}: expected numbers or quantities such as '160 s/m'") from None
        return Parameter(key, "parameter of the formula", unit=f"{q.units:~}", example=last, lower=-np.inf)


def is_axis(value: Any) -> bool:
    """Whether an option's text is a sweep axis (a range or a list)."""
    return isinstance(value, str) and (".." in value or "," in value)


def axis_count(text: str, num: int) -> int:
    """Points of an axis, from its text alone (for the memory check before parsing)."""
    return num if ".." in text else len([c for c in text.split(",") if c.strip()])
