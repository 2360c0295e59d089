"""The integrators' shared skeleton: status codes by name, module sizes of the package."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import poissonkit.numerics.integrators as integrators_pkg

INTEGRATORS = Path(integrators_pkg.__file__).parent


def literal_statuses(source: str) -> list[int]:
    """Line numbers of ``return <int literal>, ...`` (a status written as a number)."""
    lines = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Return) and isinstance(node.value, ast.Tuple) and node.value.elts:
            first = node.value.elts[0]
            if isinstance(first, ast.Constant) and type(first.value) is int:
                lines.append(node.lineno)
    return lines


def test_literal_status_is_found() -> None:
    """Negative control: the scan sees a status returned as a number."""
    src = "def run(y, t):\n    if y:\n        return 1, t, 0\n    return RUNNING, t, 0\n"
    assert literal_statuses(src) == [3]


@pytest.mark.parametrize("path", sorted(INTEGRATORS.rglob("*.py")), ids=lambda p: p.name)
def test_no_literal_status(path: Path) -> None:
    """Every compiled loop returns its status by name (RUNNING, NONFINITE, DONE, ...)."""
    assert literal_statuses(path.read_text(encoding="utf-8")) == []


@pytest.mark.parametrize("path", sorted(INTEGRATORS.rglob("*.py")), ids=lambda p: p.name)
def test_module_size(path: Path) -> None:
    """Modules of one job: none over 600 lines."""
    assert len(path.read_text(encoding="utf-8").splitlines()) <= 600
