#!/bin/bash
# Every benchmark of docs/benchmarks.md, one after another (about 15 minutes on 2 cores).
# Run from the repository root with the project installed: bash benchmarks/run_all.sh > out.txt 2>&1
set -x
git log --oneline -1
python benchmarks/bench_cycles.py
NUMBA_NUM_THREADS=1 python benchmarks/bench_cycles.py --n 100000 --n-scipy 100
python benchmarks/bench_step.py
out=$(mktemp -d)
stickslip reproduce --out "$out/warmup" > /dev/null 2>&1
time stickslip reproduce --out "$out/results"
python benchmarks/bench_records.py
NUMBA_NUM_THREADS=1 python benchmarks/bench_motion.py
python benchmarks/bench_orbits.py
python benchmarks/bench_return_maps.py
python -c "import time; from stickslip import CubicLaw, WeakeningLaw; from stickslip.bifurcation.regimes import regimes
for law, lo, hi in [(CubicLaw(alpha=0.5, gamma=1/6), 0.5, 1.5), (WeakeningLaw(c=3.8, p=0.5), 0.1, 1.5)]:
    t = time.perf_counter(); regimes(law, lo, hi); print(f'{time.perf_counter() - t:.3f} s')"
python benchmarks/bench_diagram.py
python benchmarks/bench_chain.py
python benchmarks/bench_scale.py --big
python benchmarks/bench_bp1.py
python benchmarks/bench_inertial.py
python benchmarks/bench_explore.py
python benchmarks/bench_coldstart.py --reproduce --top 8
