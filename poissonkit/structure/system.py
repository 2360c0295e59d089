"""A (conformally) Hamiltonian system: bivector + Hamiltonian + multiplier + known invariants."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Any

import sympy as sp

from poissonkit.structure.bivector import Bivector


@dataclass(frozen=True)
class HamiltonianSystem:
    """``xdot = N(x) P(x) dH(x)`` with its claimed invariants.

    Parameters
    ----------
    structure
        The Poisson bivector ``P``.
    hamiltonian
        ``H`` as a sympy expression in ``structure.coords`` and parameters.
    multiplier
        Conformal factor ``N`` (1 for Hamiltonian systems; ``-1/g`` for the survey's body-frame
        systems, see :mod:`poissonkit.conventions`).
    casimirs, integrals
        Claimed Casimirs of ``P`` and first integrals of the flow, by name.
    measure
        Claimed invariant-measure density ``rho`` (``div(rho X) = 0``), or ``None``.
    params
        Numerical values of symbolic parameters, by symbol name.
    name, doc
        Identification for reports.
    original
        Optional: the original equations of motion ``{x_i: xdot_i}`` the representation must
        reproduce (e.g. survey (34) for the Chaplygin ball).
    constraints
        Expressions that vanish on the physical phase space (e.g. ``|gamma|^2 - 1``), used when
        an identity only holds there.
    """

    structure: Bivector
    hamiltonian: sp.Expr
    multiplier: sp.Expr = sp.Integer(1)
    casimirs: Mapping[str, sp.Expr] = field(default_factory=dict)
    integrals: Mapping[str, sp.Expr] = field(default_factory=dict)
    measure: sp.Expr | None = None
    params: Mapping[str, Any] = field(default_factory=dict)
    name: str = ""
    doc: str = ""
    original: Mapping[sp.Symbol, sp.Expr] | None = None
    constraints: tuple[sp.Expr, ...] = ()

    @property
    def coords(self) -> tuple[sp.Symbol, ...]:
        """The state coordinates, in order."""
        return self.structure.coords

    def vector_field(self) -> sp.Matrix:
        """``X = N P dH`` as a column of sympy expressions."""
        return self.structure.hamiltonian_vector_field(self.hamiltonian, self.multiplier)

    def with_params(self, **values: Any) -> HamiltonianSystem:
        """A copy with some parameter values replaced."""
        merged = dict(self.params)
        merged.update(values)
        return replace(self, params=merged)
