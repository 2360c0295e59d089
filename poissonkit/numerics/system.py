"""``compile_system``: any symbolic (conformally) Hamiltonian system → compiled numerics.

``X = N P dH`` is built once with sympy, parameters are substituted, common subexpressions are
eliminated and numba code is generated for the right-hand side, its Jacobian, the energy and
the claimed Casimirs / integrals. Works for every bracket of :mod:`poissonkit.structure`,
including deformed brackets and multipliers ``N ≠ 1``.

Large fields (rational fields with square roots such as the Routh sphere's, whose ``P dH`` has
~10^5 tree nodes) take the large-expression path of :mod:`poissonkit.numerics.codegen`: plain
CSE, no expansion or simplification, and a Jacobian by differentiating the generated program.
With ``field="original"`` the system's own equations of motion (``hsys.original``) are compiled
instead of ``N P dH``, after a numerical check that both agree.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING, NamedTuple

import numpy as np
import sympy as sp
from numpy.typing import ArrayLike

from poissonkit import contracts
from poissonkit.contracts import CompiledFunction, SymbolicForm
from poissonkit.errors import DimensionError, InputError
from poissonkit.numerics.codegen import (array_source, check_free_symbols, compile_source, is_large,
                                         jacobian_source)
from poissonkit.numerics.jit import jit, load_sources, source_key, store_sources
from poissonkit.numerics.kernels import Kernels, no_drift
from poissonkit.traits import SystemTraits
from poissonkit.validation import finite_number

if TYPE_CHECKING:
    from poissonkit.structure import HamiltonianSystem


@jit
def _no_kick(y, h, data, work):
    return


@jit
def _no_distance(y, data, work):
    return np.inf


@jit
def _no_radius(y, data):
    return 0.0


def _parameter_value(name: str, value: object) -> float:
    """``float(value)`` of parameter ``name``; :class:`InputError` unless a finite number.

    Checked before substitution because sympy turns ``Float(nan) * x**2`` into ``nan``, whose
    derivative is 0, which would silently zero the right-hand side.
    """
    return finite_number(value, f"parameter {name!r}")


class GeneratedWork(NamedTuple):
    """Scratch of a generated system's kernels."""

    #: the one-entry output of the generated energy
    buffer: np.ndarray


class CompiledSystem:
    """Compiled form of a :class:`~poissonkit.structure.HamiltonianSystem`.

    Attributes
    ----------
    layout
        Coordinate names in state order.
    source
        The generated right-hand-side source (documents the state and parameter order).
    field
        ``"bivector"`` (``X = N P dH``) or ``"original"`` (``hsys.original``), see
        :func:`compile_system`.
    """

    #: the contracts this class fulfils, declared once (:mod:`poissonkit.traits`)
    traits = SystemTraits(contracts.NumericsSystem, contracts.HasCompiledKernels,
                          contracts.HasLayout, contracts.HasCasimirs, contracts.HasIntegrals,
                          contracts.HasEnergy, contracts.CompiledFrom,
                          contracts.HasSymbolicForm, contracts.HasJacobian)

    def __init__(self, hsys: HamiltonianSystem, params: Mapping[str, object] | None = None,
                 field: str = "bivector") -> None:
        from poissonkit.structure import HamiltonianSystem

        if not isinstance(hsys, HamiltonianSystem):
            raise InputError(f"compile_system needs a HamiltonianSystem, got {type(hsys).__name__}")
        if field not in ("bivector", "original"):
            raise InputError(f"field must be 'bivector' or 'original', got {field!r}")
        if field == "original" and not hsys.original:
            raise InputError(f"field='original': system {hsys.name or 'unnamed'} has no original "
                             "equations of motion")
        self.hamiltonian_system = hsys
        coords = tuple(hsys.coords)
        values = dict(hsys.params)
        values.update(params or {})
        subs = {}
        original = list(hsys.original.values()) if field == "original" else []
        for expr in [hsys.hamiltonian, hsys.multiplier, *hsys.structure.matrix, *original]:
            for s in sp.sympify(expr).free_symbols:
                if s not in coords and s.name in values:
                    subs[s] = sp.Float(_parameter_value(s.name, values[s.name]), 30)

        def prep(e: object) -> sp.Expr:
            return sp.sympify(e).xreplace(subs)

        self._prep = prep
        self._subs = subs
        self._original = original
        self._what = f"system {hsys.name or 'unnamed'}"
        self._coords = coords
        self._X: list[sp.Expr] | None = None
        self.field = field
        self.layout = tuple(str(c) for c in coords)
        self.dim = len(coords)
        self.casimir_names = tuple(hsys.casimirs)
        self.integral_names = tuple(hsys.integrals)
        cas = [prep(e) for e in hsys.casimirs.values()]
        ints = [prep(e) for e in hsys.integrals.values()]
        check_free_symbols(cas + ints, coords, self._what + " invariants")
        # generated sources are kept on disk under a hash of everything they follow from, so a
        # second process skips the symbolic work (differentiation, CSE) as well as numba's
        self._key = source_key(sp.srepr((tuple(coords), prep(hsys.hamiltonian),
                                         prep(hsys.multiplier),
                                         sp.ImmutableMatrix(hsys.structure.matrix.xreplace(subs)),
                                         tuple(prep(e) for e in original),
                                         tuple(cas), tuple(ints))), field)
        sources = load_sources(self._key)
        if sources is None:
            X = self._field()
            n = self.dim
            large = is_large(X)
            sources = {
                "large": "1" if large else "0",
                "rhs_gen": array_source("rhs_gen", coords, X, (n,), large=large),
                "energy_gen": array_source("energy_gen", coords, [prep(hsys.hamiltonian)], (1,)),
                "cas_gen": array_source("cas_gen", coords, cas or [sp.Integer(0)],
                                        (max(len(cas), 1),)),
                "int_gen": array_source("int_gen", coords, ints or [sp.Integer(0)],
                                        (max(len(ints), 1),)),
            }
            store_sources(self._key, sources)
        self._large = sources["large"] == "1"
        self.source = sources["rhs_gen"]
        rhs_gen = compile_source(self.source, "rhs_gen")
        en_gen = compile_source(sources["energy_gen"], "energy_gen")
        self._cas = compile_source(sources["cas_gen"], "cas_gen")
        self._int = compile_source(sources["int_gen"], "int_gen")

        @jit
        def rhs(y, data, work, out):
            rhs_gen(y, out)

        @jit
        def energy(y, data, work):
            return en_gen(y, work.buffer)[0]

        self._rhs = rhs
        self._energy = energy
        self._kernels: Kernels | None = None
        self.data = (0.0,)

    @property
    def kernels(self) -> Kernels:
        """Compiled kernels; the Jacobian is differentiated and generated on first access."""
        if self._kernels is None:
            # small fields: symbolic derivatives + CSE (as always); large ones: forward-mode
            # differentiation of the CSE program (linear in its length)
            key = self._key + "-jacobian"
            stored = load_sources(key)
            if stored is None:
                stored = {"jac_gen": jacobian_source("jac_gen", self._coords, self._field(),
                                                     large=self._large)}
                store_sources(key, stored)
            jac_gen = compile_source(stored["jac_gen"], "jac_gen")

            @jit
            def jac(y, data, work, out):
                jac_gen(y, out)

            self._kernels = Kernels(rhs=self._rhs, drift=no_drift, kick=_no_kick,
                                    energy=self._energy, min_distance=_no_distance,
                                    max_radius=_no_radius, jac=jac, splittable=False)
        return self._kernels

    def _field(self) -> list[sp.Expr]:
        """The vector field ``X`` (symbolic; built on first use and checked)."""
        if self._X is None:
            hsys, prep, coords = self.hamiltonian_system, self._prep, self._coords
            H = prep(hsys.hamiltonian)
            P = hsys.structure.matrix.xreplace(self._subs)
            N = prep(hsys.multiplier)
            dH = [sp.diff(H, x) for x in coords]
            n = len(coords)
            if self.field == "original":
                X = _original_field(hsys, coords, prep, self._what)
                _check_same_field(X, N, P, dH, coords, self._what)
            else:
                X = [N * sum(P[i, j] * dH[j] for j in range(n) if P[i, j] != 0)
                     for i in range(n)]
            check_free_symbols(X + [H], coords, self._what)
            self._X = X
        return self._X

    def symbolic_form(self) -> SymbolicForm:
        """``(coords, H, N, P, key)`` with this system's parameter values substituted (see
        :class:`SymbolicForm`); for integrators that need ``P`` and ``∇H`` separately."""
        hsys = self.hamiltonian_system
        return SymbolicForm(self._coords, self._prep(hsys.hamiltonian),
                            self._prep(hsys.multiplier),
                            hsys.structure.matrix.xreplace(self._subs), self._key)

    def work(self) -> GeneratedWork:
        """Scratch arrays for the kernels."""
        return GeneratedWork(np.zeros(1))

    def _state(self, y: ArrayLike) -> np.ndarray:
        y = np.asarray(y, dtype=float)
        if y.shape != (self.dim,):
            raise DimensionError(f"state has shape {y.shape}, expected ({self.dim},)")
        return np.ascontiguousarray(y)

    def rhs(self, t: float, y: ArrayLike) -> np.ndarray:
        """``ẏ = N P dH`` at ``y``."""
        out = np.empty(self.dim)
        self._rhs(self._state(y), self.data, self.work(), out)
        return out

    def jacobian(self, t: float, y: ArrayLike) -> np.ndarray:
        """``∂ẏ/∂y`` at ``y``, shape ``(dim, dim)``."""
        out = np.empty((self.dim, self.dim))
        self.kernels.jac(self._state(y), self.data, self.work(), out)
        return out

    def energy(self, y: ArrayLike) -> float | np.ndarray:
        """``H(y)`` (rows of a 2-D array give one value each)."""
        y = np.asarray(y, dtype=float)
        if y.ndim == 2:
            return np.array([self.energy(row) for row in y])
        return float(self._energy(self._state(y), self.data, self.work()))

    def casimirs(self, y: ArrayLike) -> np.ndarray:
        """Values of the system's claimed Casimirs (in ``casimir_names`` order)."""
        return self._columns(self._cas, len(self.casimir_names), y)

    def integrals(self, y: ArrayLike) -> np.ndarray:
        """Values of the claimed first integrals (in ``integral_names`` order)."""
        return self._columns(self._int, len(self.integral_names), y)

    def _columns(self, kernel: CompiledFunction, n: int, y: ArrayLike) -> np.ndarray:
        """``n`` values of a compiled ``kernel(y, out)`` at one state, or a row per state."""
        y = np.asarray(y, dtype=float)
        if y.ndim == 2:
            return np.array([self._columns(kernel, n, row) for row in y]).reshape(len(y), -1)
        out = np.empty(max(n, 1))
        kernel(self._state(y), out)
        return out[:n]

    def __repr__(self) -> str:
        return f"CompiledSystem({self.hamiltonian_system.name or 'unnamed'}, dim={self.dim})"


def _original_field(hsys: HamiltonianSystem, coords: tuple[sp.Symbol, ...],
                    prep: Callable[[object], sp.Expr], what: str) -> list[sp.Expr]:
    """``hsys.original`` in coordinate order, parameters substituted."""
    missing = [str(c) for c in coords if c not in hsys.original]
    if missing:
        raise InputError(f"field='original': {what} gives no equation for {', '.join(missing)}")
    return [prep(hsys.original[c]) for c in coords]


def _check_same_field(X: list[sp.Expr], N: sp.Expr, P: sp.Matrix, dH: list[sp.Expr],
                      coords: tuple, what: str, points: int = 3, seed: int = 20261122) -> None:
    """Check ``X = N P dH`` at a few random states in 30-digit arithmetic.

    ``P``, ``dH`` and ``N`` are evaluated separately and multiplied numerically (never the
    expanded ``P dH``, which is what makes the symbolic route slow). States where either side is
    undefined are skipped; if no state could be used the check is skipped too (the field is the
    user's declaration), but a disagreement raises.

    Raises
    ------
    InputError
        If ``X`` differs from ``N P dH`` (relative difference above ``1e-12``).
    """
    rng = np.random.default_rng(seed)
    n = len(coords)
    pairs = [(i, j) for i in range(n) for j in range(n) if P[i, j] != 0]
    exprs = [*X, *dH, *(P[i, j] for i, j in pairs), sp.sympify(N)]
    used = 0
    for _ in range(4 * points):
        if used == points:
            break
        point = {c: sp.Float(float(v), 30) for c, v in zip(coords, rng.uniform(-1.0, 1.0, n))}
        try:
            vals = [complex(v.evalf(30)) for v in _evaluate(exprs, point)]
        except (TypeError, ValueError, ZeroDivisionError):
            continue  # undefined there (zoo, nan): another state
        lhs, dh, nv = vals[:n], vals[n:2 * n], vals[-1]
        Pn = [[0j] * n for _ in range(n)]
        for (i, j), v in zip(pairs, vals[2 * n:-1]):
            Pn[i][j] = v
        rhs = [nv * sum(Pn[i][j] * dh[j] for j in range(n)) for i in range(n)]
        vals = lhs + rhs
        if not all(math.isfinite(v.real) and math.isfinite(v.imag) and abs(v.imag) < 1e-20
                   for v in vals):
            continue
        scale = max(1.0, *(abs(v) for v in vals))
        worst = max(abs(a - b) for a, b in zip(lhs, rhs))
        if worst > 1e-12 * scale:
            raise InputError(f"field='original': the original equations of {what} differ from "
                             f"N P dH by {worst:.3g} at {[float(v) for v in point.values()]}")
        used += 1


def _evaluate(exprs: list[sp.Expr], point: dict[sp.Symbol, sp.Expr]) -> list[sp.Expr]:
    """``exprs`` at ``point``, each distinct subtree rebuilt (hence evaluated) once.

    ``xreplace`` walks shared subtrees again at every occurrence, which is what makes the
    Routh sphere's ``P`` slow to evaluate; this walk is linear in the number of distinct nodes.
    """
    memo: dict[sp.Basic, sp.Basic] = dict(point)
    for e in exprs:
        stack = [e]
        while stack:  # iterative post-order over the DAG
            top = stack[-1]
            if top in memo:
                stack.pop()
                continue
            if not top.args:
                memo[top] = top
                stack.pop()
                continue
            pending = [a for a in top.args if a not in memo]
            if pending:
                stack.extend(pending)
                continue
            stack.pop()
            memo[top] = top.func(*(memo[a] for a in top.args))
    return [memo[e] for e in exprs]


_compiled: dict[tuple[object, ...], CompiledSystem] = {}


def compile_system(hsys: HamiltonianSystem, params: Mapping[str, object] | None = None,
                   field: str = "bivector") -> CompiledSystem:
    """Compile a :class:`~poissonkit.structure.HamiltonianSystem` (see :class:`CompiledSystem`).

    Parameters
    ----------
    hsys
        The symbolic system; its ``params`` (and ``params`` here, which take precedence) give
        values to every non-coordinate symbol.
    params
        Extra / overriding parameter values by symbol name.
    field
        ``"bivector"`` (default): the right-hand side is ``X = N P dH``. ``"original"``: compile
        the system's own equations of motion ``hsys.original`` instead (often a much smaller
        expression than the expanded ``P dH``: the Routh sphere's field is computed from
        ``omega(M, gamma)`` in a few dozen temporaries); they are first checked to agree with
        ``N P dH`` at random states, so the dynamics is the same.

    Raises
    ------
    InputError
        If a symbol has no value, the system uses undefined functions, ``field`` is unknown, or
        ``field="original"`` and the system has no (or a different) original field.

    Notes
    -----
    Large expressions (more than :data:`poissonkit.numerics.codegen.LARGE_TREE` tree nodes)
    are compiled without sympy's CSE pre-optimisation and get their Jacobian by differentiating
    the generated program, so the Routh sphere compiles in seconds (docs/numerics.md).
    """
    from poissonkit.structure import HamiltonianSystem

    if not isinstance(hsys, HamiltonianSystem):
        return CompiledSystem(hsys, params, field)  # raises the typed error
    # sympy objects compare structurally (assumptions included) and cache their hashes;
    # srepr strings of a large field took seconds to print
    key: tuple[object, ...] = (
        sp.ImmutableMatrix(hsys.structure.matrix), sp.sympify(hsys.hamiltonian),
        sp.sympify(hsys.multiplier), tuple(hsys.coords), tuple(map(str, hsys.coords)),
        tuple(sorted(hsys.casimirs.items())),
        tuple(sorted(hsys.integrals.items())),
        tuple(sorted((str(k), repr(v)) for k, v in {**hsys.params, **(params or {})}.items())))
    if field == "original" and hsys.original:
        key += (tuple(hsys.original.items()),)
    key += (field,)
    hit = _compiled.get(key)
    if hit is None or hit.hamiltonian_system.name != hsys.name:
        hit = CompiledSystem(hsys, params, field)
        _compiled[key] = hit
    return hit


__all__ = ["CompiledSystem", "SymbolicForm", "compile_system", "math"]
