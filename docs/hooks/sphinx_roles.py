"""griffe extension: Sphinx cross-reference roles in docstrings as Markdown.

poissonkit's numpydoc docstrings use Sphinx roles (``:class:`~poissonkit.numerics.Solution```);
mkdocstrings renders Markdown, where a role would show literally. Each role becomes inline code
with the name the role would display (the last component after ``~``, else the full path),
linked to the API reference when the target is a public name documented there (any other link
would be dead, which the strict build rejects).
"""

from __future__ import annotations

import re
from typing import Any

import griffe

_ROLE = re.compile(r":(?:py:)?(?:class|func|meth|mod|data|attr|exc|obj|const):`(~?)([^`]+?)`")


def documented() -> dict[str, str]:
    """``{dotted path: anchor}`` of the public names the API reference documents: the path of
    each definition and its ``poissonkit.NAME`` alias."""
    import poissonkit

    out: dict[str, str] = {}
    for name in poissonkit.__all__:
        if name.startswith("__"):
            continue
        if name in poissonkit._LAZY:
            path = f"{poissonkit._LAZY[name]}.{name}"
        else:
            obj = getattr(poissonkit, name)
            path = f"{obj.__module__}.{getattr(obj, '__qualname__', name)}"
        out[path] = out[f"poissonkit.{name}"] = path
    return out


def replace_roles(text: str, targets: dict[str, str] | None = None) -> str:
    """The docstring ``text`` with every Sphinx role turned into inline code, linked (an
    autorefs reference) when its target is in ``targets``."""
    def one(m: re.Match) -> str:
        target = m.group(2).strip()
        if "<" in target and target.endswith(">"):  # :class:`title <path>`
            shown, target = (part.strip(" >") for part in target.split("<", 1))
        else:
            shown = target.rsplit(".", 1)[-1] if m.group(1) else target
        anchor = (targets or {}).get(target)
        return f"[`{shown}`][{anchor}]" if anchor else f"`{shown}`"
    return _ROLE.sub(one, text)


class SphinxRoles(griffe.Extension):
    """Rewrite Sphinx roles in every docstring griffe loads."""

    def __init__(self) -> None:
        super().__init__()
        self._targets: dict[str, str] | None = None

    def on_instance(self, *, obj: griffe.Object, **kwargs: Any) -> None:
        if obj.docstring is None:
            return
        if self._targets is None:
            self._targets = documented()
        obj.docstring.value = replace_roles(obj.docstring.value, self._targets)
