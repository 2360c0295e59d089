"""What a numerics system offers, declared once as data instead of probed at run time.

A system class states the contracts of :mod:`poissonkit.contracts` it fulfils in a class
attribute ``traits = SystemTraits(HasLayout, HasCasimirs, ...)``. Code that uses an optional
capability asks :func:`offers` (``if offers(system, HasCasimirs): system.casimirs(y)``), which
reads that declaration: no attribute of the system is evaluated, so a property that compiles
kernels is never triggered by the question (as ``isinstance`` against a runtime-checkable
protocol does up to Python 3.11), and the answer costs a set look-up.

A system that declares nothing (a third party's duck-typed object, written against the
protocols alone) is still served: :func:`offers` falls back to ``isinstance`` with the protocol,
which is what it was before declarations existed. ``tests/numerics/test_system_traits.py``
checks that every built-in declaration says exactly what ``isinstance`` says of an instance.
"""

from __future__ import annotations

from typing import TypeGuard, TypeVar

from poissonkit.errors import InputError

__all__ = ["SystemTraits", "offers"]

P = TypeVar("P")


class SystemTraits:
    """The contracts (``typing.Protocol`` classes of :mod:`poissonkit.contracts`) a system
    class fulfils.

    Parameters
    ----------
    *contracts
        Runtime-checkable protocol classes, e.g. ``HasLayout, HasCasimirs``.

    Raises
    ------
    InputError
        If an argument is not a runtime-checkable protocol class.
    """

    __slots__ = ("contracts",)

    def __init__(self, *contracts: type) -> None:
        for c in contracts:
            if not (isinstance(c, type) and getattr(c, "_is_runtime_protocol", False)):
                raise InputError(f"SystemTraits takes runtime-checkable Protocol classes, got "
                                 f"{c!r}")
        self.contracts: frozenset[type] = frozenset(contracts)

    def extended(self, *contracts: type) -> SystemTraits:
        """These traits and ``contracts`` (a system class that adds to a family's traits)."""
        return SystemTraits(*self.contracts, *contracts)

    def __contains__(self, contract: object) -> bool:
        return contract in self.contracts

    def __repr__(self) -> str:
        return f"SystemTraits({', '.join(sorted(c.__name__ for c in self.contracts))})"


def offers(system: object, contract: type[P]) -> TypeGuard[P]:
    """Whether ``system`` fulfils ``contract``, from its class's declared :class:`SystemTraits`.

    Parameters
    ----------
    system
        Any object handed to the numerics as a system.
    contract
        A runtime-checkable protocol of :mod:`poissonkit.contracts`.

    Returns
    -------
    bool
        The declaration's answer; for a class that declares no traits, ``isinstance(system,
        contract)``.
    """
    declared = getattr(type(system), "traits", None)
    if isinstance(declared, SystemTraits):
        return contract in declared.contracts
    return isinstance(system, contract)
