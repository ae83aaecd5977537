"""Independent references for the tests: written from the equations, sharing no code with stickslip.

- ``one_block``: the one-block stick-slip cycle, pure-slip orbits and lab-like records with
  SciPy's ``solve_ivp`` (the friction laws typed in again);
- ``bp1``: the SEAS BP1 quasi-dynamic spring-slider for SciPy;
- ``chain``: chains of blocks, event-driven with ``solve_ivp`` events;
- ``rsf_generator``: rate-and-state velocity-step records (the state as the variable, Radau);
- ``rsfmodel``: rsfmodel's published velocity-step values, quoted, not computed.

The tests import them as ``reference.<module>`` (``tests/`` is on ``sys.path`` under pytest's
default ``prepend`` import mode: ``tests/`` has no ``__init__.py``); the benchmarks and tools put
``tests/`` on ``sys.path`` themselves.
"""
