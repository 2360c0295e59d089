"""``relative_equilibrium``: a critical point of ``H − Σ ω_k J_k + Σ λ_i C_i`` on a leaf.

On a Poisson manifold an equilibrium of ``X_H = P ∇H`` is not a critical point of ``H`` but of
``H + Σ λ_i C_i`` for multipliers ``λ`` (``P ∇C_i = 0``): the energy is stationary on the
symplectic leaf, the level set of the Casimirs. A *relative* equilibrium moves along a
symmetry, ``X_H = Σ ω_k X_{J_k}``: it is an equilibrium of the co-moving field (see
:mod:`poissonkit.numerics.equilibria.problem`).

The solver works on the vector field rather than on ``∇H``: it asks for
``X_H(x) − Σ ω_k X_{J_k}(x) = 0`` together with ``C(x) = c`` (the leaf), a square-or-taller
system whose Jacobian has full column rank at a regular isolated solution, solved by
Levenberg–Marquardt (``scipy.optimize.least_squares``) with the system's own compiled vector
field (exact derivatives of ``H``), and only then computes the multipliers.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import least_squares

from poissonkit.contracts import HasLayout, NumericsSystem
from poissonkit.errors import DimensionError, InputError
from poissonkit.numerics.equilibria import differences as fd
from poissonkit.numerics.equilibria.errors import NoConvergenceError, SingularPointError
from poissonkit.numerics.equilibria.linalg import rank
from poissonkit.numerics.equilibria.problem import EquilibriumProblem, Momentum, as_problem


@dataclass(frozen=True)
class RelativeEquilibrium:
    """A relative equilibrium found by :func:`relative_equilibrium`.

    Attributes
    ----------
    state
        The point ``x*`` (the system's state order and units).
    multipliers
        ``λ_i``, one per declared Casimir: ``x*`` is a critical point of
        ``H − Σ ω_k J_k + Σ λ_i C_i`` (least-squares values when the Casimir differentials do
        not determine them uniquely).
    casimir_values
        ``C_i(x*)``: the leaf.
    omega
        Angular velocities of the co-moving frame, one per momentum.
    momentum_values
        ``J_k(x*)``.
    energy
        ``H(x*)``.
    residual
        ``|X_H − Σ ω X_J|`` at ``x*`` relative to ``‖∂X/∂x‖ ‖x*‖`` (a relative size of the
        step that would still move the point).
    iterations
        Function evaluations of the least-squares solve.
    layout
        Names of the state components, where the system declares them.
    problem
        The system, momenta and frame velocities (what :func:`linear_stability` reads).
    """

    state: np.ndarray
    multipliers: np.ndarray
    casimir_values: np.ndarray
    omega: np.ndarray
    momentum_values: np.ndarray
    energy: float
    residual: float
    iterations: int
    layout: tuple[str, ...] | None = None
    problem: EquilibriumProblem | None = field(default=None, repr=False, compare=False)

    def named(self) -> dict[str, float]:
        """``{name: value}`` of the state components (positional names if no layout)."""
        names = self.layout or tuple(f"x{i}" for i in range(self.state.size))
        return {n: float(v) for n, v in zip(names, self.state)}


def field_scale(problem: EquilibriumProblem, x: np.ndarray) -> float:
    """Size against which a vector-field residual at ``x`` is judged: ``‖∂X/∂x‖₂ ‖x‖_∞``
    (a residual ``tol`` times this moves the root by about ``tol ‖x‖``)."""
    A = problem.field_jacobian(x)
    size = float(np.max(np.abs(x))) if x.size else 0.0
    return max(float(np.linalg.norm(A, 2)) * (size if size > 0 else 1.0), 1.0e-300)


def relative_residual(problem: EquilibriumProblem, x: np.ndarray) -> float:
    """``‖X(x)‖ / field_scale(x)`` (see :class:`RelativeEquilibrium`)."""
    return float(np.linalg.norm(problem.field(x))) / field_scale(problem, x)


def check_regular(problem: EquilibriumProblem, x: np.ndarray) -> None:
    """Raise :class:`SingularPointError` unless ``rank P(x) + rank dC(x) = dim``."""
    n = problem.dim
    rp = rank(problem.poisson(x))
    k = problem.casimirs(x).size
    rc = rank(problem.conserved_gradients(x)[:, :k].T) if k else 0
    if rp + rc < n:
        raise SingularPointError(
            f"at this point the bracket has rank {rp} and the {k} declared Casimir "
            f"differentials span {rc} dimensions ({rp} + {rc} < {n}): the point is singular "
            "(the leaf through it is not the Casimirs' level set) or the system does not "
            "declare all its Casimirs")


def multipliers(problem: EquilibriumProblem, x: np.ndarray) -> np.ndarray:
    """``λ`` with ``∇(H − Σ ω J) + Σ λ_i ∇C_i = 0`` (least squares)."""
    k = problem.casimirs(x).size
    g = fd.gradient(problem.energy, x)
    for w, j in zip(problem.omega, problem.momenta):
        if w:
            g = g - w * fd.gradient(j, x)
    if k == 0:
        return np.zeros(0)
    G = problem.conserved_gradients(x)[:, :k]
    return np.linalg.lstsq(G, -g, rcond=None)[0]


def describe(problem: EquilibriumProblem, x: np.ndarray, residual: float,
             iterations: int) -> RelativeEquilibrium:
    """Package a converged point as a :class:`RelativeEquilibrium` (checks regularity)."""
    check_regular(problem, x)
    layout = tuple(problem.system.layout) if isinstance(problem.system, HasLayout) else None
    return RelativeEquilibrium(
        state=x.copy(), multipliers=multipliers(problem, x),
        casimir_values=problem.casimirs(x), omega=problem.omega.copy(),
        momentum_values=problem.momentum_values(x), energy=problem.energy(x),
        residual=residual, iterations=iterations, layout=layout, problem=problem)


def relative_equilibrium(system: NumericsSystem, guess: ArrayLike, *,
                         momenta: Sequence[Momentum] = (),
                         omega: Sequence[float] | float | None = None,
                         casimir_values: ArrayLike | None = None,
                         tol: float = 1e-10, max_evaluations: int = 2000) -> RelativeEquilibrium:
    """Find a relative equilibrium of a compiled system near ``guess``.

    Solves ``X_H(x) − Σ ω_k X_{J_k}(x) = 0`` on the leaf ``C(x) = c`` by a Levenberg–Marquardt
    least-squares iteration, then computes the Casimir multipliers ``λ`` for which ``x*`` is a
    critical point of ``H − Σ ω_k J_k + Σ λ_i C_i``.

    Parameters
    ----------
    system
        Any numerics system (a :func:`~poissonkit.compile_system` result, an
        :class:`~poissonkit.NBodySystem`, a scene's system) that declares its bracket
        (``symbolic_form()`` or ``to_structure()``) and, through ``casimirs(y)``, its Casimirs.
    guess
        Starting state (the system's order and units).
    momenta
        Conserved momenta ``J_k(state) -> float`` of continuous symmetries, e.g. the vertical
        angular momentum; with ``omega`` they define the co-moving frame.
    omega
        Angular velocity of the frame about each momentum's symmetry (default zeros: an
        equilibrium of ``X_H`` itself).
    casimir_values
        The leaf ``C(x) = c`` to stay on (default: the Casimir values of ``guess``).
    tol
        Relative residual to reach (see :attr:`RelativeEquilibrium.residual`).
    max_evaluations
        Bound on vector-field evaluations of the least-squares solve.

    Returns
    -------
    RelativeEquilibrium

    Raises
    ------
    NoConvergenceError
        If the solve stops above ``tol`` (the last iterate and its residual are attached).
    SingularPointError
        If the solution is a singular point of the bracket or the declared Casimirs do not cut
        out the leaf there.
    InputError, DimensionError
        For a malformed system, guess, momenta or ``omega``.

    Examples
    --------
    >>> import numpy as np, poissonkit as pk
    >>> top = pk.HamiltonianSystem(pk.so3(), "m_x**2/2 + m_y**2/4 + m_z**2/6",
    ...                            casimirs={"C": "m_x**2 + m_y**2 + m_z**2"})
    >>> eq = pk.relative_equilibrium(pk.compile_system(top), [0.99, 0.05, 0.0])
    >>> np.round(eq.state, 12).tolist()
    [0.991261822124, 0.0, 0.0]
    """
    problem = as_problem(system, momenta, omega)
    x0 = problem.state(guess)
    if not (np.isfinite(tol) and tol > 0):
        raise InputError(f"tol must be positive, got {tol!r}")
    c0 = problem.casimirs(x0)
    c = c0 if casimir_values is None else np.atleast_1d(np.asarray(casimir_values, float))
    if c.shape != c0.shape:
        raise DimensionError(f"casimir_values has {c.size} entries, the system declares "
                             f"{c0.size} Casimirs")
    k = c.size
    # a field without derivatives (no equilibrium anywhere) is scaled by its own size
    s_field = max(field_scale(problem, x0), float(np.linalg.norm(problem.field(x0))))
    size = max(float(np.max(np.abs(x0))), 1.0e-300)
    G0 = problem.conserved_gradients(x0)[:, :k]
    s_cas = np.maximum(np.linalg.norm(G0, axis=0) * size, np.maximum(np.abs(c), 1.0e-300))

    def residual(x: np.ndarray) -> np.ndarray:
        return np.concatenate([problem.field(x) / s_field, (problem.casimirs(x) - c) / s_cas])

    def jac(x: np.ndarray) -> np.ndarray:
        G = problem.conserved_gradients(x)[:, :k]
        return np.vstack([problem.field_jacobian(x) / s_field, (G / s_cas).T])

    try:
        with np.errstate(all="raise"):
            out = least_squares(residual, x0, jac=jac, method="lm", xtol=1e-15, ftol=1e-15,
                                gtol=1e-15, max_nfev=max_evaluations)
    except (FloatingPointError, ValueError, np.linalg.LinAlgError) as exc:
        raise NoConvergenceError(f"the equilibrium solve failed: {exc}", x0) from None
    x = out.x
    res = relative_residual(problem, x)
    leaf = float(np.max(np.abs(problem.casimirs(x) - c) / s_cas)) if k else 0.0
    if not (res <= tol and leaf <= tol):
        raise NoConvergenceError(
            f"no relative equilibrium within tol={tol:g} after {out.nfev} evaluations "
            f"(field residual {res:.3g}, leaf residual {leaf:.3g}); try another guess",
            x, res)
    return describe(problem, x, res, int(out.nfev))


__all__ = ["RelativeEquilibrium", "check_regular", "describe", "field_scale", "multipliers",
           "relative_equilibrium", "relative_residual"]
