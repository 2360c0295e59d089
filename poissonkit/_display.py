"""Notebook display helpers: the text, HTML and LaTeX forms of poissonkit's objects.

Jupyter shows ``_repr_html_`` (or ``_repr_latex_``) when an object is the value of a cell and
``_repr_pretty_`` as plain text; the classes build those from the small helpers here so that
every object looks alike. Long listings are cut at :data:`MAX_ROWS` rows with a note of how
many were left out.
"""

from __future__ import annotations

import html
from collections.abc import Iterable, Sequence
from typing import Protocol, TypeVar

#: Rows shown before a listing is cut (brackets of an 18-dimensional structure: 81 rows).
MAX_ROWS = 40

Row = TypeVar("Row")


class PrettyPrinter(Protocol):
    """What ``_repr_pretty_`` uses of IPython's ``PrettyPrinter``."""

    def text(self, obj: str) -> None: ...


def cut(rows: Sequence[Row], limit: int = MAX_ROWS) -> tuple[list[Row], int]:
    """The first ``limit`` rows and how many were left out."""
    rows = list(rows)
    return rows[:limit], max(0, len(rows) - limit)


def text_block(title: str, rows: Iterable[tuple[str, str]], indent: str = "  ") -> str:
    """``title`` followed by ``key: value`` lines (``key = value`` when ``key`` starts with
    ``{``, i.e. a bracket)."""
    shown, more = cut(list(rows))
    lines = [title]
    for k, v in shown:
        sep = " = " if k.startswith("{") or k.startswith("Jac(") else ": "
        lines.append(f"{indent}{k}{sep}{v}")
    if more:
        lines.append(f"{indent}... ({more} more)")
    return "\n".join(lines)


def html_table(title: str, rows: Iterable[tuple[str, str]], *, ok: bool | None = None) -> str:
    """A small two-column HTML table with a bold caption; ``ok`` colours the caption."""
    shown, more = cut(list(rows))
    colour = "" if ok is None else (' style="color:#1a7f37"' if ok else ' style="color:#cf222e"')
    body = "".join(f"<tr><th style=\"text-align:left\">{html.escape(str(k))}</th>"
                   f"<td style=\"text-align:left\"><code>{html.escape(str(v))}</code></td></tr>"
                   for k, v in shown)
    if more:
        body += f"<tr><td colspan=\"2\"><i>... {more} more</i></td></tr>"
    return (f"<div class=\"poissonkit-repr\"><b{colour}>{html.escape(title)}</b>"
            f"<table>{body}</table></div>")


def latex_aligned(rows: Iterable[tuple[str, str]]) -> str:
    """``$\\begin{aligned} lhs &= rhs \\\\ ... \\end{aligned}$`` from LaTeX pieces."""
    shown, more = cut(list(rows))
    lines = [f"{lhs} &= {rhs}" for lhs, rhs in shown]
    if more:
        lines.append(f"&\\dots\\ \\text{{({more} more)}}")
    return "$\\begin{aligned}" + " \\\\ ".join(lines) + "\\end{aligned}$"


def latex_text(s: str) -> str:
    """Plain text safe inside ``\\text{...}``."""
    for a, b in (("\\", "\\backslash "), ("{", "\\{"), ("}", "\\}"), ("_", "\\_"), ("%", "\\%"),
                 ("&", "\\&"), ("#", "\\#"), ("$", "\\$"), ("^", "\\^{}")):
        s = s.replace(a, b)
    return f"\\text{{{s}}}"


def latex_table(rows: Iterable[tuple[str, str]]) -> str:
    """A two-column ``array`` of text, for objects whose content is not mathematics."""
    shown, _more = cut(list(rows))
    body = " \\\\ ".join(f"{latex_text(str(k))} & {latex_text(str(v))}" for k, v in shown)
    return "$\\begin{array}{ll}" + body + "\\end{array}$"


class Displayable:
    """Mixin: ``_repr_pretty_`` (IPython's plain text) prints ``str(self)``."""

    def _repr_pretty_(self, p: PrettyPrinter, cycle: bool) -> None:
        p.text(type(self).__name__ + "(...)" if cycle else str(self))


class TitledRows:
    """The text and notebook forms of an object that shows as a title over ``key: value`` rows.

    A subclass defines ``_title()`` and ``_rows()``; ``str()``, IPython's plain text and
    Jupyter's HTML table follow from them, so that every such result looks alike.
    ``_verdict()`` colours the HTML caption (green holds, red fails; ``None``: not a verdict).
    """

    def _title(self) -> str:
        raise NotImplementedError

    def _rows(self) -> list[tuple[str, str]]:
        raise NotImplementedError

    def _verdict(self) -> bool | None:
        return None

    def __str__(self) -> str:
        return text_block(self._title(), self._rows())

    def _repr_pretty_(self, p: PrettyPrinter, cycle: bool) -> None:
        p.text(f"{type(self).__name__}(...)" if cycle else str(self))

    def _repr_html_(self) -> str:
        return html_table(self._title(), self._rows(), ok=self._verdict())
