"""The one-block model in the browser: ``stickslip explore``.

:mod:`~.session` computes what the page shows from a set-up (no web server);
:mod:`~.app` is the Bokeh server application around it.
"""

from .app import Explorer, make_server, serve
from .session import (
    EXPR,
    NU_RANGE,
    Setup,
    View,
    check_nu,
    command,
    compute,
    default_params,
    law_names,
    parse_params,
    regime_diagram,
    slider_range,
    view_csv,
)

__all__ = [
    "EXPR",
    "NU_RANGE",
    "Explorer",
    "Setup",
    "View",
    "check_nu",
    "command",
    "compute",
    "default_params",
    "law_names",
    "make_server",
    "parse_params",
    "regime_diagram",
    "serve",
    "slider_range",
    "view_csv",
]
