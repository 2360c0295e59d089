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
from poissonkit.traits import offers


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
        Largest component of the Newton step still left at ``x*``, in units of each
        component's typical size (``scale``): how far the solution may be from the exact one.
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


def newton_step(problem: EquilibriumProblem, x: np.ndarray,
                leaf: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The least-squares Newton step towards ``X = 0`` (and ``C = leaf``) in units of
    ``problem.scale``, and the equilibrated residual it leaves."""
    D = problem.scale
    k = problem.casimirs(x).size
    rows = [problem.field_jacobian(x) * D]
    rhs = [-problem.field(x)]
    if k and leaf is not None:
        rows.append(problem.conserved_gradients(x)[:, :k].T * D)
        rhs.append(leaf - problem.casimirs(x))
    J, r = np.vstack(rows), np.concatenate(rhs)
    # the Casimir rows and the field rows live in different units: equilibrate the rows (a row
    # without derivatives is weighed like the most sensitive one)
    w = np.linalg.norm(J, axis=1)
    w = np.where(w > 0, w, max(float(np.max(w)), 1.0))
    J, r = J / w[:, None], r / w
    # directions the Jacobian hardly resolves (a symmetry orbit of solutions, differences'
    # noise) are no part of the distance to the solution set
    step = np.linalg.lstsq(J, r, rcond=1e-7)[0]
    return step, r - J @ step


def relative_residual(problem: EquilibriumProblem, x: np.ndarray,
                      leaf: np.ndarray | None = None) -> float:
    """Distance of ``x`` from the relative equilibrium in units of ``problem.scale``: the
    largest component of the scaled Newton step, or of the part of the residual that no step
    can remove (a field without a zero nearby)."""
    if not x.size:
        return 0.0
    step, unresolved = newton_step(problem, x, leaf)
    return float(max(np.max(np.abs(step)), np.max(np.abs(unresolved))))


def check_regular(problem: EquilibriumProblem, x: np.ndarray) -> None:
    """Raise :class:`SingularPointError` unless ``rank P(x) + rank dC(x) = dim``."""
    n, D = problem.dim, problem.scale
    rp = rank(problem.poisson(x) / np.outer(D, D))  # in the scaled coordinates x / scale
    k = problem.casimirs(x).size
    rc = rank(problem.conserved_gradients(x)[:, :k].T * D) if k else 0
    if rp + rc < n:
        raise SingularPointError(
            f"at this point the bracket has rank {rp} and the {k} declared Casimir "
            f"differentials span {rc} dimensions ({rp} + {rc} < {n}): the point is singular "
            "(the leaf through it is not the Casimirs' level set) or the system does not "
            "declare all its Casimirs")


def multipliers(problem: EquilibriumProblem, x: np.ndarray) -> np.ndarray:
    """``λ`` with ``∇(H − Σ ω J) + Σ λ_i ∇C_i = 0`` (least squares)."""
    k = problem.casimirs(x).size
    g = problem.energy_gradient(x)
    for w, j in zip(problem.omega, problem.momenta):
        if w:
            g = g - w * fd.gradient(j, x, problem.scale)
    if k == 0:
        return np.zeros(0)
    G = problem.conserved_gradients(x)[:, :k]
    return np.linalg.lstsq(G, -g, rcond=None)[0]


def describe(problem: EquilibriumProblem, x: np.ndarray, residual: float,
             iterations: int) -> RelativeEquilibrium:
    """Package a converged point as a :class:`RelativeEquilibrium` (checks regularity)."""
    check_regular(problem, x)
    layout = tuple(problem.system.layout) if offers(problem.system, HasLayout) else None
    return RelativeEquilibrium(
        state=x.copy(), multipliers=multipliers(problem, x),
        casimir_values=problem.casimirs(x), omega=problem.omega.copy(),
        momentum_values=problem.momentum_values(x), energy=problem.energy(x),
        residual=residual, iterations=iterations, layout=layout, problem=problem)


def relative_equilibrium(system: NumericsSystem, guess: ArrayLike, *,
                         momenta: Sequence[Momentum] = (),
                         omega: Sequence[float] | float | None = None,
                         casimir_values: ArrayLike | None = None,
                         scale: ArrayLike | None = None, tol: float = 1e-10,
                         max_evaluations: int = 2000) -> RelativeEquilibrium:
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
    scale
        Typical size of each state component (a number or one per component); default: the
        largest magnitude in ``guess`` of each vector the layout names (``top.r_x``,
        ``top.r_y``, ``top.r_z`` share one), so states mixing centimetres and 1e-4 kg m²/s
        are solved and differentiated component by component.
    tol
        Largest Newton step left at the solution, relative to ``scale`` (see
        :attr:`RelativeEquilibrium.residual`).
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
    problem = as_problem(system, momenta, omega, state=np.asarray(guess, dtype=float),
                         scale=scale)
    x0 = problem.state(guess)
    if not (np.isfinite(tol) and tol > 0):
        raise InputError(f"tol must be positive, got {tol!r}")
    c0 = problem.casimirs(x0)
    c = c0 if casimir_values is None else np.atleast_1d(np.asarray(casimir_values, float))
    if c.shape != c0.shape:
        raise DimensionError(f"casimir_values has {c.size} entries, the system declares "
                             f"{c0.size} Casimirs")
    k = c.size
    D = problem.scale
    # solve in scaled coordinates ξ = x / scale, rows equilibrated at the guess
    J0 = problem.field_jacobian(x0) * D
    w_field = np.linalg.norm(J0, axis=1)
    w_field = np.where(w_field > 0, w_field, max(float(np.max(w_field)), 1.0))
    w_field = np.maximum(w_field, np.abs(problem.field(x0)))
    G0 = problem.conserved_gradients(x0)[:, :k].T * D
    w_cas = np.linalg.norm(G0, axis=1) if k else np.zeros(0)
    w_cas = np.where(w_cas > 0, w_cas, 1.0)

    def residual(xi: np.ndarray) -> np.ndarray:
        x = xi * D
        return np.concatenate([problem.field(x) / w_field, (problem.casimirs(x) - c) / w_cas])

    def jac(xi: np.ndarray) -> np.ndarray:
        x = xi * D
        G = problem.conserved_gradients(x)[:, :k].T * D
        return np.vstack([problem.field_jacobian(x) * D / w_field[:, None],
                          G / w_cas[:, None]])

    try:
        with np.errstate(over="raise", divide="raise", invalid="raise"):  # not underflow
            out = least_squares(residual, x0 / D, jac=jac, method="lm", xtol=1e-15,
                                ftol=1e-15, gtol=1e-15, max_nfev=max_evaluations)
    except (FloatingPointError, ValueError, np.linalg.LinAlgError) as exc:
        raise NoConvergenceError(f"the equilibrium solve failed: {exc}", x0) from None
    x = out.x * D
    res = relative_residual(problem, x, c)
    leaf = float(np.max(np.abs(problem.casimirs(x) - c) / (w_cas * 1.0))) if k else 0.0
    if not (res <= tol and leaf <= tol):
        raise NoConvergenceError(
            f"no relative equilibrium within tol={tol:g} after {out.nfev} evaluations "
            f"(Newton step left {res:.3g} of the components' scales, leaf residual "
            f"{leaf:.3g}); try another guess", x, res)
    return describe(problem, x, res, int(out.nfev))


__all__ = ["RelativeEquilibrium", "check_regular", "describe", "multipliers", "newton_step",
           "relative_equilibrium", "relative_residual"]
