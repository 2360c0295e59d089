"""Independent reference for the Levitron: hovering height and linear stability window.

Standalone (numpy and scipy only; magpylib only in the tests that check the field): it shares
no code with poissonkit's systems, scenes or stability analysis, so agreeing with them means
something.

Model (Berry 1996; Simon, Heflinger & Ridgway 1997; Dullin & Easton 1999): a symmetric top of
mass ``M``, moments of inertia ``I₁ = I₂`` and ``I₃``, magnetic moment ``μ`` along its axis
``ν``, above an axially magnetised ring magnet (polarisation ``J = μ₀M_base`` along ``+z``, inner
and outer radii ``a < R``, thickness ``t``, top face at ``z = 0``). State ``(r, p, ν, m)`` with
the canonical ⊕ e(3) bracket and

    H = |p|²/2M + |m|²/2I₁ + M g z − μ ν·B(r)

(the spin part ``(1/I₃ − 1/I₁)(ν·m)²/2`` is a function of a Casimir and drops out). The moment
points down (``ν = −e_z``), against the base's field, so the top is repelled.

Field: on the axis the ring's field is exact,
``b(z) = (J/2) Σ ± [f_R(z + t) − f_R(z) − f_a(z + t) + f_a(z)]``, ``f_ρ(u) = u/√(u² + ρ²)``;
near the axis a curl- and divergence-free axisymmetric field is
``B_z = b − ρ² b''/4``, ``B_ρ = −ρ b'/2`` to second order in ``ρ``, which is all the
linearisation needs.

Linearisation: at an equilibrium of ``X_H = P ∇H`` on a Poisson manifold,
``∂X/∂x = P ∇²(H + Σ λ_i C_i)`` with the Casimir multipliers ``λ`` (differentiate
``P ∇C_i ≡ 0``); restricted to the leaf ``ker dC`` its spectrum decides spectral stability.
Every derivative here is written out by hand.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from scipy.optimize import brentq

MU0 = 4.0e-7 * math.pi
G = 9.81


@dataclass(frozen=True)
class LevitronParameters:
    """A ferrite ring base and a ferrite top, SI units.

    Close to the top of Simon, Heflinger & Ridgway (1997), a 22 g top floating about 3.2 cm
    above its base: here a 22.0 g top with a 0.60 A m² moment hovers 3.27 cm above a ferrite
    ring (J = 0.265 T, radii 0.8 and 4 cm, 1 cm thick). The inertias are those of a ferrite
    disc of radius 1.4 cm with a short stem. The field is a ring's, not their measured base's,
    and the inertias are ours: the window differs from theirs (see docs/levitron.md).
    """

    mass: float = 0.0220            # kg
    moment: float = 0.60            # A m² (along the axis)
    I1: float = 1.15e-6             # kg m², about a transverse axis through the centre
    I3: float = 2.10e-6             # kg m², about the symmetry axis
    polarization: float = 0.265     # T, base J = μ₀ M along +z (ferrite)
    inner_radius: float = 0.008     # m
    outer_radius: float = 0.040     # m
    thickness: float = 0.010        # m
    g: float = G                    # m/s²


def _f(u: np.ndarray, rho: float) -> np.ndarray:
    """``f = u/√(u²+ρ²)`` and its first three derivatives in ``u`` (leading axis)."""
    s = u * u + rho * rho
    return np.array([u / np.sqrt(s), rho * rho / s ** 1.5, -3.0 * rho * rho * u / s ** 2.5,
                     -3.0 * rho * rho * (rho * rho - 4.0 * u * u) / s ** 3.5])


def axis_field(z: float | np.ndarray, p: LevitronParameters) -> np.ndarray:
    """``(b, b', b'', b⁽³⁾)`` of the on-axis field ``B_z(0, 0, z)`` [T, T/m, T/m², T/m³],
    ``z`` above the top face of the base (an array of heights gives one column each)."""
    z = np.asarray(z, dtype=float)
    out = sum(sign * (_f(z + p.thickness, rho) - _f(z, rho))
              for rho, sign in ((p.outer_radius, 1.0), (p.inner_radius, -1.0)))
    return 0.5 * p.polarization * out


def near_axis_field(r: np.ndarray, p: LevitronParameters) -> np.ndarray:
    """``B`` at ``r`` to second order in the distance from the axis."""
    b, b1, b2, _ = axis_field(float(r[2]), p)
    return np.array([-0.5 * r[0] * b1, -0.5 * r[1] * b1,
                     b - 0.25 * (r[0] ** 2 + r[1] ** 2) * b2])


def hover_height(p: LevitronParameters) -> float:
    """Height ``z₀`` where the magnetic lift ``−μ b'(z)`` (moment down) balances ``M g`` on
    the branch with a vertical restoring force (``b'' > 0``)."""
    # b' is most negative at the inflection b'' = 0; above it −μ b' falls monotonically
    zs = np.linspace(1e-4, 0.5, 5000)
    k = int(np.argmin(axis_field(zs, p)[1]))
    lift = lambda z: -p.moment * axis_field(z, p)[1] - p.mass * p.g  # noqa: E731
    if lift(zs[k]) <= 0:
        raise ValueError("the base cannot lift this top (too heavy or too weak a moment)")
    return brentq(lift, zs[k], zs[-1], xtol=1e-15, rtol=1e-15)


def height_window(p: LevitronParameters) -> tuple[float, float]:
    """Heights where Berry's adiabatic potential ``μ|B| + M g z`` can trap: vertically
    ``b'' > 0`` and horizontally ``b'² > 2 b b''`` (Berry 1996, eq. (14))."""
    zs = np.linspace(1e-4, 0.3, 30001)
    b, b1, b2, _ = axis_field(zs, p)
    ok = (b > 0) & (b1 < 0) & (b2 > 0) & (b1 ** 2 > 2 * b * b2)  # above the maximum
    idx = np.nonzero(ok)[0]
    return float(zs[idx[0]]), float(zs[idx[-1]])


def equilibrium(p: LevitronParameters, spin_rpm: float, z0: float | None = None) -> np.ndarray:
    """The hovering state ``(r, p, ν, m)`` (SI): on the axis at ``z₀`` (default
    :func:`hover_height`), ``ν = −e_z``, ``m = I₃ ω₃ ν``."""
    z0 = hover_height(p) if z0 is None else z0
    L = p.I3 * spin_rpm * 2.0 * math.pi / 60.0
    nu = np.array([0.0, 0.0, -1.0])
    return np.concatenate([[0.0, 0.0, z0], np.zeros(3), nu, L * nu])


def poisson_matrix(x: np.ndarray) -> np.ndarray:
    """canonical(3) ⊕ e(3): ``{r_i, p_j} = δ_ij``, ``{ν_i, m_j} = ε_ijk ν_k``,
    ``{m_i, m_j} = ε_ijk m_k`` (poissonkit's conventions, written out again here)."""
    def hat(v: np.ndarray) -> np.ndarray:  # hat(v)[i, j] = ε_ijk v_k
        return np.array([[0.0, v[2], -v[1]], [-v[2], 0.0, v[0]], [v[1], -v[0], 0.0]])

    P = np.zeros((12, 12))
    P[0:3, 3:6] = np.eye(3)
    P[3:6, 0:3] = -np.eye(3)
    nu, m = x[6:9], x[9:12]
    P[6:9, 9:12] = hat(nu)
    P[9:12, 6:9] = hat(nu)
    P[9:12, 9:12] = hat(m)
    return P


def hessian(p: LevitronParameters, x: np.ndarray) -> tuple[np.ndarray, float, float]:
    """``∇²(H + λ₁|ν|² + λ₂ ν·m)`` at the hovering state, with the multipliers ``λ₁, λ₂``."""
    z0, s = x[2], x[8]  # s = ν_z = −1
    L = float(x[6:9] @ x[9:12])
    b, b1, b2, _ = axis_field(z0, p)
    mu = p.moment
    lam2 = -L / p.I1                             # ∂/∂m:  m/I₁ + λ₂ ν = 0
    lam1 = 0.5 * (mu * b * s - lam2 * L)         # ∂/∂ν: −μ b e_z + 2λ₁ν + λ₂ m = 0
    Hs = np.zeros((12, 12))
    # −μ ∂²(ν·B)/∂r² = −μ s ∂²B_z/∂r² (B_z = b − ρ² b''/4)
    Hs[0:3, 0:3] = -mu * s * np.diag([-0.5 * b2, -0.5 * b2, b2])
    Hs[3:6, 3:6] = np.eye(3) / p.mass
    # (r_i, ν_j): −μ ∂B_j/∂r_i (∂B_x/∂x = ∂B_y/∂y = −b'/2, ∂B_z/∂z = b')
    Hs[0:3, 6:9] = -mu * np.diag([-0.5 * b1, -0.5 * b1, b1])
    Hs[6:9, 0:3] = Hs[0:3, 6:9].T
    Hs[6:9, 6:9] = 2.0 * lam1 * np.eye(3)
    Hs[6:9, 9:12] = lam2 * np.eye(3)
    Hs[9:12, 6:9] = lam2 * np.eye(3)
    Hs[9:12, 9:12] = np.eye(3) / p.I1
    return Hs, lam1, lam2


def leaf_spectrum(p: LevitronParameters, spin_rpm: float,
                  z0: float | None = None) -> np.ndarray:
    """Eigenvalues [1/s] of the linearisation on the symplectic leaf (10 of them)."""
    x = equilibrium(p, spin_rpm, z0)
    A = poisson_matrix(x) @ hessian(p, x)[0]
    nu, m = x[6:9], x[9:12]
    dC = np.zeros((2, 12))
    dC[0, 6:9] = 2.0 * nu                    # |ν|²
    dC[1, 6:9], dC[1, 9:12] = m, nu          # ν·m
    _, _, vt = np.linalg.svd(dC)
    Q = vt[2:].T
    return np.linalg.eigvals(Q.T @ A @ Q)


def is_stable(p: LevitronParameters, spin_rpm: float, tol: float = 1e-9,
              z0: float | None = None) -> bool:
    """Spectral stability (every eigenvalue on the imaginary axis within ``tol``·max|λ|)."""
    ev = leaf_spectrum(p, spin_rpm, z0)
    return bool(np.max(ev.real) <= tol * np.max(np.abs(ev)))


def stability_window(p: LevitronParameters, lo: float = 100.0, hi: float = 20000.0,
                     points: int = 400) -> tuple[float, float]:
    """``(lower, upper)`` spin [rpm] of the linear stability window (bisected to 0.01 rpm).

    Raises ``ValueError`` if no spin in ``[lo, hi]`` is stable.
    """
    z0 = hover_height(p)
    grid = np.geomspace(lo, hi, points)
    ok = np.array([is_stable(p, w, z0=z0) for w in grid])
    idx = np.nonzero(ok)[0]
    if idx.size == 0:
        raise ValueError("no stable spin in the range: the height is outside the trap")
    if not np.all(ok[idx[0]:idx[-1] + 1]):
        raise ValueError("the stable spins are not one interval")

    def edge(a: float, b: float) -> float:  # stability changes between a and b
        sa = is_stable(p, a, z0=z0)
        while b - a > 0.01:
            c = 0.5 * (a + b)
            if is_stable(p, c, z0=z0) == sa:
                a = c
            else:
                b = c
        return 0.5 * (a + b)

    lower = edge(grid[idx[0] - 1], grid[idx[0]]) if idx[0] > 0 else float(grid[0])
    upper = edge(grid[idx[-1]], grid[idx[-1] + 1]) if idx[-1] < points - 1 else float(grid[-1])
    return lower, upper


def estimates(p: LevitronParameters) -> dict[str, float]:
    """Order-of-magnitude limits of the literature, at the hovering height [rpm]:
    ``flip`` — the sleeping-top condition ``L² > 4 I₁ μ |B|`` (the field's torque in place of
    gravity's); ``adiabatic`` — the precession rate ``μ|B|/L`` equal to the horizontal
    frequency of the adiabatic trap (Simon et al.'s upper limit)."""
    z0 = hover_height(p)
    b, b1, b2, _ = axis_field(z0, p)
    to_rpm = 60.0 / (2.0 * math.pi) / p.I3
    flip = math.sqrt(4.0 * p.I1 * p.moment * abs(b)) * to_rpm
    k_h = p.moment * (b1 ** 2 / (4.0 * b) - 0.5 * b2)   # horizontal stiffness of μ|B|
    w_h = math.sqrt(max(k_h, 0.0) / p.mass)
    adiabatic = p.moment * abs(b) / w_h * to_rpm if w_h > 0 else math.inf
    return {"height": z0, "flip": flip, "adiabatic": adiabatic,
            "vertical_hz": math.sqrt(p.moment * b2 / p.mass) / (2 * math.pi),
            "horizontal_hz": w_h / (2 * math.pi)}


def with_mass(p: LevitronParameters, mass: float) -> LevitronParameters:
    """The same top with another mass (weights added or removed)."""
    return replace(p, mass=mass)


if __name__ == "__main__":
    p = LevitronParameters()
    print("hover height [cm]:", 100 * hover_height(p))
    print("adiabatic trap heights [cm]:", [100 * h for h in height_window(p)])
    print("linear window [rpm]:", stability_window(p))
    print("estimates:", estimates(p))
