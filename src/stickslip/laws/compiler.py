"""Compiled kernels for laws declared by formula or table: generated once, cached on disk.

The engine (:mod:`stickslip.core.engine`, :mod:`stickslip.core.variational`) reaches
its friction law through the functions of :mod:`stickslip.core.laws`. For a law
without a hand-tuned kernel there, this module writes a module of the same
functions from the law's formula (numba code printed by sympy), copies the
engine's modules beside it into a package of its own, imports that package and
returns its :class:`~stickslip.core.api.Kernel`. The engine is thus compiled with
the law inlined: the same exact stick, the same events, no smoothing, and the
speed of a built-in law.

The package's name is the SHA-256 of everything in it (the law module, the
engine's sources, the numba and Python versions), so a cached package can never
be stale; numba caches its machine code beside it. The folder is
``$STICKSLIP_CACHE_DIR`` or ``~/.cache/stickslip/kernels``. The first use of a
law compiles the engine for it (about 20 s on 2 cores); later runs load it.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import importlib
import importlib.util
import os
import shutil
import sys
import tempfile
import threading
from collections.abc import Iterator, Sequence
from pathlib import Path

import numba
import numpy as np
import sympy as sp
from sympy.printing.pycode import PythonCodePrinter

from ..core.api import Kernel

__all__ = [
    "SLOW_NOTICE_S",
    "builtin_kernel",
    "builtin_module_source",
    "cache_dir",
    "compile_kernel",
    "law_module_source",
    "piecewise_module_source",
    "slow_notice",
]

#: the engine's modules copied into each law's package (the law module is generated)
ENGINE_MODULES = (
    "_dop853_tableau.py",
    "_dop853_unrolled.py",
    "dop853.py",
    "engine.py",
    "variational.py",
    "chain.py",
)

_LOCK = threading.Lock()
_LOADED: dict[str, Kernel] = {}


#: seconds a law's preparation runs before a terminal is told about it
SLOW_NOTICE_S = 2.0


@contextlib.contextmanager
def slow_notice(message: str, after: float = SLOW_NOTICE_S) -> Iterator[None]:
    """Print ``stickslip: message`` on a terminal's stderr if the block runs longer than ``after`` s.

    A pipe, a log or a parsed output stays the command's own; nothing is printed for a
    block that ends in time.
    """
    if not sys.stderr.isatty():
        yield
        return
    timer = threading.Timer(after, lambda: print(f"stickslip: {message}", file=sys.stderr, flush=True))
    timer.daemon = True
    timer.start()
    try:
        yield
    finally:
        timer.cancel()


def cache_dir() -> Path:
    """Return the folder of the generated kernels (created when missing)."""
    root = os.environ.get("STICKSLIP_CACHE_DIR")
    base = (
        Path(root) if root else Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "stickslip"
    )
    path = base / "kernels"
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError:  # a read-only home: the temporary folder still works
        path = (
            Path(tempfile.gettempdir()) / f"stickslip-kernels-{os.getuid() if hasattr(os, 'getuid') else 0}"
        )
        path.mkdir(parents=True, exist_ok=True)
    return path


class _Printer(PythonCodePrinter):
    """Python code for numba: floats printed exactly, math functions qualified."""

    def _print_Float(self, expr: sp.Float) -> str:
        return repr(float(expr))

    def _print_Rational(self, expr: sp.Rational) -> str:
        return repr(float(expr))

    def _print_Integer(self, expr: sp.Integer) -> str:
        return f"{int(expr)}.0"

    def _print_Pow(self, expr: sp.Pow, rational: bool = False) -> str:
        b, e = expr.as_base_exp()
        if e.is_Integer and 2 <= int(e) <= 4:
            base = self.parenthesize(b, 1000)
            return "(" + "*".join([base] * int(e)) + ")"
        if e == -1:
            return f"(1.0/{self.parenthesize(b, 1000)})"
        if e.is_Integer:
            return f"{self.parenthesize(b, 1000)}**{int(e)}"
        return super()._print_Pow(expr, rational=rational)


def _code(expr: sp.Expr, symbols: Sequence[sp.Symbol]) -> str:
    """Python code of ``expr`` with the parameters renamed ``P[i]`` and ``w``."""
    sub = {s: sp.Symbol(f"_p{i}", real=True) for i, s in enumerate(symbols)}
    text = _Printer({"fully_qualified_modules": True, "standard": "python3"}).doprint(expr.subs(sub))
    for i in range(len(symbols)):
        text = text.replace(f"_p{i}", f"P[{i}]")
    return text


#: a formula printed longer than this is printed as one line per distinct part (:func:`_lines`)
INLINE_CHARS = 20_000


def _lines(
    exprs: Sequence[sp.Expr], symbols: Sequence[sp.Symbol], indent: str
) -> tuple[list[str], list[str]]:
    """Lines of temporaries, one per distinct part of ``exprs``, and the code of each after them.

    A derivative repeats its formula's parts (the chain rule) and a Taylor coefficient
    its arguments' coefficients: printed as trees, they grow exponentially with the
    nesting, while their distinct parts (shared subtrees, once each) grow as the formula
    does. The parts are walked without recursion, so a formula as deep as the parser
    allows prints.
    """
    names = {s: f"P[{i}]" for i, s in enumerate(symbols)}
    names[sp.Symbol("w", real=True)] = "w"
    printer = _Printer({"fully_qualified_modules": True, "standard": "python3"})
    code: dict[int, str] = {}
    lines: list[str] = []
    stack: list[tuple[sp.Basic, bool]] = [(e, False) for e in exprs]
    while stack:
        node, ready = stack.pop()
        if id(node) in code:
            continue
        if node.is_Symbol:
            code[id(node)] = names[node]
            continue
        if node.is_Number or node.is_NumberSymbol:
            text = printer.doprint(sp.Float(node, 17) if node.is_NumberSymbol else node)
            code[id(node)] = f"({text})" if text.startswith("-") else text
            continue
        if not ready:
            stack.append((node, True))
            stack.extend((a, False) for a in node.args if id(a) not in code)
            continue
        args = [code[id(a)] for a in node.args]
        if isinstance(node, sp.Add):
            text = " + ".join(args)
        elif isinstance(node, sp.Mul):
            text = "*".join(args)
        elif isinstance(node, sp.Pow):
            e = node.args[1]
            if e.is_Integer and 2 <= int(e) <= 4:
                text = "*".join([args[0]] * int(e))
            elif e == -1:
                text = f"1.0/{args[0]}"
            else:
                text = f"{args[0]}**{args[1]}"
        else:  # a function: printed with its arguments as the temporaries' names
            dummies = [sp.Symbol(a, real=True) for a in args]
            text = printer.doprint(node.func(*dummies))
        name = f"_t{len(lines)}"
        lines.append(f"{indent}{name} = {text}")
        code[id(node)] = name
    return lines, [code[id(e)] for e in exprs]


def _printed(expr: sp.Expr, symbols: Sequence[sp.Symbol], indent: str) -> tuple[list[str], str]:
    """Return the code of ``expr``: one expression, or lines of its parts where that is long."""
    text = _code(expr, symbols) if expr.count_ops() < INLINE_CHARS // 10 else ""
    if text and len(text) <= INLINE_CHARS:
        return [], text
    lines, (value,) = _lines([expr], symbols, indent)
    return lines, value


def _function(name: str, expr: sp.Expr, negative: Sequence[sp.Expr], symbols: Sequence[sp.Symbol]) -> str:
    """Return a kernel function: ``expr`` for ``w >= 0``, the polynomial ``negative`` below."""
    lines, value = _printed(expr, symbols, " " * 8)
    body = "\n".join([*lines, f"        return {value}"])
    cont, coefficients = _lines(negative, symbols, " " * 4)
    horner = coefficients[-1]
    for c in reversed(coefficients[:-1]):
        horner = f"({horner})*w + {c}"
    tail = "\n".join([*cont, f"    return {horner}"])
    return f"""

@njit(cache=True)
def {name}(law, P, w):
    if w >= 0.0:
{body}
{tail}
"""


_HEADER = '''"""Kernel of the friction law {name!r} (generated by stickslip.laws.compiler; do not edit).

f_+(w) = {formula}
"""

import math

import numpy as np
from numba import njit

N_LAW_PARAMS = 8
STATIC_THRESHOLD = 1.0
BUILTIN_LAWS = ()
'''

_PARAMS = """

@njit(cache=True, inline="always")
def params(lp):
    return (lp[0], lp[1], lp[2], lp[3], lp[4], lp[5], lp[6], lp[7])
"""

#: a slip phase's friction and acceleration from ``f_plus`` (the odd extension for ``d = -1``)
_GENERIC = """

@njit(cache=True)
def friction_scalar(law, P, d, w):
    return d * f_plus(law, P, d * w)


@njit(cache=True)
def slip_accel(law, P, d, s, w):
    return s - d * f_plus(law, P, d * w)
"""
_COMMON = _PARAMS + _GENERIC


def law_module_source(
    expr: sp.Expr,
    dexpr: sp.Expr,
    continuation: Sequence[sp.Expr],
    symbols: Sequence[sp.Symbol],
    name: str,
) -> str:
    """Return the numba module of a law given by formulas (for ``w >= 0``) and its continuation.

    ``continuation`` holds the coefficients of the Taylor polynomial at 0 that
    continues the law to ``w < 0``, lowest degree first.
    """
    slope = [sp.Mul(k, c, evaluate=False) for k, c in enumerate(continuation)][1:] or [sp.Integer(0)]
    body = _function("f_plus", expr, list(continuation), symbols) + _function(
        "df_plus", dexpr, slope, symbols
    )
    return _HEADER.format(name=name, formula=sp.sstr(expr)) + _COMMON + body


def _array(values: np.ndarray) -> str:
    return "np.array([" + ", ".join(repr(float(x)) for x in np.ravel(values)) + "])"


def piecewise_module_source(breaks: np.ndarray, coefs: np.ndarray, name: str, formula: str) -> str:
    """Return the numba module of a law tabulated as a piecewise cubic in the physical velocity.

    ``f_+(w) = mu(w / P[0]) / P[1]`` with ``P[0] = beta`` (s/m) and ``P[1] = mu_s``;
    ``mu`` is the cubic ``coefs[:, i]`` (highest power first, local variable ``v - breaks[i]``)
    on ``[breaks[i], breaks[i+1]]``, the first piece below ``breaks[0]`` (a polynomial: the
    continuation to ``w < 0``) and a straight line with the end slope above the last.

    The pieces are one array, a row of five numbers (the break and the four coefficients)
    each, read by one function (``_piece``): compiled for a GPU, a module's array goes to
    its constant memory (64 KB), once for each function that reads it, and each name read
    (five arrays read by ``f_plus`` and ``df_plus`` each held eleven copies of its rows:
    88 bytes a row, so 700 rows at most; one array read in one place holds 40).
    """
    n = coefs.shape[1]
    last = breaks[-1] - breaks[-2]
    c = coefs[:, -1]
    mu_end = ((c[0] * last + c[1]) * last + c[2]) * last + c[3]
    slope_end = (3.0 * c[0] * last + 2.0 * c[1]) * last + c[2]
    table = np.column_stack([np.asarray(breaks, dtype=float)[:n], *np.asarray(coefs, dtype=float)])
    body = f"""
# each row: the piece's break and its coefficients of (v - break)**3, **2, **1, **0
_TABLE = {_array(table)}
_N = {n}
_V_END = {float(breaks[-1])!r}
_MU_END = {float(mu_end)!r}
_SLOPE_END = {float(slope_end)!r}


@njit(cache=True)
def _piece(v):
    t = _TABLE
    lo = 0
    hi = _N - 1
    while lo < hi:
        mid = (lo + hi + 1) // 2
        if t[5 * mid] <= v:
            lo = mid
        else:
            hi = mid - 1
    j = 5 * lo
    return v - t[j], t[j + 1], t[j + 2], t[j + 3], t[j + 4]


@njit(cache=True)
def f_plus(law, P, w):
    v = w / P[0]
    if v >= _V_END:
        return (_MU_END + _SLOPE_END * (v - _V_END)) / P[1]
    x, c3, c2, c1, c0 = _piece(v)
    return (((c3 * x + c2) * x + c1) * x + c0) / P[1]


@njit(cache=True)
def df_plus(law, P, w):
    v = w / P[0]
    if v >= _V_END:
        return _SLOPE_END / (P[0] * P[1])
    x, c3, c2, c1, _c0 = _piece(v)
    return ((3.0 * c3 * x + 2.0 * c2) * x + c1) / (P[0] * P[1])
"""
    return _HEADER.format(name=name, formula=formula) + _COMMON + body


def builtin_module_source(law_id: int) -> str:
    """Return the law module of a built-in law's own engine: its functions of :mod:`stickslip.core.laws`.

    The module imports the law's hand-written functions from :mod:`stickslip.core.laws`
    under the names the engine calls, so the engine compiled with it holds this law
    only (no switch over the four laws): it compiles in less time, and the code is the
    same as the built-in engine's for this law, so are its results, bit for bit.
    """
    from ..core import laws

    prefix = laws.LAW_PREFIX[law_id]
    names = {"f_plus": f"{prefix}_f", "df_plus": f"{prefix}_df"}
    if law_id == laws.LAW_WEAKENING:
        names.update(friction_scalar=f"{prefix}_friction", slip_accel=f"{prefix}_accel")
    imports = "\n".join(f"from stickslip.core.laws import {src} as {dst}" for dst, src in names.items())
    head = (
        f'"""Kernel of the built-in friction law {prefix!r} (generated by stickslip.laws.compiler; '
        'do not edit)."""\n\n'
        + ("" if law_id == laws.LAW_WEAKENING else "from numba import njit\n\n")
        + "from stickslip.core.laws import N_LAW_PARAMS, STATIC_THRESHOLD, params\n"
        f"{imports}\n\n"
        "BUILTIN_LAWS = ()\n"
        "__all__ = ['N_LAW_PARAMS', 'STATIC_THRESHOLD', 'params', "
        "'f_plus', 'df_plus', 'friction_scalar', 'slip_accel']\n"
    )
    if law_id == laws.LAW_WEAKENING:
        return head
    return head + _GENERIC


@functools.cache
def builtin_kernel(law_id: int, name: str) -> Kernel:
    """Return the engine of a built-in law compiled with that law alone (see :func:`compile_kernel`)."""
    return compile_kernel(builtin_module_source(law_id), name, law_id=law_id, check=False)


@functools.cache
def _engine_sources() -> tuple[dict[str, str], str]:
    """Return the engine's modules (copied into each package) and ``core/laws.py`` (hashed), read once."""
    core = Path(__file__).resolve().parent.parent / "core"
    sources = {m: (core / m).read_text(encoding="utf-8") for m in ENGINE_MODULES}
    return sources, (core / "laws.py").read_text(encoding="utf-8")


def compile_kernel(law_source: str, name: str, law_id: int = 0, *, check: bool = True) -> Kernel:
    """Return the kernel of a law module: its engine package, written and imported once.

    ``law_id`` is passed to the engine's functions, which the law module may ignore
    (a formula or table law) or not (a built-in law's module importing the functions
    of :mod:`stickslip.core.laws`, whose source is then part of the package's name).
    ``check`` compiles the law's functions first, so that a formula numba cannot
    compile fails with a clear message (not needed for a built-in law).

    Raises
    ------
    ValueError
        When numba cannot compile the law's functions (a formula numba does not support).

    """
    engine_src, core_laws = _engine_sources()
    digest = hashlib.sha256()
    for part in (law_source, *engine_src.values(), core_laws, numba.__version__, sys.version):
        digest.update(part.encode())
    key = digest.hexdigest()[:24]
    with _LOCK:
        if key in _LOADED:
            return _LOADED[key]
        folder = cache_dir() / f"k{key}"
        if not (folder / "__init__.py").exists():
            tmp = Path(tempfile.mkdtemp(prefix=f".k{key}-", dir=folder.parent))
            try:
                for m, text in engine_src.items():
                    (tmp / m).write_text(text, encoding="utf-8")
                (tmp / "laws.py").write_text(law_source, encoding="utf-8")
                (tmp / "__init__.py").write_text(f'"""Engine compiled for the friction law {name!r}."""\n')
                try:
                    os.rename(tmp, folder)
                except OSError:  # another process was first: its copy is the same
                    shutil.rmtree(tmp, ignore_errors=True)
            except BaseException:
                shutil.rmtree(tmp, ignore_errors=True)
                raise
        pkg = f"stickslip_kernel_{key}"
        if pkg not in sys.modules:
            spec = importlib.util.spec_from_file_location(
                pkg, folder / "__init__.py", submodule_search_locations=[str(folder)]
            )
            assert spec is not None and spec.loader is not None
            module = importlib.util.module_from_spec(spec)
            sys.modules[pkg] = module
            spec.loader.exec_module(module)
        if sys.stderr.isatty() and not any((folder / "__pycache__").glob("engine.*.nbi")):
            # numba compiles the engine at its first call, for 10 to 30 s with nothing to show:
            # say so once, on a terminal's stderr (a pipe, a log or a parsed JSON output stays
            # the command's own)
            print(
                f"stickslip: compiling the engine for the friction law {name!r} once "
                f"(10 to 30 s on two cores); cached afterwards in {folder}",
                file=sys.stderr,
                flush=True,
            )
        laws = importlib.import_module(f"{pkg}.laws")
        # compile the law's own functions now: a formula numba cannot compile fails here, clearly;
        # each on its own, so that a probe that lands on a pole does not skip the next one's typing
        probes = ((laws.f_plus, 0.5), (laws.df_plus, 0.5), (laws.f_plus, -1e-3)) if check else ()
        for fn, w in probes:
            try:
                fn(law_id, (0.5,) * 8, w)
            except ArithmeticError:  # compiled, and the probe landed on a pole (1/(w - 0.5)): the
                pass  # law's check tells a pole the block can reach; compiling is what is asked here
            except Exception as exc:  # numba's TypingError and friends
                first = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
                raise ValueError(f"law {name!r}: numba cannot compile its formula ({first})") from None
        kernel = Kernel(
            int(law_id),
            importlib.import_module(f"{pkg}.engine"),
            importlib.import_module(f"{pkg}.variational"),
            name,
            importlib.import_module(f"{pkg}.chain"),
        )
        _LOADED[key] = kernel
        return kernel
