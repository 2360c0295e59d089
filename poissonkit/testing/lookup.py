"""A contribution given as its registry entry or its registered name."""

from __future__ import annotations

from typing import TypeVar

from poissonkit.errors import InputError
from poissonkit.plugin.contributions import Entry
from poissonkit.testing.report import Findings

E = TypeVar("E", bound=Entry)


def entry_of(contribution: E | str, kind: str, etype: type[E]) -> E:
    """The registry entry: ``contribution`` itself, or the one registered under that name.

    Raises
    ------
    UnknownNameError
        An unknown name (the message lists the registered ones).
    InputError
        An object that is not a ``etype``.
    """
    if isinstance(contribution, str):
        from poissonkit.errors import UnknownNameError
        from poissonkit.plugin import entries

        found = entries(kind)
        if contribution not in found:
            raise UnknownNameError(kind, contribution, found)
        contribution = found[contribution]  # type: ignore[assignment]
    if not isinstance(contribution, etype):
        raise InputError(f"expected a {etype.__name__} or the name of a registered {kind}, "
                         f"got {type(contribution).__name__}")
    return contribution


def label(kind: str, entry: Entry) -> str:
    """``"potential 'dipole'"``: how the messages name a contribution."""
    return f"{kind} {entry.name!r}"


def findings_for(contribution: E | str, kind: str, etype: type[E], noun: str = ""
                 ) -> tuple[E, Findings]:
    """How every check starts: the entry (:func:`entry_of`) and its empty :class:`Findings`.

    ``noun`` names the kind in messages where it differs from the registry's ``kind``
    (``"model family"`` for ``"model_family"``).
    """
    entry = entry_of(contribution, kind, etype)
    return entry, Findings(label(noun or kind, entry))
