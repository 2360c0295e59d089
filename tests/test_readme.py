"""The README's example runs as printed and says what its comments claim."""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"


def test_readme_example_runs_and_prints_what_it_claims():
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), re.S)
    assert blocks, "README has no python example"
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(blocks[0], str(README), "exec"), {})  # our own file, not user input
    lines = out.getvalue().splitlines()
    assert lines[0] == "True"
    assert lines[1].count("top1.nu_x**2") == 1 and lines[1].count("top2.m_x*top2.nu_x") == 1
    assert lines[2] == "top1.nu_z"
    energy, force = lines[3].split(" ", 1)
    assert float(energy) < 0                                   # opposite axes side by side attract
    assert float(force.strip("[] ").split()[0]) < 0            # pulled back towards body 1


def test_readme_example_uses_the_public_surface_only():
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), re.S)
    imports = [line.strip() for b in blocks for line in b.splitlines()
               if re.match(r"\s*(from|import)\s", line)]
    assert imports == ["import poissonkit as pk"] * len(blocks), imports
