"""Numeric core: compiled friction laws, the DOP853 slip integrator and the event-driven engine.

Numbers only: no units, plotting or I/O. The kernels (:mod:`.engine`, :mod:`.chain`,
:mod:`.ratestate`, :mod:`.variational`, :mod:`.dop853`, :mod:`.radau`) are reached from
above only through the core's face (an import-linter contract):

* the array entry points: :mod:`.block_api` (one block), :mod:`.chain_api` (a chain of
  blocks) and :mod:`.kernel` (what both share), re-exported together by :mod:`.api`;
  :mod:`.ratestate_api` (rate and state); :mod:`.cuda` (the GPU backend);
* the results decoded once into named rows and status enums: :mod:`.results`;
* the validators of plain numbers, one per rule: :mod:`.checks`; the memory check:
  :mod:`.memory`; the law kernels' table: :mod:`.laws`; noise and total-variation
  denoising of records: :mod:`.noise`, :mod:`.tv`.
"""

from ._typing_memo import install as _install_typing_memo

_install_typing_memo()
