"""The classical-algebras guide page runs as printed: every ``text`` block after a ``python`` block
is exactly what that block prints.

Truths used: the page's printed outputs were checked by hand against the textbook so(4) bracket,
the Pfaffian of a 4 x 4 antisymmetric matrix and the Hopf relation; this test keeps them true.
"""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

PAGE = Path(__file__).resolve().parents[2] / "docs" / "guide" / "classical-algebras.md"


def test_classical_algebras_guide_prints_what_it_says():
    text = PAGE.read_text(encoding="utf-8")
    pairs = re.findall(r"```python\n(.*?)```\s*(?:prints\s*)?(?:\n[^`]*?)?```text\n(.*?)```",
                       text, re.S)
    assert len(pairs) == 5
    namespace: dict = {}
    for code, expected in pairs:
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            exec(compile(code, str(PAGE), "exec"), namespace)  # our own file
        assert out.getvalue() == expected, code
