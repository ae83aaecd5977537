#!/usr/bin/env bash
# On a lent GPU machine (the workplace's `device` tool, carry [".whl"]): install the wheels of
# tools/device_wheels.sh, name the device and the versions, run benchmarks/bench_gpu.py and the
# tests of tests/test_cuda.py that a real GPU runs (the simulator's run in CI), each stage under
# its own time limit, everything teed into $OUT.
#
#   bash tools/gpu_run.sh [all|bench|tests] [bench_gpu.py arguments]
#
# 'all' (the default) runs both stages in one call (bench 300 s, tests 270 s: the device
# tool's 600 s a call); 'bench' alone gives the benchmark 560 s (its launch variants compile
# the kernel again, some 5-15 s each), and 'tests' the tests 560 s, as two calls on the
# machine while it stays warm.
set -uo pipefail
stage=all
case "${1:-}" in all|bench|tests) stage=$1; shift ;; esac
cd "$(dirname "$0")/.."
OUT=${OUT:-/tmp/gpu_out}
mkdir -p "$OUT"
python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl || exit 1
export PYTHONPATH=/tmp/site:$PWD/src:$PWD/benchmarks PYTHONUNBUFFERED=1 NUMBA_CACHE_DIR=/tmp/numba_cache
{
  nvidia-smi --query-gpu=name,memory.total,driver_version,clocks.max.sm --format=csv
  python3 -c "import numpy, numba, scipy, xarray, pint; print('numpy', numpy.__version__, 'numba', numba.__version__, 'scipy', scipy.__version__, 'xarray', xarray.__version__, 'pint', pint.__version__)"
  if ! python3 -c "import numba_cuda; from numba import cuda; print('numba-cuda', numba_cuda.__version__, 'usable', cuda.is_available())"; then
    echo "the image's numba-cuda does not import: the carried 0.30.4"
    python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/alt/*.whl
    python3 -c "import numba_cuda; from numba import cuda; print('numba-cuda', numba_cuda.__version__, 'usable', cuda.is_available())"
  fi
  python3 -c "from stickslip.core import cuda; print('stickslip cuda_status', cuda.cuda_status())"
} 2>&1 | tee "$OUT/env.txt"
if [ "$stage" != tests ]; then
  timeout "$([ "$stage" = bench ] && echo 560 || echo 300)" python3 benchmarks/bench_gpu.py "$@" 2>&1 | tee "$OUT/bench_gpu.txt"
fi
[ "$stage" = bench ] && exit 0
timeout "$([ "$stage" = tests ] && echo 560 || echo 270)" python3 -m pytest -p no:cacheprovider -q -rs tests/test_cuda.py -k "not simulator and not rows_and_statuses and not streams and not too_long and not stopped_half_way and not frees_its_workers and not held_once and not fields_kept and not any_order and not persistent" 2>&1 | tee "$OUT/test_cuda.txt"
