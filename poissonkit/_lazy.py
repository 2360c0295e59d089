"""Names a package imports on first use (PEP 562), for ``poissonkit``, ``poissonkit.scene`` and
``poissonkit.numerics``: their ``__getattr__`` hands each look-up to :func:`load`, so that
importing the package stays cheap (no sympy, numpy or numba until a name is asked for)."""

import importlib
from collections.abc import Mapping, MutableMapping


def load(namespace: MutableMapping[str, object], table: Mapping[str, str], name: str) -> object:
    """``name`` imported from the module ``table[name]`` and kept in ``namespace``.

    Parameters
    ----------
    namespace
        The package's ``globals()``: the value is stored there, so later look-ups do not reach
        the package's ``__getattr__`` again.
    table
        ``{name: module}``: where each lazily imported name is defined (a module name with a
        leading dot is relative to the package, ``namespace["__name__"]``).
    name
        The attribute asked for.

    Raises
    ------
    AttributeError
        ``name`` is not in ``table`` (as for any missing module attribute).
    """
    if name not in table:
        raise AttributeError(f"module {namespace['__name__']!r} has no attribute {name!r}")
    package = str(namespace["__name__"])
    value = getattr(importlib.import_module(table[name], package), name)
    namespace[name] = value
    return value
