"""An import-linter contract of our own: no module reaches a private name of another package.

A name with a leading underscore (``_helper``, a private module ``_dop853_unrolled``) is
private to the package that defines it: its module's siblings may import it, nothing
outside may. Registered in ``pyproject.toml`` (``contract_types``); ``.ci/run`` runs
``lint-imports`` with this folder on ``PYTHONPATH``.
"""

from __future__ import annotations

import ast
import importlib.util
from pathlib import Path

from importlinter import Contract, ContractCheck, fields, output

__all__ = ["PrivateNamesContract"]


def _private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


class PrivateNamesContract(Contract):
    """Private names (leading underscore) are imported only from within their own package.

    Options: ``root`` (the package checked).
    """

    root = fields.StringField()

    def check(self, graph, verbose: bool) -> ContractCheck:  # type: ignore[no-untyped-def]
        spec = importlib.util.find_spec(str(self.root))
        assert spec is not None and spec.origin is not None
        base = Path(spec.origin).parent
        problems: list[str] = []
        for module in sorted(m for m in graph.modules if m == self.root or m.startswith(f"{self.root}.")):
            rel = module.split(".")[1:]
            init = base.joinpath(*rel, "__init__.py")
            path = init if init.exists() else base.joinpath(*rel[:-1], f"{rel[-1]}.py")
            if not path.exists():
                continue
            is_package = path.name == "__init__.py"
            package = module if is_package else module.rsplit(".", 1)[0]
            tree = ast.parse(path.read_text(encoding="utf-8"))
            for node in ast.walk(tree):
                if isinstance(node, ast.ImportFrom):
                    if node.level:
                        parts = package.split(".")
                        anchor = parts[: len(parts) - (node.level - 1)]
                        target = ".".join(anchor + ([node.module] if node.module else []))
                    else:
                        target = node.module or ""
                    if not target.startswith(str(self.root)):
                        continue
                    for alias in node.names:
                        self._judge(problems, module, package, target, alias.name, node.lineno, graph)
                elif isinstance(node, ast.Import):
                    for alias in node.names:
                        if alias.name.startswith(str(self.root)):
                            head, _, last = alias.name.rpartition(".")
                            self._judge(problems, module, package, head, last, node.lineno, graph)
        return ContractCheck(kept=not problems, warnings=None, metadata={"problems": problems})

    def _judge(  # type: ignore[no-untyped-def]
        self, problems: list[str], module: str, package: str, target: str, name: str, line: int, graph
    ) -> None:
        # the package a private name belongs to: a private module's own package, or the package
        # of the module that defines a private attribute
        segments = f"{target}.{name}".split(".")
        for i, seg in enumerate(segments):
            if not _private(seg):
                continue
            owner = ".".join(segments[:i])
            is_module = ".".join(segments[: i + 1]) in graph.modules
            if not is_module and owner in graph.modules and not _is_package(owner, graph):
                owner = owner.rsplit(".", 1)[0]  # a private attribute of a module: its package's
            if not (package == owner or package.startswith(owner + ".")):
                problems.append(f"{module}:{line} imports {'.'.join(segments[: i + 1])}, private to {owner}")
            return

    def render_broken_contract(self, check: ContractCheck) -> None:
        for p in check.metadata["problems"]:
            output.print_error(p, bold=False)
            output.new_line()


def _is_package(module: str, graph) -> bool:  # type: ignore[no-untyped-def]
    return any(m.startswith(module + ".") for m in graph.modules)
