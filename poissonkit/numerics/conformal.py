"""Conformally Hamiltonian systems in physical time, through a time change.

A conformally Hamiltonian field ``X = N(x) P dH`` (survey eq. (7)) with ``N = sigma c(x)``,
``sigma = ±1`` constant and ``c > 0``, becomes Hamiltonian after the time change
``dtau = c(x) dt``:

    dx/dtau = sigma P dH,        dt/dtau = 1 / c(x).

For the Chaplygin ball ``N = -1/g``: ``sigma = -1``, ``c = 1/g`` and ``dt = g dtau`` (the survey's
time change). The ``tau`` system is integrated with a Poisson-structure-friendly method (by
default the implicit midpoint rule, which keeps every quadratic Casimir such as
``(gamma, gamma)``, ``(gamma, M)`` to round-off and the energy to ``O(h^2)`` without drift) and
the clock ``t(tau)`` is integrated alongside with the same midpoint rule
(``t_{n+1} = t_n + h / c((x_n + x_{n+1})/2)``, i.e. implicit midpoint on the augmented system
``(x, t)``). The state at the requested physical time is obtained by cubic Hermite
interpolation in ``tau``.

:func:`solve_direct` integrates ``X`` itself in physical time with any registered integrator,
for comparison.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Union

import numpy as np
import sympy as sp
from numpy.typing import ArrayLike

from poissonkit import contracts
from poissonkit.errors import InputError, IntegrationError
from poissonkit.traits import SystemTraits

if TYPE_CHECKING:
    from poissonkit.numerics.solution import Solution
    from poissonkit.numerics.system import CompiledSystem
    from poissonkit.structure import HamiltonianSystem

__all__ = ["ConformalIntegrator", "ConformalSolution", "LambdifiedSystem", "invariant_drift",
           "midpoint_python", "solve_conformal", "solve_direct", "time_change"]


def _values(hsys: HamiltonianSystem) -> dict[sp.Symbol, sp.Expr]:
    """Substitution of the system's numeric parameters (by symbol name)."""
    out: dict[sp.Symbol, sp.Expr] = {}
    exprs = [hsys.hamiltonian, hsys.multiplier, *hsys.structure.matrix]
    for expr in exprs:
        for s in sp.sympify(expr).free_symbols:
            if s not in hsys.coords and s.name in hsys.params:
                out[s] = sp.Float(float(hsys.params[s.name]), 30)
    return out


def time_change(hsys: HamiltonianSystem, y0: ArrayLike) -> tuple[int, sp.Expr]:
    """Split ``N = sigma c`` with ``c > 0`` at ``y0``; return ``(sigma, 1/c)`` (``dt/dtau``).

    Raises
    ------
    InputError
        If ``N(y0)`` is zero or not finite (the time change is singular there).
    """
    N = sp.sympify(hsys.multiplier).xreplace(_values(hsys))
    point = dict(zip(hsys.coords, np.asarray(y0, dtype=float)))
    value = complex(N.xreplace({k: sp.Float(v) for k, v in point.items()}).evalf())
    if not (math.isfinite(value.real) and abs(value.imag) < 1e-12 and value.real != 0):
        raise InputError(f"multiplier N = {N} is {value} at y0: the time change is singular")
    sigma = 1 if value.real > 0 else -1
    return sigma, sp.simplify(1 / (sigma * N)) if N.count_ops() < 40 else 1 / (sigma * N)


@dataclass
class ConformalSolution:
    """A run of :class:`ConformalIntegrator`.

    Attributes
    ----------
    t
        Physical times of the saved states (non-uniform), ending exactly at ``t_end``.
    tau
        The Hamiltonian time of the same states.
    y
        States, shape ``(n, dim)``.
    sigma
        Sign of the multiplier (``dx/dtau = sigma P dH``).
    steps, wall_time
        Steps in ``tau`` and seconds spent integrating.
    compiled
        The compiled ``tau`` system (its ``energy``, ``casimirs`` and ``integrals`` evaluate the
        invariants).
    """

    t: np.ndarray
    tau: np.ndarray
    y: np.ndarray
    sigma: int
    steps: int
    wall_time: float
    compiled: InvariantSystem
    method: str = "midpoint"
    extra: dict[str, object] = field(default_factory=dict)

    @property
    def y_final(self) -> np.ndarray:
        """State at ``t_end``."""
        return self.y[-1]

    def invariant_drift(self) -> dict[str, float]:
        """Largest absolute change of ``H``, each Casimir and each integral over the integrator's
        own steps (the last state, interpolated to ``t_end``, is excluded: interpolation does not
        preserve the Casimirs exactly)."""
        return invariant_drift(self.compiled, self.y[:-1])


def invariant_drift(compiled: InvariantSystem, y: np.ndarray) -> dict[str, float]:
    """``max_t |F(y(t)) - F(y(0))|`` for ``H`` and every Casimir and integral of ``compiled``."""
    out = {"H": float(np.max(np.abs(compiled.energy(y) - compiled.energy(y[0]))))}
    if compiled.casimir_names:
        c = compiled.casimirs(y)
        for k, name in enumerate(compiled.casimir_names):
            out[name] = float(np.max(np.abs(c[:, k] - c[0, k])))
    if compiled.integral_names:
        f = compiled.integrals(y)
        for k, name in enumerate(compiled.integral_names):
            out[name] = float(np.max(np.abs(f[:, k] - f[0, k])))
    return out


class LambdifiedSystem:
    """A light, numpy-only stand-in for :class:`~poissonkit.numerics.system.CompiledSystem`.

    ``sympy.lambdify`` with common-subexpression elimination: builds in about a second (no numba
    compilation), evaluates one state in tens of microseconds. Used by the ``"python"`` backend
    (tests, quick looks); the compiled path is faster for long runs.
    """

    #: the contracts this class fulfils, declared once (:mod:`poissonkit.traits`)
    traits = SystemTraits(contracts.NumericsSystem, contracts.HasLayout, contracts.HasCasimirs,
                          contracts.HasIntegrals, contracts.HasEnergy)

    def __init__(self, hsys: HamiltonianSystem) -> None:
        vals = _values(hsys)
        coords = hsys.coords
        P = hsys.structure.matrix.xreplace(vals)
        H = sp.sympify(hsys.hamiltonian).xreplace(vals)
        N = sp.sympify(hsys.multiplier).xreplace(vals)
        dH = [sp.diff(H, x) for x in coords]
        n = len(coords)
        X = [N * sum((P[i, j] * dH[j] for j in range(n) if P[i, j] != 0), sp.Integer(0))
             for i in range(n)]
        self.dim = n
        self.layout = tuple(map(str, coords))
        self._f = sp.lambdify([coords], X, modules="math", cse=True)
        self._H = sp.lambdify([coords], H, modules="numpy", cse=True)
        self.casimir_names = tuple(hsys.casimirs)
        self.integral_names = tuple(hsys.integrals)
        cas = [sp.sympify(e).xreplace(vals) for e in hsys.casimirs.values()]
        ints = [sp.sympify(e).xreplace(vals) for e in hsys.integrals.values()]
        self._C = [sp.lambdify([coords], e, modules="numpy", cse=True) for e in cas]
        self._I = [sp.lambdify([coords], e, modules="numpy", cse=True) for e in ints]

    def rhs(self, t: float, y: ArrayLike) -> np.ndarray:
        """The field at ``y``.

        Raises
        ------
        IntegrationError
            If the field is undefined at ``y`` (a square root of a negative number, a division
            by zero: the state left the physical domain, e.g. ``g^2 = 1 - d (gamma, A gamma) < 0``).
        """
        try:
            return np.array(self._f(tuple(np.asarray(y, dtype=float))), dtype=float)
        except (ValueError, ZeroDivisionError, OverflowError) as exc:
            raise IntegrationError(f"the field is undefined at the state {np.asarray(y)!r} "
                                   f"({exc}); it left the physical domain or the step is too "
                                   "large") from None

    @staticmethod
    def _rows(fun, y: np.ndarray) -> np.ndarray:
        y = np.atleast_2d(np.asarray(y, dtype=float))
        return np.broadcast_to(np.asarray(fun(y.T), dtype=float), (y.shape[0],)).copy()

    def energy(self, y: ArrayLike) -> np.ndarray:
        """``H`` at each row of ``y``."""
        return self._rows(self._H, y)

    def casimirs(self, y: ArrayLike) -> np.ndarray:
        """Casimirs at each row, shape ``(rows, k)``."""
        return np.stack([self._rows(f, y) for f in self._C], axis=1)

    def integrals(self, y: ArrayLike) -> np.ndarray:
        """Integrals at each row, shape ``(rows, k)``."""
        return np.stack([self._rows(f, y) for f in self._I], axis=1)


#: A system whose invariants :func:`invariant_drift` measures: compiled (numba) or lambdified.
InvariantSystem = Union["CompiledSystem", LambdifiedSystem]


@dataclass
class _Run:
    t: np.ndarray
    y: np.ndarray
    steps: int


def midpoint_python(system: LambdifiedSystem, y0: np.ndarray, span: float, step: float,
                    tol: float = 1e-14, max_iterations: int = 100) -> _Run:
    """Implicit midpoint with fixed-point iteration (numpy backend).

    Raises
    ------
    IntegrationError
        If the iteration does not converge (reduce the step) or the state is not finite.
    """
    n = max(1, int(math.ceil(span / step - 1e-12)))
    h = span / n
    ys = np.empty((n + 1, y0.size))
    ys[0] = y = np.array(y0, dtype=float)
    f = system.rhs
    for k in range(n):
        Y = y + h * f(0.0, y)
        for _ in range(max_iterations):
            Y_new = y + h * f(0.0, 0.5 * (y + Y))
            err = np.max(np.abs(Y_new - Y))
            Y = Y_new
            if err <= tol * (1.0 + np.max(np.abs(Y))):
                break
        else:
            raise IntegrationError(f"midpoint iteration did not converge at step {k}; reduce the step")
        if not np.all(np.isfinite(Y)):
            raise IntegrationError(f"non-finite state at step {k}")
        ys[k + 1] = y = Y
    return _Run(t=np.linspace(0.0, n * h, n + 1), y=ys, steps=n)


class ConformalIntegrator:
    """Compile once, integrate many times in physical time through ``dtau = |N| dt``.

    Parameters
    ----------
    hsys
        A :class:`~poissonkit.structure.HamiltonianSystem` with numeric parameters.
    y_ref
        A state at which the sign of ``N`` is read (``N`` must keep its sign along runs).
    method
        Integrator registry name for the ``tau`` system (default ``"midpoint"``).
    backend
        ``"compiled"`` (:func:`~poissonkit.numerics.system.compile_system` + the registered
        integrator; numba compilation takes tens of seconds once, runs are fast) or ``"python"``
        (:class:`LambdifiedSystem` + :func:`midpoint_python`; starts in about a second).
    field
        Compiled backend only: ``"bivector"`` (default) compiles the ``tau`` field
        ``sigma P dH``; ``"original"`` compiles ``(dt/dtau) X`` from the system's original
        equations ``X`` (checked to agree with ``sigma P dH``), usually far smaller than the
        expanded ``P dH`` (see :func:`~poissonkit.numerics.system.compile_system`).

    Examples
    --------
    >>> from poissonkit_nonholonomic.ball import chaplygin_ball
    >>> ci = ConformalIntegrator(chaplygin_ball(), [0, 0.6, 0.8, 1, -0.5, 0.2])  # doctest: +SKIP
    >>> sol = ci.solve([0, 0.6, 0.8, 1, -0.5, 0.2], t_end=10.0, step=0.01)  # doctest: +SKIP
    """

    def __init__(self, hsys: HamiltonianSystem, y_ref: ArrayLike, method: str = "midpoint",
                 backend: str = "compiled", field: str = "bivector") -> None:
        if backend not in ("compiled", "python"):
            raise InputError(f"backend must be 'compiled' or 'python', got {backend!r}")
        if field not in ("bivector", "original"):
            raise InputError(f"field must be 'bivector' or 'original', got {field!r}")
        if field == "original" and backend != "compiled":
            raise InputError("field='original' needs backend='compiled'")
        if backend == "python" and method != "midpoint":
            raise InputError("the python backend only provides method='midpoint'")
        self.hsys = hsys
        self.backend = backend
        self.sigma, clock = time_change(hsys, y_ref)
        tau_sys = replace(hsys, multiplier=sp.Integer(self.sigma))
        if backend == "compiled":
            from poissonkit.numerics.system import compile_system

            if field == "original" and hsys.original:
                # dx/dtau = (dt/dtau) dx/dt: the tau field from the original equations
                tau_sys = replace(tau_sys, original={k: v * clock for k, v in hsys.original.items()})
            self.compiled = compile_system(tau_sys, field=field)
        else:
            self.compiled = LambdifiedSystem(tau_sys)
        clock = sp.sympify(clock).xreplace(_values(hsys))
        self._clock = sp.lambdify([hsys.coords], clock, modules="numpy")
        self.clock_expr = clock
        self.method = method

    def clock(self, y: np.ndarray) -> np.ndarray:
        """``dt/dtau`` at the rows of ``y``."""
        y = np.atleast_2d(y)
        val = self._clock(y.T)
        return np.broadcast_to(np.asarray(val, dtype=float), (y.shape[0],)).copy()

    def _run(self, y0: np.ndarray, tau_span: float, step: float, tol: float | None
             ) -> _Run | Solution:
        if self.backend == "python":
            return midpoint_python(self.compiled, y0, tau_span, step, tol or 1e-14)
        from poissonkit.numerics.solver import solve

        return solve(self.compiled, y0, tau_span, method=self.method, step=step, tol=tol)

    def solve(self, y0: ArrayLike, t_end: float, step: float, tol: float | None = None,
              max_chunks: int = 50) -> ConformalSolution:
        """Integrate from ``t = 0`` to ``t_end`` (physical time) with ``tau``-step ``step``.

        Raises
        ------
        InputError
            On a non-positive ``t_end`` or ``step``.
        IntegrationError
            If the clock does not reach ``t_end`` (``N`` changes sign or blows up).
        """
        if not (math.isfinite(t_end) and t_end > 0):
            raise InputError(f"t_end must be positive and finite, got {t_end!r}")
        if not (math.isfinite(step) and step > 0):
            raise InputError(f"step must be positive and finite, got {step!r}")
        y = np.array(y0, dtype=float)
        taus, ts, ys = [np.zeros(1)], [np.zeros(1)], [y[None, :]]
        tau0 = t0 = 0.0
        steps = 0
        start = time.perf_counter()
        for _ in range(max_chunks):
            rate = float(self.clock(y)[0])  # dt/dtau at the chunk start
            if not (math.isfinite(rate) and rate > 0):
                raise IntegrationError(f"clock dt/dtau = {rate} is not positive: N changed sign")
            span = max((t_end - t0) / rate * 1.05, 2 * step)
            n = max(1, int(math.ceil(span / step)))
            sol = self._run(y, n * step, step, tol)
            tau_c = sol.t + tau0
            yc = sol.y
            mid = 0.5 * (yc[1:] + yc[:-1])
            rates = self.clock(mid)
            if not np.all(np.isfinite(rates) & (rates > 0)):
                bad = int(np.argmax(~(np.isfinite(rates) & (rates > 0))))
                raise IntegrationError(
                    f"the clock dt/dtau = 1/|N| is {rates[bad]:.3g} near tau = {tau0 + sol.t[bad]:.6g}: "
                    "N changes sign or blows up there; integrate directly (solve_direct)")
            t_c = t0 + np.concatenate([[0.0], np.cumsum(np.diff(sol.t) * rates)])
            steps += sol.steps
            taus.append(tau_c[1:])
            ts.append(t_c[1:])
            ys.append(yc[1:])
            tau0, t0, y = float(tau_c[-1]), float(t_c[-1]), yc[-1]
            if t0 >= t_end:
                break
        else:
            raise IntegrationError(f"the clock reached t = {t0:.6g} < t_end = {t_end} in "
                                   f"{max_chunks} chunks")
        tau = np.concatenate(taus)
        t = np.concatenate(ts)
        Y = np.concatenate(ys)
        k = int(np.searchsorted(t, t_end))  # t[k-1] < t_end <= t[k]
        # tau at t_end: linear in t inside the step (t is monotone and smooth in tau), then a
        # cubic Hermite interpolant of x(tau) using the tau field at both ends
        frac = (t_end - t[k - 1]) / (t[k] - t[k - 1])
        h = tau[k] - tau[k - 1]
        s = frac
        f0 = self.compiled.rhs(0.0, Y[k - 1])
        f1 = self.compiled.rhs(0.0, Y[k])
        h00, h10 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s
        h01, h11 = -2 * s**3 + 3 * s**2, s**3 - s**2
        y_end = h00 * Y[k - 1] + h10 * h * f0 + h01 * Y[k] + h11 * h * f1
        wall = time.perf_counter() - start
        return ConformalSolution(
            t=np.concatenate([t[:k], [t_end]]), tau=np.concatenate([tau[:k], [tau[k - 1] + s * h]]),
            y=np.vstack([Y[:k], y_end]), sigma=self.sigma, steps=steps, wall_time=wall,
            compiled=self.compiled, method=self.method)


def solve_conformal(hsys: HamiltonianSystem, y0: ArrayLike, t_end: float, step: float, method: str = "midpoint",
                    tol: float | None = None, backend: str = "compiled",
                    field: str = "bivector") -> ConformalSolution:
    """One-shot :class:`ConformalIntegrator` run (compiles every call; reuse the class in loops)."""
    return ConformalIntegrator(hsys, y0, method, backend, field).solve(y0, t_end, step, tol)


def solve_direct(hsys: HamiltonianSystem, y0: ArrayLike, t_end: float, method: str = "dop853",
                 step: float | None = None, tol: float | None = 1e-10,
                 compiled: InvariantSystem | None = None, backend: str = "compiled",
                 field: str = "bivector") -> Solution | tuple[_Run, float]:
    """Integrate ``X = N P dH`` in physical time with a registered integrator.

    Returns the :class:`~poissonkit.numerics.solution.Solution` of
    :func:`poissonkit.numerics.solve`; ``compiled`` reuses a compiled system. With
    ``backend="python"`` the field is lambdified and integrated by
    :func:`scipy.integrate.solve_ivp` (``method`` a scipy name such as ``"DOP853"``); the result
    then has ``t`` and ``y`` (rows are states) like a Solution. ``field="original"`` compiles
    the system's original equations instead of ``N P dH`` (compiled backend, see
    :func:`~poissonkit.numerics.system.compile_system`).
    """
    if field != "bivector" and backend == "python":
        raise InputError(f"field={field!r} needs backend='compiled'")
    if backend == "python":
        from scipy.integrate import solve_ivp

        sysl = compiled if compiled is not None else LambdifiedSystem(hsys)
        name = {"dop853": "DOP853", "rk45": "RK45", "radau": "Radau"}.get(method, method)
        start = time.perf_counter()
        r = solve_ivp(sysl.rhs, (0.0, t_end), np.asarray(y0, dtype=float), method=name,
                      rtol=tol or 1e-10, atol=tol or 1e-10)
        if not r.success:
            raise IntegrationError(f"solve_ivp failed: {r.message}")
        return _Run(t=r.t, y=r.y.T, steps=int(r.nfev)), time.perf_counter() - start
    from poissonkit.numerics.solver import solve
    from poissonkit.numerics.system import compile_system

    compiled = compiled if compiled is not None else compile_system(hsys, field=field)
    return solve(compiled, y0, t_end, method=method, step=step, tol=tol)
