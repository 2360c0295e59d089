"""The tutorial notebooks of docs/notebooks: stored executed, listed in the site, and they run.

The docs site renders each notebook from its stored outputs (mkdocs-jupyter, ``execute:
false``), so the stored copy must be executed, without errors, with its figures. Executing them
again (nbclient, a fresh kernel) must give the same checks: the so(3) bracket is Poisson with
the Casimir ``x1² + x2² + x3²`` (known), the splitting keeps the energy of the magnets and the
Wisdom–Holman map that of the Sun and giant planets to well below 1e-6 (symplectic maps of
conservative systems: the error is bounded, not drifting).
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
BOOKS = ROOT / "docs" / "notebooks"
NAMES = ("brackets", "magnets", "planets")

nbformat = pytest.importorskip("nbformat")


def _outputs(book) -> tuple[str, int, list[str]]:
    """All text output, the number of images, the error names."""
    text, images, errors = [], 0, []
    for cell in book.cells:
        for out in cell.get("outputs", []):
            if out.get("output_type") == "error":
                errors.append(f"{out.get('ename')}: {out.get('evalue')}")
            data = out.get("data", {})
            images += "image/png" in data
            text.append(out.get("text", "") + data.get("text/plain", ""))
    return "\n".join(text), images, errors


def _checks(name: str, text: str, images: int) -> None:
    if name == "brackets":
        assert "True exact" in text and "Casimirs up to degree 2: [x1**2 + x2**2 + x3**2]" in text
        assert "Jacobi identity: FAILS" in text
        return
    errors = [float(v) for v in re.findall(r"^([0-9.]+e-?[0-9]+)$", text, flags=re.M)]
    errors += [float(v) for v in re.findall(r"max \|ΔH\|/\|H\|: ([0-9.e+-]+)", text)]
    assert errors and max(errors) < 1e-6, text
    assert images >= (4 if name == "magnets" else 3)


@pytest.mark.parametrize("name", NAMES)
def test_the_stored_notebook_is_executed_and_listed_in_the_site(name):
    book = nbformat.read(BOOKS / f"{name}.ipynb", as_version=4)
    code = [c for c in book.cells if c.cell_type == "code"]
    assert all(c.execution_count for c in code), "stored without running every cell"
    text, images, errors = _outputs(book)
    assert not errors, errors
    _checks(name, text, images)
    nav = (ROOT / "mkdocs.yml").read_text(encoding="utf-8")
    assert f"notebooks/{name}.ipynb" in nav
    assert (BOOKS / f"{name}.ipynb").stat().st_size < 600_000  # small enough for the repo


def _execute(name: str):
    pytest.importorskip("nbclient")
    pytest.importorskip("ipykernel")
    from nbclient import NotebookClient

    book = nbformat.read(BOOKS / f"{name}.ipynb", as_version=4)
    # the kernel as a reader's: its own inline figures, not the test session's Agg backend
    env = {k: v for k, v in os.environ.items() if k != "MPLBACKEND"}
    NotebookClient(book, timeout=1200, kernel_name="python3",
                   resources={"metadata": {"path": str(BOOKS)}}).execute(env=env)
    return book


def test_the_brackets_notebook_runs():
    text, images, errors = _outputs(_execute("brackets"))
    assert not errors
    _checks("brackets", text, images)


@pytest.mark.slow  # compiles the N-body kernels: minutes on a cold cache
@pytest.mark.parametrize("name", ["magnets", "planets"])
def test_the_numerical_notebooks_run(name):
    text, images, errors = _outputs(_execute(name))
    assert not errors, errors
    _checks(name, text, images)
