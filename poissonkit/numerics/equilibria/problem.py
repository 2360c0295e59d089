"""What the equilibrium solver and the stability analysis read of a system, in one place.

A system is reached only through the contracts of :mod:`poissonkit.contracts`: the vector field
and energy (:class:`~poissonkit.contracts.NumericsSystem`), the Casimirs
(:class:`~poissonkit.contracts.HasCasimirs`), the Poisson matrix ``P(x)`` from the symbolic form
of a compiled system (:class:`~poissonkit.contracts.HasSymbolicForm`) or from the structure of a
system of bodies (:class:`~poissonkit.contracts.HasPoissonStructure`), and an analytic Jacobian
where the system has one (:class:`~poissonkit.contracts.HasJacobian`).

A *momentum* is a conserved function ``J(x)`` generating a continuous symmetry (spin about the
vertical: ``J = (Σ r × p + m)_z``); a relative equilibrium with angular velocities ``ω`` is a
point where ``X_H = Σ ω_k X_{J_k}``, an equilibrium of ``X_H − Σ ω_k X_{J_k}`` (the field seen
in the co-moving frame).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
import sympy as sp
from numpy.typing import ArrayLike

from poissonkit.contracts import (HasCasimirs, HasJacobian, HasLayout, HasPoissonStructure,
                                  HasSymbolicForm, NumericsSystem)
from poissonkit.errors import DimensionError, InputError
from poissonkit.numerics.equilibria import differences as fd
from poissonkit.traits import offers

#: A conserved momentum ``J(x)`` (a float of one state).
Momentum = Callable[[np.ndarray], float]


def _poisson_matrix(system: NumericsSystem) -> Callable[[np.ndarray], np.ndarray]:
    """``x ↦ P(x)`` (numpy), from the symbolic bracket the system declares."""
    if offers(system, HasSymbolicForm):
        form = system.symbolic_form()
        coords, matrix = form.coords, form.structure
    elif offers(system, HasPoissonStructure):
        bivector = system.to_structure()
        coords, matrix = tuple(bivector.coords), bivector.matrix
    else:
        raise InputError(f"{type(system).__name__} declares no Poisson structure (needs "
                         "symbolic_form() or to_structure()): the linearisation on the Poisson "
                         "manifold needs P(x)")
    if len(coords) != system.dim:
        raise DimensionError(f"the structure has {len(coords)} coordinates, the system "
                             f"{system.dim}")
    free = set().union(*(e.free_symbols for e in matrix)) - set(coords)
    if free:
        raise InputError(f"the Poisson structure has unset parameters {sorted(map(str, free))}")
    fn = sp.lambdify([list(coords)], matrix, modules="numpy")
    return lambda x: np.asarray(fn(np.asarray(x, dtype=float)), dtype=float)


@dataclass(frozen=True)
class EquilibriumProblem:
    """A system with the momenta and frame angular velocities of a relative equilibrium.

    Parameters
    ----------
    system
        Any numerics system with ``rhs``, ``energy`` and a declared bracket.
    momenta
        Conserved momenta ``J_k(x)`` of continuous symmetries (may be empty).
    omega
        Angular velocities ``ω_k`` of the co-moving frame, one per momentum (zeros: an
        equilibrium in the fixed frame).
    scale
        Typical size of each state component (finite-difference steps, convergence test and
        the coordinates of the stability analysis are relative to it).
    """

    system: NumericsSystem
    momenta: tuple[Momentum, ...] = ()
    omega: np.ndarray = field(default_factory=lambda: np.zeros(0))
    scale: np.ndarray = field(default_factory=lambda: np.zeros(0))

    def __post_init__(self) -> None:
        if not offers(self.system, NumericsSystem):
            raise InputError(f"needs a numerics system (rhs, energy, dim), got "
                             f"{type(self.system).__name__}")
        for j in self.momenta:
            if not callable(j):
                raise InputError(f"momenta must be callables J(state) -> float, got {j!r}")
        om = np.zeros(len(self.momenta)) if self.omega is None else np.atleast_1d(
            np.asarray(self.omega, dtype=float))
        if om.shape != (len(self.momenta),):
            raise DimensionError(f"omega has {om.size} entries for {len(self.momenta)} momenta")
        if not np.all(np.isfinite(om)):
            raise InputError(f"omega must be finite, got {om.tolist()}")
        object.__setattr__(self, "omega", om)
        sc = np.asarray(self.scale, dtype=float)
        if sc.shape != (self.system.dim,) or not np.all(np.isfinite(sc)) or np.any(sc <= 0):
            raise InputError(f"scale must be {self.system.dim} positive numbers, got "
                             f"{np.asarray(self.scale).tolist()}")
        object.__setattr__(self, "scale", sc)
        object.__setattr__(self, "_P", _poisson_matrix(self.system))

    @property
    def dim(self) -> int:
        """State length."""
        return int(self.system.dim)

    def state(self, y: object) -> np.ndarray:
        """``y`` as a finite float vector of the system's length."""
        x = np.asarray(y, dtype=float)
        if x.shape != (self.dim,):
            raise DimensionError(f"state has shape {x.shape}, expected ({self.dim},)")
        if not np.all(np.isfinite(x)):
            raise InputError("state contains non-finite values")
        return x

    def energy(self, x: np.ndarray) -> float:
        """``H(x)``."""
        return float(self.system.energy(x))

    def energy_gradient(self, x: np.ndarray) -> np.ndarray:
        """``∇H(x)`` (central differences)."""
        return fd.gradient(self.energy, x, self.scale)

    def energy_hessian(self, x: np.ndarray) -> np.ndarray:
        """``∇²H(x)`` (central differences)."""
        return fd.hessian(self.energy, x, self.scale)

    def casimirs(self, x: np.ndarray) -> np.ndarray:
        """Declared Casimir values (empty if none)."""
        if offers(self.system, HasCasimirs):
            return np.atleast_1d(np.asarray(self.system.casimirs(x), dtype=float))
        return np.zeros(0)

    def momentum_values(self, x: np.ndarray) -> np.ndarray:
        """``J_k(x)``."""
        return np.array([float(j(x)) for j in self.momenta])

    def poisson(self, x: np.ndarray) -> np.ndarray:
        """The Poisson matrix ``P(x)``."""
        return self._P(x)  # type: ignore[attr-defined]

    def field(self, x: np.ndarray) -> np.ndarray:
        """The co-moving vector field ``X_H − Σ ω_k P ∇J_k`` at ``x``."""
        f = np.asarray(self.system.rhs(0.0, x), dtype=float)
        if self.momenta and np.any(self.omega):
            P = self.poisson(x)
            for w, j in zip(self.omega, self.momenta):
                if w:
                    f = f - w * (P @ fd.gradient(j, x, self.scale))
        return f

    def field_jacobian(self, x: np.ndarray) -> np.ndarray:
        """``∂(co-moving field)/∂x``: the system's own Jacobian where it has one (central
        differences of its field otherwise), minus ``Σ ω_k ∂(P ∇J_k)/∂x`` formed as
        ``(∂P·∇J_k) + P ∇²J_k`` (differences of differences would lose half the digits)."""
        if offers(self.system, HasJacobian):
            A = np.asarray(self.system.jacobian(0.0, x), dtype=float)
        else:
            A = fd.jacobian(lambda z: np.asarray(self.system.rhs(0.0, z), dtype=float), x,
                            self.scale)
        if self.momenta and np.any(self.omega):
            P = self.poisson(x)
            for w, j in zip(self.omega, self.momenta):
                if w:
                    g = fd.gradient(j, x, self.scale)
                    dP = fd.jacobian(lambda z, g=g: self.poisson(z) @ g, x, self.scale)
                    A = A - w * (dP + P @ fd.hessian(j, x, self.scale))
        return A

    def conserved_gradients(self, x: np.ndarray) -> np.ndarray:
        """Columns ``∇C_i`` then ``∇J_k`` at ``x`` (shape ``(dim, k + q)``)."""
        cols = [fd.gradient(lambda z, i=i: float(self.casimirs(z)[i]), x, self.scale)
                for i in range(self.casimirs(x).size)]
        cols += [fd.gradient(j, x, self.scale) for j in self.momenta]
        return np.column_stack(cols) if cols else np.zeros((self.dim, 0))

    def conserved_hessians(self, x: np.ndarray) -> list[np.ndarray]:
        """Hessians of ``C_i`` then ``J_k`` (the order of :meth:`conserved_gradients`)."""
        out = [fd.hessian(lambda z, i=i: float(self.casimirs(z)[i]), x, self.scale)
               for i in range(self.casimirs(x).size)]
        return out + [fd.hessian(j, x, self.scale) for j in self.momenta]


def as_problem(system: NumericsSystem, momenta: Sequence[Momentum] = (),
               omega: Sequence[float] | float | None = None, *, state: np.ndarray,
               scale: ArrayLike | None = None) -> EquilibriumProblem:
    """Build an :class:`EquilibriumProblem` (checks the inputs); ``scale`` defaults to the
    :func:`~poissonkit.numerics.equilibria.differences.typical_scales` of ``state``."""
    if not offers(system, NumericsSystem):
        raise InputError(f"needs a numerics system (rhs, energy, dim), got {type(system).__name__}")
    x = np.asarray(state, dtype=float)
    if x.shape != (system.dim,):
        raise DimensionError(f"state has shape {x.shape}, expected ({system.dim},)")
    if not np.all(np.isfinite(x)):
        raise InputError("state contains non-finite values")
    if scale is None:
        layout = tuple(system.layout) if offers(system, HasLayout) else None
        scale = fd.typical_scales(x, layout)
    return EquilibriumProblem(system, tuple(momenta),
                              None if omega is None else np.asarray(omega, dtype=float),
                              np.broadcast_to(np.asarray(scale, dtype=float), x.shape).copy())


__all__ = ["EquilibriumProblem", "Momentum", "as_problem"]
