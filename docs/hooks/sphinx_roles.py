"""griffe extension: Sphinx cross-reference roles in docstrings shown as inline code.

poissonkit's numpydoc docstrings use Sphinx roles (``:class:`~poissonkit.numerics.Solution```);
mkdocstrings renders Markdown, where a role would show literally. Each role becomes inline code
with the name the role would display (the last component after ``~``, else the full path).
"""

from __future__ import annotations

import re
from typing import Any

import griffe

_ROLE = re.compile(r":(?:py:)?(?:class|func|meth|mod|data|attr|exc|obj|const):`(~?)([^`]+?)`")


def replace_roles(text: str) -> str:
    """The docstring ``text`` with every Sphinx role turned into inline code."""
    def one(m: re.Match) -> str:
        target = m.group(2).strip()
        if "<" in target and target.endswith(">"):  # :class:`title <path>`
            target = target.split("<", 1)[0].strip()
        elif m.group(1):
            target = target.rsplit(".", 1)[-1]
        return f"`{target}`"
    return _ROLE.sub(one, text)


class SphinxRoles(griffe.Extension):
    """Rewrite Sphinx roles in every docstring griffe loads."""

    def on_instance(self, *, obj: griffe.Object, **kwargs: Any) -> None:
        if obj.docstring is not None:
            obj.docstring.value = replace_roles(obj.docstring.value)
