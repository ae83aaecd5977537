"""``python -m stickslip.cli``: the command line, started as ``stickslip`` starts it."""

from stickslip.__main__ import main

main()
