#!/usr/bin/env bash
# Wheels for a lent GPU machine (the `device` tool), which reaches no package index.
#
# Its image holds numpy, scipy, numba, numba-cuda, xarray, pandas, matplotlib, sympy,
# click, tqdm, JAX and diffrax (the device's KINDS.md); stickslip's other dependencies
# are downloaded here, at the versions of this checkout's .venv, as CPython 3.12 x86-64
# wheels (the image's python3) into .whl/ (ignored by git), 24 MB. Then, on the
# device, with carry [".whl"]:
#
#   python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade \
#       --target /tmp/site .whl/*.whl && export PYTHONPATH=/tmp/site:$PWD/src:$PWD/benchmarks || exit;
#   python3 -c "import numpy, numba, numba_cuda; print(numpy.__version__, numba.__version__, numba_cuda.__version__)";
#   PYTHONUNBUFFERED=1 python3 benchmarks/bench_gpu.py 2>&1 | tee $OUT/bench_gpu.txt;
#   python3 -m pytest -p no:cacheprovider -q tests/test_cuda.py 2>&1 | tee $OUT/test_cuda.txt
#
# (The image's numpy is 2.5: should its numba-cuda fail to import with it, carry
# numba-cuda 0.30.x too: NAMES below, one more line.)
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
du -sh .whl
ls .whl
