"""``linear_stability``: spectrum on the leaf and the energy–Casimir test.

At a relative equilibrium ``x*`` of the co-moving field ``X`` (see
:mod:`poissonkit.numerics.equilibria.relative`) the linearisation ``A = ∂X/∂x`` maps every
vector into ``T = ker dC ∩ ker dJ`` (each conserved ``F`` has ``dF·X ≡ 0``, hence ``dF·A = 0``
where ``X = 0``) and kills the symmetry directions ``X_{J_k}(x*)`` (the flows commute). The
spectrum that decides stability is that of ``A`` on ``T`` modulo the symmetry orbit: ``Wᵀ A W``
for an orthonormal basis ``W`` of the complement of the orbit directions in ``T``. The trivial
zero eigenvalues (Casimir and momentum directions, the orbit) are thereby removed.

Energy–Casimir (Arnold; Holm, Marsden, Ratiu & Weinstein 1985): ``H + Φ(C, J)`` is conserved
for every ``Φ``; if for some ``Φ`` it is critical at ``x*`` with a definite Hessian on ``T``
modulo the orbit, it is a Lyapunov function and ``x*`` is (orbitally) Lyapunov stable. Only
``Φ``'s first derivatives ``c`` enter on ``T``, and all ``c`` with ``∇H + Σ c_i ∇F_i = 0`` form
an affine family; the smallest eigenvalue of the restricted Hessian is concave in ``c``, so it
is maximised over the family (and likewise the largest, for a definite maximum). Failing
definiteness the test is *inconclusive* (gyroscopic stability, as the Levitron's, is invisible
to it).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import minimize

from poissonkit.contracts import NumericsSystem
from poissonkit.errors import InputError
from poissonkit.numerics.equilibria.errors import NotAnEquilibriumError
from poissonkit.numerics.equilibria.linalg import RANK_TOL, complement, null_space
from poissonkit.numerics.equilibria.problem import EquilibriumProblem, Momentum, as_problem
from poissonkit.numerics.equilibria.relative import (RelativeEquilibrium, check_regular, describe,
                                                     relative_residual)

#: Verdict strings (compare against these, not against literals).
UNSTABLE = "unstable"
SPECTRALLY_STABLE = "spectrally stable"
LYAPUNOV_STABLE = "Lyapunov stable (energy–Casimir)"
INCONCLUSIVE = "inconclusive"


@dataclass(frozen=True)
class LinearStability:
    """Linear stability of a relative equilibrium (see :func:`linear_stability`).

    Attributes
    ----------
    equilibrium
        The relative equilibrium analysed.
    eigenvalues
        Spectrum of the linearisation on the leaf modulo the symmetry orbit, sorted by real
        part then imaginary part (a Hamiltonian spectrum: symmetric under ``λ → −λ, λ̄``).
    reduced_dimension
        Dimension of that space (leaf dimension minus momentum levels and orbit directions).
    growth_rate
        Largest real part of the spectrum.
    spectral_verdict
        ``"unstable"`` if ``growth_rate > tol × max |λ|``, else ``"spectrally stable"``.
    energy_casimir
        ``"Lyapunov stable (energy–Casimir)"`` if some ``H + Φ(C, J)`` has a definite Hessian
        on the reduced space, else ``"inconclusive"``.
    energy_casimir_margin
        Best smallest eigenvalue of ``±Hessian`` on the reduced space over the admissible
        multipliers, relative to the Hessian's norm (positive: definite).
    hessian_eigenvalues
        Eigenvalues of the restricted Hessian at the best multipliers (in the coordinates
        ``x / scale`` of the analysis).
    energy_casimir_coefficients
        Those multipliers ``c`` (Casimirs then momenta) of ``H + Σ c_i F_i``.
    """

    equilibrium: RelativeEquilibrium
    eigenvalues: np.ndarray
    reduced_dimension: int
    growth_rate: float
    spectral_verdict: str
    energy_casimir: str
    energy_casimir_margin: float
    hessian_eigenvalues: np.ndarray
    energy_casimir_coefficients: np.ndarray

    @property
    def spectrally_stable(self) -> bool:
        """No eigenvalue with positive real part (within the tolerance)."""
        return self.spectral_verdict == SPECTRALLY_STABLE

    @property
    def lyapunov_stable(self) -> bool:
        """The energy–Casimir test proved Lyapunov stability."""
        return self.energy_casimir == LYAPUNOV_STABLE

    @property
    def frequencies(self) -> np.ndarray:
        """Non-negative imaginary parts of the spectrum (angular frequencies of the modes)."""
        im = self.eigenvalues.imag
        return np.sort(im[im >= 0])

    def __str__(self) -> str:
        return (f"{self.spectral_verdict} (max Re λ = {self.growth_rate:.3g} on a "
                f"{self.reduced_dimension}-dimensional reduced space); energy–Casimir: "
                f"{self.energy_casimir} (margin {self.energy_casimir_margin:.3g})")


def reduced_basis(problem: EquilibriumProblem, x: np.ndarray) -> np.ndarray:
    """Orthonormal ``W`` (in the scaled coordinates ``ξ = x / scale``) of
    ``ker dC ∩ ker dJ`` minus the orbit directions ``P ∇J_k``."""
    D = problem.scale
    G = problem.conserved_gradients(x) * D[:, None]
    T = null_space(G.T, problem.dim)
    if problem.momenta:
        k = G.shape[1] - len(problem.momenta)
        P = problem.poisson(x) / np.outer(D, D)
        orbit = P @ G[:, k:]
        # an orbit direction that vanishes (a fixed point of the symmetry) up to the
        # differences' round-off is no direction
        size = np.linalg.norm(P, 2) * np.linalg.norm(G[:, k:], axis=0)
        T = complement(T, orbit[:, np.linalg.norm(orbit, axis=0) > RANK_TOL * size])
    return T


def _energy_casimir(problem: EquilibriumProblem, x: np.ndarray, W: np.ndarray,
                    tol: float) -> tuple[str, float, np.ndarray, np.ndarray]:
    """Verdict, margin, restricted Hessian eigenvalues and the best coefficients (all in the
    scaled coordinates ``ξ = x / scale``, where definiteness is judged)."""
    D = problem.scale
    G = problem.conserved_gradients(x) * D[:, None]
    g = problem.energy_gradient(x) * D
    DD = np.outer(D, D)
    hessians = [W.T @ (h * DD) @ W for h in problem.conserved_hessians(x)]
    HH = W.T @ (problem.energy_hessian(x) * DD) @ W
    if G.shape[1]:
        c0 = np.linalg.lstsq(G, -g, rcond=None)[0]
        free = null_space(G, G.shape[1])
    else:
        c0, free = np.zeros(0), np.zeros((0, 0))

    def restricted(t: np.ndarray) -> np.ndarray:
        c = c0 + (free @ t if free.size else 0.0)
        S = HH + sum((ci * h for ci, h in zip(c, hessians)), np.zeros_like(HH))
        return 0.5 * (S + S.T)

    if W.shape[1] == 0:
        return LYAPUNOV_STABLE, 1.0, np.zeros(0), c0
    norm_h = max([float(np.linalg.norm(h, 2)) for h in hessians] + [1.0e-300])
    step = max(float(np.linalg.norm(HH, 2)) / norm_h, float(np.linalg.norm(c0)), 1.0e-12)
    best = (-np.inf, np.zeros(free.shape[1] if free.size else 0))
    for sign in (1.0, -1.0):
        def objective(t: np.ndarray, sign: float = sign) -> float:
            S = sign * restricted(t)
            return -float(np.linalg.eigvalsh(S)[0]) / max(float(np.linalg.norm(S, 2)), 1e-300)

        t0 = np.zeros(free.shape[1] if free.size else 0)
        if t0.size:
            simplex = np.vstack([t0, t0 + step * np.eye(t0.size)])
            out = minimize(objective, t0, method="Nelder-Mead",
                           options={"initial_simplex": simplex, "xatol": 1e-10 * step,
                                    "fatol": 1e-12, "maxiter": 400 * t0.size})
            t, margin = out.x, -float(out.fun)
        else:
            t, margin = t0, -objective(t0)
        if margin > best[0]:
            best = (margin, t)
    margin, t = best
    S = restricted(t)
    c = c0 + (free @ t if free.size else 0.0)
    verdict = LYAPUNOV_STABLE if margin > tol else INCONCLUSIVE
    return verdict, float(margin), np.linalg.eigvalsh(S), np.asarray(c, dtype=float)


def linear_stability(point: RelativeEquilibrium | NumericsSystem, state: ArrayLike | None = None,
                     *, momenta: Sequence[Momentum] = (),
                     omega: Sequence[float] | float | None = None,
                     scale: ArrayLike | None = None, tol: float = 1e-6,
                     energy_casimir_tol: float = 1e-6,
                     equilibrium_tol: float = 1e-7) -> LinearStability:
    """Linearise a relative equilibrium on the Poisson manifold and judge its stability.

    Parameters
    ----------
    point
        A :class:`RelativeEquilibrium` (from :func:`relative_equilibrium`), or a system, in
        which case ``state`` (and ``momenta``, ``omega``) describe the point.
    state
        The equilibrium state when ``point`` is a system.
    momenta, omega, scale
        As in :func:`relative_equilibrium` (only when ``point`` is a system).
    tol
        Spectral verdict: ``"unstable"`` if some eigenvalue has ``Re λ > tol × max |λ|``.
    energy_casimir_tol
        Smallest relative eigenvalue that counts as definite in the energy–Casimir test.
    equilibrium_tol
        Largest relative residual accepted for a ``state`` given directly.

    Returns
    -------
    LinearStability
        The spectrum on the leaf (modulo the symmetry orbit), the spectral verdict and the
        energy–Casimir verdict.

    Raises
    ------
    NotAnEquilibriumError
        If ``state`` is not a relative equilibrium within ``equilibrium_tol``.
    SingularPointError
        At a singular point of the bracket (see :func:`relative_equilibrium`).

    Notes
    -----
    Derivatives of the energy, Casimirs and momenta are central differences (relative steps
    1e-6 and 1e-4, :mod:`poissonkit.numerics.equilibria.differences`); the vector field's
    Jacobian is the system's own where it has one. Eigenvalues are therefore accurate to about
    1e-8 relative, which the default tolerances leave room for; a spectrum within that of the
    imaginary axis near a stability boundary is reported as stable.

    Examples
    --------
    Euler's top about its middle axis is unstable, about the others stable:

    >>> import poissonkit as pk
    >>> top = pk.compile_system(pk.HamiltonianSystem(
    ...     pk.so3(), "m_x**2/2 + m_y**2/4 + m_z**2/6",
    ...     casimirs={"C": "m_x**2 + m_y**2 + m_z**2"}))
    >>> pk.linear_stability(top, [0.0, 1.0, 0.0]).spectral_verdict
    'unstable'
    >>> pk.linear_stability(top, [1.0, 0.0, 0.0]).energy_casimir
    'Lyapunov stable (energy–Casimir)'
    """
    if isinstance(point, RelativeEquilibrium):
        if state is not None or momenta or omega is not None or scale is not None:
            raise InputError("give state, momenta and omega only with a system, not with a "
                             "RelativeEquilibrium")
        eq = point
        if eq.problem is None:
            raise InputError("this RelativeEquilibrium carries no system")
        problem = eq.problem
    else:
        if state is None:
            raise InputError("linear_stability(system, state): the state is missing")
        problem = as_problem(point, momenta, omega, state=np.asarray(state, dtype=float),
                             scale=scale)
        x = problem.state(state)
        res = relative_residual(problem, x)
        if not res <= equilibrium_tol:
            raise NotAnEquilibriumError(
                f"the state is not a relative equilibrium: relative field residual {res:.3g} "
                f"> {equilibrium_tol:g} (find one with relative_equilibrium)")
        eq = describe(problem, x, res, 0)
    for name, v in (("tol", tol), ("energy_casimir_tol", energy_casimir_tol)):
        if not (np.isfinite(v) and v > 0):
            raise InputError(f"{name} must be positive, got {v!r}")
    x = eq.state
    check_regular(problem, x)
    W = reduced_basis(problem, x)
    D = problem.scale
    A = problem.field_jacobian(x) * D[None, :] / D[:, None]  # ξ = x / scale: D⁻¹ A D
    reduced = W.T @ A @ W
    eig = np.linalg.eigvals(reduced) if reduced.size else np.zeros(0, dtype=complex)
    eig = eig[np.lexsort((eig.imag, eig.real))]
    size = max(float(np.max(np.abs(eig))) if eig.size else 0.0, 1.0e-300)
    growth = float(np.max(eig.real)) if eig.size else 0.0
    spectral = UNSTABLE if growth > tol * size else SPECTRALLY_STABLE
    verdict, margin, hess_eig, coeffs = _energy_casimir(problem, x, W, energy_casimir_tol)
    return LinearStability(equilibrium=eq, eigenvalues=eig, reduced_dimension=W.shape[1],
                           growth_rate=growth, spectral_verdict=spectral, energy_casimir=verdict,
                           energy_casimir_margin=margin, hessian_eigenvalues=hess_eig,
                           energy_casimir_coefficients=coeffs)


__all__ = ["INCONCLUSIVE", "LYAPUNOV_STABLE", "LinearStability", "SPECTRALLY_STABLE",
           "UNSTABLE", "linear_stability", "reduced_basis"]
