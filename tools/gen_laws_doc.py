"""Rewrite the laws table in docs/laws.md from the registry (the built-in laws).

Usage: python tools/gen_laws_doc.py
"""

from __future__ import annotations

import pathlib

from stickslip.laws import BUILTIN_LAWS
from stickslip.laws.docs import BEGIN, END, laws_markdown

DOC = pathlib.Path(__file__).resolve().parent.parent / "docs" / "laws.md"


def main() -> None:
    text = DOC.read_text(encoding="utf-8")
    head, _, rest = text.partition(BEGIN)
    _, _, tail = rest.partition(END)
    DOC.write_text(head + laws_markdown(BUILTIN_LAWS).rstrip("\n") + tail, encoding="utf-8")
    print(f"wrote {DOC}")


if __name__ == "__main__":
    main()
