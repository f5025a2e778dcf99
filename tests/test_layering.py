"""The package's import graph follows docs/architecture.md: each module imports only from
modules above it in the architecture's module table (imports inside functions included), so
the core never imports the shells and there is no cycle between the parts."""

from __future__ import annotations

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "src" / "dancebots"


def documented_order() -> list[str]:
    """The parts of the package in the order of the architecture's module table."""
    text = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
    table = text.split("| module | what it holds |", 1)[1]
    names = re.findall(r"^\| `([\w/.]+)` \|", table, flags=re.MULTILINE)
    return [n.removesuffix(".py").removesuffix("/") for n in names
            if (PACKAGE / n.removesuffix("/")).exists()
            and (n.endswith(".py") or (PACKAGE / n.removesuffix("/") / "__init__.py").exists()
                 or any((PACKAGE / n.removesuffix("/")).glob("*.py")))]


def part_of(module: str) -> str:
    """``dancebots.sim.stage`` -> ``sim``; ``dancebots`` itself -> ``""``."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else ""


def imports() -> dict[str, set[str]]:
    """Each part of the package -> the parts it imports (any import, anywhere in its files)."""
    found: dict[str, set[str]] = {}
    for path in PACKAGE.rglob("*.py"):
        relative = path.relative_to(PACKAGE).with_suffix("")
        here = part_of(".".join(("dancebots", *relative.parts)))
        if relative.parts[-1] == "__init__" and len(relative.parts) == 1:
            here = ""
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            targets: list[str] = []
            if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                targets = [node.module]
            elif isinstance(node, ast.Import):
                targets = [alias.name for alias in node.names]
            for target in targets:
                if target == "dancebots" or target.startswith("dancebots."):
                    there = part_of(target)
                    if there and there != here:
                        found.setdefault(here, set()).add(there)
    return found


def test_the_documented_order_names_every_part() -> None:
    order = documented_order()
    parts = {p.stem if p.is_file() else p.name for p in PACKAGE.iterdir()
             if (p.suffix == ".py" and p.stem != "__init__")
             or (p.is_dir() and any(p.glob("*.py")))}
    assert set(order) == parts


def test_every_import_goes_up_the_documented_order() -> None:
    order = documented_order()
    rank = {name: i for i, name in enumerate(order)}
    wrong = sorted(f"{here} imports {there}" for here, theres in imports().items()
                   for there in theres if here and rank[there] >= rank[here])
    assert wrong == []


def test_the_core_never_imports_the_shells() -> None:
    shells = {"cli", "ros1"}
    graph = imports()
    assert {s for here, theres in graph.items() if here not in shells | {"report"}
            for s in theres & (shells | {"report"})} == set()
    assert "cli" not in graph.get("ros1", set())
