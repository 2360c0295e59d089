"""``isinstance`` against a runtime-checkable Protocol, without recomputing its members.

Up to Python 3.11 every ``isinstance(obj, SomeProtocol)`` walks the protocol's MRO and
``__dict__`` twice to list its members (≈ 10–30 µs), and :func:`~poissonkit.numerics.solve`
asks half a dozen such questions per call. There :func:`conforms` lists the members once per
protocol and applies the same test as ``typing`` (``hasattr`` of every member, methods not
``None``); whenever that test fails it defers to ``isinstance`` itself, so the answer is always
``isinstance``'s. From Python 3.12 on ``typing`` keeps the member list itself (and tests
members without evaluating properties), so :func:`conforms` is plain ``isinstance``.
"""

from __future__ import annotations

import sys
import typing
from functools import lru_cache
from typing import TypeGuard, TypeVar

P = TypeVar("P")


#: the member lister of ``typing`` up to Python 3.11 (``None`` from 3.12: isinstance is fast)
_LISTER = (getattr(typing, "_get_protocol_attrs", None)
           if not hasattr(typing.Protocol, "__protocol_attrs__") and sys.version_info < (3, 12)
           else None)


@lru_cache(maxsize=None)
def _members(proto: type) -> tuple[tuple[str, bool], ...] | None:
    """``(name, is a method)`` of each member of ``proto``, or ``None``: use ``isinstance``."""
    if _LISTER is None or not getattr(proto, "_is_runtime_protocol", False):
        return None
    return tuple((n, callable(getattr(proto, n, None))) for n in sorted(_LISTER(proto)))


def conforms(obj: object, proto: type[P]) -> TypeGuard[P]:
    """``isinstance(obj, proto)`` for a ``@runtime_checkable`` Protocol ``proto`` (faster).

    Parameters
    ----------
    obj
        Any object.
    proto
        A runtime-checkable :class:`typing.Protocol`.

    Returns
    -------
    bool
        Exactly what ``isinstance(obj, proto)`` returns.
    """
    members = _members(proto)
    if members is not None and all(
            hasattr(obj, name) and (not method or getattr(obj, name) is not None)
            for name, method in members):
        return True
    return isinstance(obj, proto)
