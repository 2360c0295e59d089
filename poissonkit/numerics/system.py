"""``compile_system``: any symbolic (conformally) Hamiltonian system → compiled numerics.

``X = N P dH`` is built once with sympy, parameters are substituted, common subexpressions are
eliminated and numba code is generated for the right-hand side, its Jacobian, the energy and
the claimed Casimirs / integrals. Works for every bracket of :mod:`poissonkit.structure`,
including deformed brackets and multipliers ``N ≠ 1``.
"""

from __future__ import annotations

import math
from typing import Any

import numba
import numpy as np
import sympy as sp

from poissonkit.errors import DimensionError, InputError
from poissonkit.numerics.codegen import array_source, check_free_symbols, compile_source
from poissonkit.numerics.kernels import Kernels, no_drift


@numba.njit(error_model="numpy")
def _no_kick(y, h, data, work):
    return


@numba.njit(error_model="numpy")
def _no_distance(y, data, work):
    return np.inf


@numba.njit(error_model="numpy")
def _no_radius(y, data):
    return 0.0


def _parameter_value(name: str, value: Any) -> float:
    """``float(value)`` of parameter ``name``; :class:`InputError` unless a finite number.

    Checked before substitution because sympy turns ``Float(nan) * x**2`` into ``nan``, whose
    derivative is 0, which would silently zero the right-hand side.
    """
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"parameter {name!r} must be a number, got {value!r}") from None
    if not math.isfinite(v):
        raise InputError(f"parameter {name!r} must be finite, got {value!r}")
    return v


class CompiledSystem:
    """Compiled form of a :class:`~poissonkit.structure.HamiltonianSystem`.

    Attributes
    ----------
    layout
        Coordinate names in state order.
    source
        The generated right-hand-side source (documents the state and parameter order).
    """

    def __init__(self, hsys: Any, params: dict[str, Any] | None = None) -> None:
        from poissonkit.structure import HamiltonianSystem

        if not isinstance(hsys, HamiltonianSystem):
            raise InputError(f"compile_system needs a HamiltonianSystem, got {type(hsys).__name__}")
        self.hamiltonian_system = hsys
        coords = tuple(hsys.coords)
        values = dict(hsys.params)
        values.update(params or {})
        subs = {}
        for expr in [hsys.hamiltonian, hsys.multiplier, *hsys.structure.matrix]:
            for s in sp.sympify(expr).free_symbols:
                if s not in coords and s.name in values:
                    subs[s] = sp.Float(_parameter_value(s.name, values[s.name]), 30)

        def prep(e: Any) -> sp.Expr:
            return sp.sympify(e).xreplace(subs)

        H = prep(hsys.hamiltonian)
        P = hsys.structure.matrix.xreplace(subs)
        N = prep(hsys.multiplier)
        dH = [sp.diff(H, x) for x in coords]
        n = len(coords)
        X = [N * sum(P[i, j] * dH[j] for j in range(n) if P[i, j] != 0) for i in range(n)]
        what = f"system {hsys.name or 'unnamed'}"
        check_free_symbols(X + [H], coords, what)
        self._X = X
        self._coords = coords
        self.layout = tuple(str(c) for c in coords)
        self.dim = n
        self.casimir_names = tuple(hsys.casimirs)
        self.integral_names = tuple(hsys.integrals)
        cas = [prep(e) for e in hsys.casimirs.values()]
        ints = [prep(e) for e in hsys.integrals.values()]
        check_free_symbols(cas + ints, coords, what + " invariants")
        self.source = array_source("rhs_gen", coords, X, (n,))
        rhs_gen = compile_source(self.source, "rhs_gen")
        en_gen = compile_source(array_source("energy_gen", coords, [H], (1,)), "energy_gen")
        self._cas = compile_source(array_source("cas_gen", coords, cas or [sp.Integer(0)],
                                                (max(len(cas), 1),)), "cas_gen")
        self._int = compile_source(array_source("int_gen", coords, ints or [sp.Integer(0)],
                                                (max(len(ints), 1),)), "int_gen")

        @numba.njit(error_model="numpy")
        def rhs(y, data, work, out):
            rhs_gen(y, out)

        @numba.njit(error_model="numpy")
        def energy(y, data, work):
            return en_gen(y, work[0])[0]

        self._rhs = rhs
        self._energy = energy
        self._kernels: Kernels | None = None
        self.data = (0.0,)

    @property
    def kernels(self) -> Kernels:
        """Compiled kernels; the Jacobian is differentiated and generated on first access."""
        if self._kernels is None:
            n = self.dim
            Jm = [sp.diff(self._X[i], self._coords[j]) for i in range(n) for j in range(n)]
            jac_gen = compile_source(array_source("jac_gen", self._coords, Jm, (n, n)), "jac_gen")

            @numba.njit(error_model="numpy")
            def jac(y, data, work, out):
                jac_gen(y, out)

            self._kernels = Kernels(rhs=self._rhs, drift=no_drift, kick=_no_kick,
                                    energy=self._energy, min_distance=_no_distance,
                                    max_radius=_no_radius, jac=jac, splittable=False)
        return self._kernels

    def work(self) -> tuple[np.ndarray, ...]:
        """Scratch arrays for the kernels."""
        return (np.zeros(1),)

    def _state(self, y: Any) -> np.ndarray:
        y = np.asarray(y, dtype=float)
        if y.shape != (self.dim,):
            raise DimensionError(f"state has shape {y.shape}, expected ({self.dim},)")
        return np.ascontiguousarray(y)

    def rhs(self, t: float, y: Any) -> np.ndarray:
        """``ẏ = N P dH`` at ``y``."""
        out = np.empty(self.dim)
        self._rhs(self._state(y), self.data, self.work(), out)
        return out

    def jacobian(self, t: float, y: Any) -> np.ndarray:
        """``∂ẏ/∂y`` at ``y``, shape ``(dim, dim)``."""
        out = np.empty((self.dim, self.dim))
        self.kernels.jac(self._state(y), self.data, self.work(), out)
        return out

    def energy(self, y: Any) -> float | np.ndarray:
        """``H(y)`` (rows of a 2-D array give one value each)."""
        y = np.asarray(y, dtype=float)
        if y.ndim == 2:
            return np.array([self.energy(row) for row in y])
        return float(self._energy(self._state(y), self.data, self.work()))

    def casimirs(self, y: Any) -> np.ndarray:
        """Values of the system's claimed Casimirs (in ``casimir_names`` order)."""
        y = np.asarray(y, dtype=float)
        if y.ndim == 2:
            return np.array([self.casimirs(row) for row in y]).reshape(len(y), -1)
        out = np.empty(max(len(self.casimir_names), 1))
        self._cas(self._state(y), out)
        return out[:len(self.casimir_names)]

    def integrals(self, y: Any) -> np.ndarray:
        """Values of the claimed first integrals (in ``integral_names`` order)."""
        y = np.asarray(y, dtype=float)
        if y.ndim == 2:
            return np.array([self.integrals(row) for row in y]).reshape(len(y), -1)
        out = np.empty(max(len(self.integral_names), 1))
        self._int(self._state(y), out)
        return out[:len(self.integral_names)]

    def __repr__(self) -> str:
        return f"CompiledSystem({self.hamiltonian_system.name or 'unnamed'}, dim={self.dim})"


_compiled: dict[tuple, CompiledSystem] = {}


def compile_system(hsys: Any, params: dict[str, Any] | None = None) -> CompiledSystem:
    """Compile a :class:`~poissonkit.structure.HamiltonianSystem` (see :class:`CompiledSystem`).

    Parameters
    ----------
    hsys
        The symbolic system; its ``params`` (and ``params`` here, which take precedence) give
        values to every non-coordinate symbol.
    params
        Extra / overriding parameter values by symbol name.

    Raises
    ------
    InputError
        If a symbol has no value or the system uses undefined functions.
    """
    try:
        key = (sp.srepr(hsys.structure.matrix), sp.srepr(sp.sympify(hsys.hamiltonian)),
               sp.srepr(sp.sympify(hsys.multiplier)), tuple(map(str, hsys.coords)),
               tuple(sorted((k, sp.srepr(v)) for k, v in hsys.casimirs.items())),
               tuple(sorted((k, sp.srepr(v)) for k, v in hsys.integrals.items())),
               tuple(sorted((str(k), repr(v)) for k, v in {**hsys.params, **(params or {})}.items())))
    except AttributeError:
        return CompiledSystem(hsys, params)
    hit = _compiled.get(key)
    if hit is None or hit.hamiltonian_system.name != hsys.name:
        hit = CompiledSystem(hsys, params)
        _compiled[key] = hit
    return hit


__all__ = ["CompiledSystem", "compile_system", "math"]
