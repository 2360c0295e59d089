"""The user guide's Python examples run as printed and say what their comments claim.

Truths used: so(3)'s bracket is Poisson of rank 2 with the Casimir |x|^2 (textbook); the
hand-computed Jacobiator of the negative control (see tests/notebook); midpoint keeps the free
rigid body's quadratic invariants to round-off.
"""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
GUIDE = ROOT / "docs" / "guide"


def _run_blocks(page: Path, tmp_path: Path, monkeypatch) -> list[str]:
    blocks = re.findall(r"```python\n(.*?)```", page.read_text(encoding="utf-8"), re.S)
    assert blocks, f"{page.name} has no python example"
    monkeypatch.chdir(tmp_path)  # files an example writes land in the temporary folder
    out = io.StringIO()
    namespace: dict = {}
    with contextlib.redirect_stdout(out):
        for block in blocks:  # one namespace: a page is read top to bottom
            exec(compile(block, str(page), "exec"), namespace)  # our own file
    return out.getvalue().splitlines()


def test_verify_your_bracket_examples(tmp_path, monkeypatch):
    lines = _run_blocks(GUIDE / "verify-your-bracket.md", tmp_path, monkeypatch)
    text = "\n".join(lines)
    assert "{x1, x2} = x3" in text and "{x1, x3} = -x2" in text  # print(B)
    assert "True exact" in lines
    assert re.search(r"Jac\(x1, x2, x3\) = -?x3", text) and "FAILS" in text
    assert "2" in lines                                   # rank of so(3)
    assert "[x1**2 + x2**2 + x3**2]" in lines
    assert "True 2 ['x1**2 + x2**2 + x3**2']" in lines    # the report


def test_integrate_your_system_examples(tmp_path, monkeypatch):
    import matplotlib

    matplotlib.use("Agg")
    lines = _run_blocks(GUIDE / "integrate-your-system.md", tmp_path, monkeypatch)
    assert lines[0] == "True"                             # |m|^2 is a first integral, exactly
    assert any("steps: 1000" in line for line in lines)   # t_end / step
    assert any("'midpoint'" in line and "'splitting6'" in line for line in lines)
    assert lines[-1] == "True"                            # energy kept to round-off
    assert (tmp_path / "drifts.png").stat().st_size > 1000
    import matplotlib.pyplot as plt

    plt.close("all")


@pytest.mark.parametrize("page", sorted(p.name for p in GUIDE.glob("*.md")))
def test_guide_pages_use_the_public_surface_only(page):
    text = (GUIDE / page).read_text(encoding="utf-8")
    for block in re.findall(r"```python\n(.*?)```", text, re.S):
        imports = re.findall(r"^\s*(?:from|import) .*$", block, re.M)
        assert all(i.strip() in ("import poissonkit as pk", "import sympy as sp")
                   for i in imports), imports


def test_paper_to_bracket_examples(tmp_path, monkeypatch):
    # truths: Plank's bracket is Poisson for all a, b, c and gives the Lotka–Volterra field
    # with H = x1 + x2 + x3; x1*x2*x3 is its Casimir at (a, b, c) = (1, -1, 1); the damped top
    # has no Hamiltonian among its (non-)integrals
    lines = _run_blocks(GUIDE / "paper-to-bracket.md", tmp_path, monkeypatch)
    assert "  {x1, x2} = a*x1*x2" in lines and "  {x2, x3} = c*x2*x3" in lines
    assert lines.count("True") >= 4                       # Jacobi, X = P dH, Casimir, found P
    assert "[x1*x2*x3]" in lines and "True ()" in lines
    assert any(line.startswith("H = m1**2 + m2**2/2 + m3**2/3 |") for line in lines)
    assert "no_linear_solution True" in lines and lines[-1] == "True ok"
