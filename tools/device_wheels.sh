#!/usr/bin/env bash
# Wheels for a lent GPU machine (the `device` tool), which reaches no package index.
#
# Its image holds numpy, scipy, numba, numba-cuda, xarray, pandas, matplotlib, sympy,
# click, tqdm, JAX and diffrax (the device's KINDS.md); stickslip's other dependencies
# are downloaded here, at the versions of this checkout's .venv, as CPython 3.12 x86-64
# wheels (the image's python3) into .whl/ (ignored by git), 24 MB, and numba-cuda 0.30.4
# into .whl/alt/ (installed there only if the image's own does not import). Then, on the
# device, with carry [".whl"]:
#
#   bash tools/gpu_run.sh
#
# which installs them, names the device and the versions, and runs benchmarks/bench_gpu.py
# and the real-GPU tests of tests/test_cuda.py into $OUT (2026-11-25 on an H100: about 5
# minutes; the machine's start takes 20-60 s more). The image's numpy was 2.5.2 and its
# numba-cuda 0.30.4, which stickslip.core.cuda makes work with it (np.row_stack).
#
# Run: bash tools/device_wheels.sh
set -euo pipefail
cd "$(dirname "$0")/.."
PY=.venv/bin/python
NAMES="pint flexcache flexparser platformdirs netCDF4 cftime zarr numcodecs donfig google-crc32c
dask distributed tornado tblib partd locket zict importlib_metadata lazy-importer"
mkdir -p .whl
for name in $NAMES; do
  version=$("$PY" -c "import importlib.metadata as m; print(m.version('$name'))")
  "$PY" -m pip download -q --no-deps --only-binary=:all: --python-version 3.12 --implementation cp \
    --platform manylinux_2_28_x86_64 --platform manylinux_2_27_x86_64 --platform manylinux_2_17_x86_64 \
    --platform manylinux2014_x86_64 --platform manylinux1_x86_64 -d .whl "$name==$version"
done
mkdir -p .whl/alt
"$PY" -m pip download -q --no-deps --only-binary=:all: --python-version 3.12 --implementation cp \
  --platform manylinux_2_28_x86_64 --platform manylinux_2_24_x86_64 -d .whl/alt "numba-cuda==0.30.4"
du -sh .whl
ls .whl
