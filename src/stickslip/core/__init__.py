"""Numeric core: compiled friction laws, the DOP853 slip integrator and the event-driven engine.

Numbers only: no units, plotting or I/O. The array entry points of the compiled
engines: :mod:`.block_api` (one block), :mod:`.chain_api` (a chain of blocks) and
:mod:`.kernel` (what both share), re-exported together by :mod:`.api`.
"""

from ._typing_memo import install as _install_typing_memo

_install_typing_memo()
