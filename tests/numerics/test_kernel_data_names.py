"""No code reads the compiled kernels' data or scratch by position.

The constants a kernel reads (``system.data``) and its scratch (``system.work()``) are named
tuples (:mod:`poissonkit.numerics.nbody.data`); a positional read such as ``data[3]`` would
silently read another slot once a field is added or moved. This test walks every source file of
``poissonkit/`` and ``plugins/`` and fails on a subscript with an integer constant (or a slice
with integer bounds) of a kernel data variable.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

#: the names a kernel's data, scratch and their parts go by
DATA_NAMES = frozenset({"data", "work", "fd", "lists", "gdata"})

#: modules that may index these names (none: the data is built by keyword)
BUILDERS: frozenset[str] = frozenset()

def _is_position(node: ast.expr) -> bool:
    """An integer constant, ``-k``, or a slice whose bounds are such constants."""
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
        node = node.operand
    if isinstance(node, ast.Constant):
        return isinstance(node.value, int) and not isinstance(node.value, bool)
    if isinstance(node, ast.Slice):
        bounds = [b for b in (node.lower, node.upper) if b is not None]
        return bool(bounds) and all(_is_position(b) for b in bounds)
    return False


def _data_name(node: ast.expr) -> str | None:
    """``data`` for ``data`` and for ``<anything>.data`` (e.g. ``system.data``), else None."""
    if isinstance(node, ast.Name) and node.id in DATA_NAMES:
        return node.id
    if isinstance(node, ast.Attribute) and node.attr in DATA_NAMES:
        return node.attr
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) \
            and node.func.attr == "work":  # system.work()[k]
        return "work()"
    return None


def positional_reads(source: str, filename: str = "<snippet>") -> list[str]:
    """``file:line: expression`` of every positional read of kernel data in ``source``."""
    found = []
    for node in ast.walk(ast.parse(source, filename)):
        if isinstance(node, ast.Subscript) and _is_position(node.slice) \
                and _data_name(node.value) is not None:
            found.append(f"{filename}:{node.lineno}: {ast.unparse(node)}")
    return found


def _sources() -> list[Path]:
    files = [*(ROOT / "poissonkit").rglob("*.py"), *(ROOT / "plugins").rglob("*.py")]
    return sorted(f for f in files if "__pycache__" not in f.parts)


def test_no_positional_reads_of_kernel_data() -> None:
    hits = []
    for path in _sources():
        rel = path.relative_to(ROOT).as_posix()
        if rel in BUILDERS:
            continue
        hits += positional_reads(path.read_text(encoding="utf-8"), rel)
    assert not hits, "kernel data read by position:\n" + "\n".join(hits)


def test_the_walk_sees_the_kernel_modules() -> None:
    """The walk covers the modules that hold the kernels (a wrong root would pass vacuously)."""
    names = {p.relative_to(ROOT).as_posix() for p in _sources()}
    assert "poissonkit/numerics/nbody/loops.py" in names
    assert "poissonkit/numerics/fields/compose.py" in names
    assert any(n.startswith("plugins/") for n in names)


@pytest.mark.parametrize("snippet", [
    "def f(y, data, work):\n    return data[3]\n",
    "def f(y, data, work):\n    F = work[2]\n",
    "def f(system):\n    return system.data[0]\n",
    "def f(system):\n    mass, alpha = system.data[:2]\n",
    "def f(s):\n    return s.work()[4]\n",
    "def f(data):\n    fd = data.fields\n    return fd[-1]\n",
])
def test_a_positional_read_is_caught(snippet: str) -> None:
    assert len(positional_reads(snippet)) == 1


@pytest.mark.parametrize("snippet", [
    "def f(y, data, work):\n    return data.mass[3]\n",
    "def f(y, data, work):\n    F = work.F\n    return F[2]\n",
    "def f(doc):\n    return doc['data'][0]\n",
    "def f(data, k):\n    return data[k]\n",
    "def f(data):\n    return data['bivector']\n",
])
def test_named_reads_pass(snippet: str) -> None:
    assert positional_reads(snippet) == []
