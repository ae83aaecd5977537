"""Figures and numbers of docs/chain.md: the Kraków three-block scan and a Carlson-Langer catalogue.

python tools/chain_figures.py krakow            # docs/images/krakow_lyapunov.png and the table
python tools/chain_figures.py cl CATALOG.nc[,MORE.nc] [NAME] # docs/images/NAME.png (default
                                      # cl_magnitude_frequency and cl_space_time), b; several
                                      # catalogues (independent chains) are pooled
python tools/chain_figures.py cl-run CATALOG.nc [SEED [EVENTS]] # the catalogue (seed 1, 10^5 events),
                                      # started or resumed
python tools/chain_figures.py bootstrap [MEMBERS]  # the b-value's bootstrap errors against the spread
                                      # over MEMBERS (40) chains of 300 blocks (10 min on 2 cores)
python tools/chain_figures.py range-vs-size  # the default range and b on the first n events of two
                                      # catalogues, with and without the slope test (2 min)
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import xarray as xr

from stickslip.chains import (
    ChainParameters,
    b_value,
    chain,
    completeness_magnitude,
    open_catalog,
    power_law_range,
)
from stickslip.chains.lyapunov import lyapunov_exponent
from stickslip.laws import CarlsonLangerLaw, WeakeningLaw
from stickslip.plots.chains import plot_lyapunov, plot_magnitude_frequency, plot_space_time

IMAGES = Path(__file__).resolve().parent.parent / "docs" / "images"


def krakow() -> None:
    cs = [0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.45, 0.5, 0.55, 0.6, 0.7, 0.8, 1.0, 1.5, 2.0, 3.0]
    lam, err, gap = [], [], []
    print("| c | largest Lyapunov exponent (per event) | outer blocks' gap |u_1 - u_3| |")
    print("|---|---|---|")
    for c in cs:
        p = ChainParameters(3, WeakeningLaw(c=c), 0.01, 1.0)
        r = lyapunov_exponent(p, [0.0, 0.3, 0.1], events=400, transient=300)
        lam.append(r.exponent)
        err.append(r.error)
        gap.append(r.lateral_gap)
        shown = "no event end (the chain slides)" if not r.defined else f"{r.exponent:+.3f} ± {r.error:.3f}"
        print(f"| {c:g} | {shown} | {r.lateral_gap:.2e} |")
    fig = plot_lyapunov(cs, lam, err, gap, label="c (F1, three blocks, nu = 0.01, ell = 1)")
    IMAGES.mkdir(exist_ok=True)
    fig.savefig(IMAGES / "krakow_lyapunov.png", dpi=110)


def cl(paths: str, name: str = "cl_magnitude_frequency") -> None:
    names = paths.split(",")
    cats = [open_catalog(p) for p in names]
    for p, c in zip(names, cats, strict=True):
        seed = json.loads(c.attrs["setup"])["seed"]
        one = b_value(c["magnitude"].values, mc=-2.0, m_max=0.0, block="auto")
        t0 = c["t_start"].values
        print(
            f"{p}: {c.sizes['event']} events, seed {seed}, t = {float(c['t_end'][-1]):.4g}, "
            f"recurrence {np.mean(np.diff(t0)):.4g}, b = {one.b:.3f} ± {one.error:.3f} "
            f"(blocks of {one.block}) over [-2, 0] "
            f"({one.n} events), whole chain {np.mean(c['n_blocks'].values == c.attrs['blocks']):.1%}"
        )
    pooled = [c.drop_dims(["recorded_event", "block"], errors="ignore") for c in cats]
    cat = cats[0] if len(cats) == 1 else xr.concat(pooled, "event", combine_attrs="drop_conflicts")
    m = cat["magnitude"].values
    mc = completeness_magnitude(m)
    print(f"events {m.size}, blocks {cat.attrs['blocks']}, Mc (max. curvature) {mc:.2f}")
    for top in (None, -1.0, 0.0):
        f = b_value(m, mc=mc, m_max=top, block="auto")
        print(
            f"b = {f.b:.3f} ± {f.error:.3f} (Shi-Bolt {f.shi_bolt:.3f}) over [{mc:.2f}, {top}] {f.n} events"
        )
    # the power law proper: above the plateau of one- and few-block events (M < -2), below the bump
    small = b_value(m, mc=-2.0, m_max=0.0, block="auto")
    print(
        f"b = {small.b:.3f} ± {small.error:.3f} (blocks of {small.block}) over [-2, 0] "
        f"{small.n} events (KS {small.ks:.2f})"
    )
    auto = b_value(m, mc="auto", block="auto")
    print(
        f"b = {auto.b:.3f} ± {auto.error:.3f} over the power-law range [{auto.mc:.2f}, {auto.m_max:.2f}] "
        f"{auto.n} events (KS {auto.ks:.2f}; stickslip chain's default)"
    )
    nb = cat["n_blocks"].values
    print(f"over 100 blocks: {np.mean(nb > 100):.3%}; of all blocks: {np.mean(nb == nb.max()):.3%}")
    fig = plot_magnitude_frequency(cat, auto)
    IMAGES.mkdir(exist_ok=True)
    fig.savefig(IMAGES / f"{name}.png", dpi=110)
    if name == "cl_magnitude_frequency":
        plot_space_time(cats[0]).savefig(IMAGES / "cl_space_time.png", dpi=90)


def cl_run(path: str, seed: str = "1", events: str = "100000") -> None:
    """Carlson and Langer's set on 1000 blocks: 10^5 events after 2000 of transient (hours on one core).

    Another seed gives an independent chain (its own random start): ``cl`` pools their catalogues.
    """
    p = ChainParameters(blocks=1000, law=CarlsonLangerLaw(alpha=2.5, sigma=0.01), nu=0.01, ell=10.0)
    kw = {"transient": 2000, "record_slip": 3000, "seed": int(seed), "progress": True}
    r = chain(p, int(events), out=path, resume=Path(path).exists(), **kw)
    print(r.summary())


def _bootstrap_member(seed: int) -> dict[str, list[float]]:
    p = ChainParameters(blocks=300, law=CarlsonLangerLaw(alpha=2.5, sigma=0.01), nu=0.01, ell=10.0)
    m = chain(p, 20000, transient=2000, seed=seed, progress=False).catalog["magnitude"].values
    out = {}
    for name, top in (("[-3, 0]", 0.0), ("[-3, top] (the bump in)", None)):
        one = b_value(m, mc=-3.0, m_max=top)
        blocks = b_value(m, mc=-3.0, m_max=top, block="auto")
        out[name] = [one.b, one.error, blocks.error, blocks.block]
    return out


def bootstrap(members: str = "40") -> None:
    """Each chain's bootstrap errors (event by event, and in blocks) against the spread of b over chains."""
    from multiprocessing import Pool

    with Pool(2) as pool:
        rows = pool.map(_bootstrap_member, range(1, int(members) + 1))
    for name in rows[0]:
        a = np.array([r[name] for r in rows])
        spread = float(np.std(a[:, 0], ddof=1))
        print(
            f"M in {name}: {len(a)} chains, b = {a[:, 0].mean():.4f}, spread {spread:.4f} "
            f"(itself ±{100 / np.sqrt(2 * (len(a) - 1)):.0f} %); mean error event by event "
            f"{a[:, 1].mean():.4f} ({a[:, 1].mean() / spread:.2f} of the spread), in blocks "
            f"{a[:, 2].mean():.4f} ({a[:, 2].mean() / spread:.2f}), blocks of "
            f"{int(a[:, 3].min())}-{int(a[:, 3].max())} events (median {np.median(a[:, 3]):.0f})"
        )


def range_vs_size() -> None:
    """The default range and b on the first n events of two catalogues, with and without the slope test."""
    cl = CarlsonLangerLaw(alpha=2.5, sigma=0.01)
    sets = {
        "1000 blocks, nu = 0.001": (ChainParameters(blocks=1000, law=cl, nu=0.001, ell=10.0), 100000),
        "300 blocks, nu = 0.01": (ChainParameters(blocks=300, law=cl, nu=0.01, ell=10.0), 50000),
    }
    print("| catalogue | events | KS alone: range, b | KS and one slope (default): range, b | halves |")
    print("|---|---|---|---|---|")
    for name, (p, events) in sets.items():
        m = chain(p, events, transient=2000, seed=1, progress=False).catalog["magnitude"].values
        for n in (1000, 3000, 10000, 30000, events):
            x = m[:n]
            lo, hi, _ = power_law_range(x, slope_level=0.0)
            old = b_value(x, mc=lo, m_max=None if np.isinf(hi) else hi, block="auto")
            new = b_value(x, mc="auto", block="auto")
            print(
                f"| {name} | {n} | [{old.mc:.1f}, {old.m_max:.1f}]: {old.b:.3f} ± {old.error:.3f} "
                f"| [{new.mc:.1f}, {new.m_max:.1f}]: {new.b:.3f} ± {new.error:.3f} "
                f"| {new.b_lower:.3f} / {new.b_upper:.3f} (p {new.slope_p:.2g}) |"
            )


if __name__ == "__main__":
    if sys.argv[1] == "krakow":
        krakow()
    elif sys.argv[1] == "cl-run":
        cl_run(*sys.argv[2:5])
    elif sys.argv[1] == "bootstrap":
        bootstrap(*sys.argv[2:3])
    elif sys.argv[1] == "range-vs-size":
        range_vs_size()
    else:
        cl(*sys.argv[2:4])
