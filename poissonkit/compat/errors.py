"""Errors of the PoissonGeometry-compatible front end.

PoissonGeometry raises its own exception classes (``MultivectorError``, ``DiferentialFormError``
— sic —, ``FunctionError``, ``CasimirError``, ``Nonlinear``, ``Nonhomogeneous``,
``DimensionError``). The same names exist here so that ``except`` clauses written for that package
keep working after switching the import; each one is also a :class:`poissonkit.errors.InputError`
(hence a ``ValueError`` and a :class:`~poissonkit.errors.PoissonkitError`).
"""

from __future__ import annotations

from poissonkit.errors import DimensionError, InputError, ParseError

__all__ = [
    "CasimirError", "DiferentialFormError", "DifferentialFormError", "DimensionError",
    "FunctionError", "MultivectorError", "Nonhomogeneous", "Nonlinear", "ParseError",
]


class MultivectorError(InputError):
    """A multivector dict is malformed: repeated, zero/negative or out-of-range indices, keys of
    different lengths, an empty multivector where one is required."""


class DiferentialFormError(InputError):
    """A differential-form dict is malformed (PoissonGeometry's spelling, kept for drop-in use)."""


#: Correctly spelled alias of :class:`DiferentialFormError`.
DifferentialFormError = DiferentialFormError


class FunctionError(InputError):
    """A function that must be nowhere vanishing is identically zero."""


class CasimirError(InputError):
    """The number of Casimir functions does not match ``dim - 2`` (Flaschka–Ratiu)."""


class Nonlinear(InputError):
    """A bivector that must be linear (Lie–Poisson) is not."""


class Nonhomogeneous(InputError):
    """A bivector that must be homogeneous polynomial is not."""
