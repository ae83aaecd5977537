"""Example inputs for the README's commands: a friction table, amplitudes, records.

No measured data ship with stickslip; :func:`write_examples` makes, in seconds and
always the same (fixed seeds), the files the README's commands read, from the
paper's "zv" set-up (``zv_parameters``: 231 g on 62 N/m, load 196 mN, law F1 with
mu_s = 0.46 and a = 160 s/m) with the noise of a force sensor:

- ``mu_v.csv``: the friction coefficient of that law at rest and at 24 velocities from
  1 um/s to 100 mm/s, the table a tribometer's velocity sweep gives (``--law table``);
- ``amplitudes.csv``: the model's stick-slip amplitude at 12 driving velocities from
  5 to 1000 um/s with 1 % noise and its error column (``stickslip classify``);
- ``records/``: five force-time records at 50 to 500 um/s, 6 stick-slip periods each
  after the start-up transient, 100 Hz, 0.5 mN of white noise (``stickslip analyze``);
- ``record.csv``: one record at 100 um/s, 8 periods, 200 Hz, 0.5 mN (``stickslip fit``).

Real records of a published experiment (Colas et al., Phys. Rev. E 100, 032803,
2019) are read in the tutorial on laboratory records; they are not shipped.
"""

from __future__ import annotations

import dataclasses
import os
from typing import Any

import numpy as np

from ..io.output import OutputFolder, text_writer
from ..io.records import format_record
from .synthetic import synthetic_record

__all__ = ["EXAMPLE_FILES", "write_examples"]

#: the files and folder :func:`write_examples` writes, with what reads them
EXAMPLE_FILES = {
    "mu_v.csv": "stickslip cycle --law table --table mu_v.csv",
    "amplitudes.csv": "stickslip classify amplitudes.csv",
    "records": "stickslip analyze records",
    "record.csv": "stickslip fit record.csv",
    "README.txt": "what these files are",
}

_RECORD_VELOCITIES = (50, 100, 200, 300, 500)  # um/s


def _csv(header: str, columns: tuple[Any, ...]) -> str:
    rows = "\n".join(",".join(repr(float(v)) for v in row) for row in zip(*columns, strict=True))
    return header + "\n" + rows + "\n"


def _record_text(v0_um_s: float, periods: int, rate: str, seed: int, name: str) -> str:
    from ..dynamics.cycle import cycle
    from ..models.parameters import zv_parameters

    params = zv_parameters(f"{v0_um_s} um/s")
    steady = cycle(params, probe=False)
    rec = synthetic_record(
        params,
        duration=f"{periods * steady.period} s",
        rate=rate,
        noise="0.5 mN",
        seed=seed,
        name=name,
        start=f"{steady.transient_time} s",
    )
    sample = "synthetic: the zv set-up of stickslip's model, 0.5 mN sensor noise"
    return format_record(dataclasses.replace(rec, metadata={**rec.metadata, "sample": sample}))


def write_examples(folder: str | os.PathLike[str], *, overwrite: bool = False) -> list[str]:
    """Write the example inputs into ``folder``; return the paths written.

    The files are those of :data:`EXAMPLE_FILES` (what each is: the module's
    docstring); like every output, they are written atomically and an existing file
    that stickslip did not write is kept unless ``overwrite``.
    """
    from ..dynamics.sweep import sweep
    from ..laws import f1
    from ..models.parameters import zv_parameters
    from ..units import Q_

    law = f1(mu_s=0.46, a="160 s/m")
    v_table = np.r_[0.0, np.geomspace(1e-6, 0.1, 24)]  # the first row: the static coefficient
    mu = 0.46 / (1.0 + law.a.to("s/m").magnitude * v_table)
    v_amp = np.geomspace(5.0, 1000.0, 12)
    ds = sweep(zv_parameters(), {"v0": Q_(v_amp, "um/s")}, progress=False)
    amp = ds.amplitude.values * 1e3  # mN
    rng = np.random.default_rng(54)
    err = 0.01 * amp
    noisy = amp + err * rng.standard_normal(amp.size)
    with OutputFolder(folder, "examples", overwrite=overwrite) as out:
        out.expect(
            {
                "mu_v.csv": "friction-table",
                "amplitudes.csv": "amplitudes",
                "record.csv": "record",
                "README.txt": "examples-readme",
                **{f"records/run_{v:03d}um_s.csv": "record" for v in _RECORD_VELOCITIES},
            }
        )
        paths = [
            out.write(
                "mu_v.csv",
                "friction-table",
                text_writer(
                    "# stickslip friction table: the paper's law F1, mu_s = 0.46, a = 160 s/m (synthetic)\n"
                    + _csv("velocity [um/s],friction coefficient [1]", (v_table * 1e6, mu))
                ),
            ),
            out.write(
                "amplitudes.csv",
                "amplitudes",
                text_writer(
                    "# stickslip amplitudes: stick-slip of the zv set-up (model), 1 % noise (synthetic)\n"
                    + _csv("velocity [um/s],amplitude [mN],amplitude_err [mN]", (v_amp, noisy, err))
                ),
            ),
            out.write(
                "record.csv", "record", text_writer(_record_text(100, 8, "200 Hz", seed=100, name="record"))
            ),
        ]
        for i, v in enumerate(_RECORD_VELOCITIES):
            name = f"records/run_{v:03d}um_s.csv"
            paths.append(
                out.write(name, "record", text_writer(_record_text(v, 6, "100 Hz", seed=i, name=name)))
            )
        paths.append(out.write("README.txt", "examples-readme", text_writer(_readme())))
    return paths


def _readme() -> str:
    doc = __doc__ or ""
    body = doc.split("\n\n", 1)[1]
    return "stickslip's example inputs (stickslip examples DIR)\n\n" + body
