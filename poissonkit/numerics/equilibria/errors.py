"""Typed errors of the relative-equilibrium solver and the linear stability analysis."""

from __future__ import annotations

from poissonkit.errors import InputError, PoissonkitError


class EquilibriumError(PoissonkitError):
    """Base class of the errors of :func:`~poissonkit.relative_equilibrium` and
    :func:`~poissonkit.linear_stability`."""


class NoConvergenceError(EquilibriumError):
    """The Newton / least-squares solve did not reach a relative equilibrium.

    Attributes
    ----------
    state
        The last iterate.
    residual
        Its relative residual (see :class:`~poissonkit.RelativeEquilibrium`).
    """

    def __init__(self, message: str, state: object = None, residual: float = float("nan")) -> None:
        super().__init__(message)
        self.state = state
        self.residual = residual


class SingularPointError(EquilibriumError):
    """The point is not on a regular symplectic leaf cut out by the declared Casimirs: the
    bracket's rank plus the rank of the Casimir differentials is less than the dimension (a
    singular point of the bracket, dependent Casimir differentials, or Casimirs the system does
    not declare), so the leaf's tangent space is not the Casimirs' constraint space."""


class NotAnEquilibriumError(EquilibriumError, InputError):
    """A state given to :func:`~poissonkit.linear_stability` is not a relative equilibrium."""


__all__ = ["EquilibriumError", "NoConvergenceError", "NotAnEquilibriumError",
           "SingularPointError"]
