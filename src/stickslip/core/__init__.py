"""Numeric core: compiled friction laws, the DOP853 slip integrator and the event-driven engine.

Numbers only: no units, plotting or I/O.
"""

from ._typing_memo import install as _install_typing_memo

_install_typing_memo()
