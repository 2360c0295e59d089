"""Relative equilibria and their linear stability against classical results.

Independent truth: Euler's top (rotation about the major and minor axes stable, the middle one
unstable with growth rate ``m √((a₁−a₂)(a₂−a₃))``); the sleeping Lagrange top (spectrally stable
iff ``I₃²ω₃² > 4 I₁ M g l``, Klein–Sommerfeld; nutation frequencies
``(L ± √(L² − 4 I₁ M g l)) / (2 I₁)``); the energy–Casimir result for the heavy top on e(3)*
(Holm, Marsden, Ratiu & Weinstein 1985: with the vertical momentum the same threshold; the
hanging top is a minimum of the energy–Casimir function); the steady precession of a Lagrange
top (``I₁ Ω² cos θ − L₃ Ω + M g l = 0``).
"""

from __future__ import annotations

import numpy as np
import pytest

import poissonkit as pk
from poissonkit.numerics.equilibria.stability import (
    INCONCLUSIVE,
    LYAPUNOV_STABLE,
    SPECTRALLY_STABLE,
    UNSTABLE,
)

A = (1.0, 0.5, 1.0 / 3.0)  # inverse principal moments of Euler's top


@pytest.fixture(scope="module")
def euler_top():
    return pk.compile_system(pk.HamiltonianSystem(
        pk.so3(), f"{A[0]}*m_x**2/2 + {A[1]}*m_y**2/2 + {A[2]}*m_z**2/2",
        casimirs={"C": "m_x**2 + m_y**2 + m_z**2"}))


def heavy_top(I1: float, Mgl: float):
    return pk.compile_system(pk.HamiltonianSystem(
        pk.e3(), "alpha*(m_x**2 + m_y**2 + m_z**2)/2 + Mgl*nu_z",
        casimirs={"C1": "nu_x**2 + nu_y**2 + nu_z**2", "C2": "nu_x*m_x + nu_y*m_y + nu_z*m_z"},
        params={"alpha": 1.0 / I1, "Mgl": Mgl}))


def vertical_momentum(y: np.ndarray) -> float:
    return float(y[5])  # m_z: rotation about the vertical


@pytest.mark.parametrize("axis, verdict, ec", [(0, SPECTRALLY_STABLE, LYAPUNOV_STABLE),
                                               (1, UNSTABLE, INCONCLUSIVE),
                                               (2, SPECTRALLY_STABLE, LYAPUNOV_STABLE)])
def test_euler_top_axes(euler_top, axis, verdict, ec):
    m0 = 1.7
    s = pk.linear_stability(euler_top, m0 * np.eye(3)[axis])
    assert (s.spectral_verdict, s.energy_casimir) == (verdict, ec)
    assert s.reduced_dimension == 2
    others = [a for i, a in enumerate(A) if i != axis]
    rate2 = m0 ** 2 * (A[axis] - others[0]) * (A[axis] - others[1])  # ω² (stable) or −σ²
    if verdict == UNSTABLE:
        assert s.growth_rate == pytest.approx(np.sqrt(-rate2), rel=1e-7)
    else:
        assert s.frequencies[-1] == pytest.approx(np.sqrt(rate2), rel=1e-7)


def test_relative_equilibrium_finds_the_axis_on_the_guess_leaf(euler_top):
    guess = np.array([0.2, 1.5, -0.1])
    eq = pk.relative_equilibrium(euler_top, guess)
    r = np.linalg.norm(guess)
    assert np.allclose(eq.state, [0.0, r, 0.0], atol=1e-10)
    # critical point of H + λ C: ∂/∂m_y gives a₂ m + 2 λ m = 0
    assert eq.multipliers[0] == pytest.approx(-A[1] / 2, rel=1e-8)
    assert eq.casimir_values[0] == pytest.approx(r ** 2, rel=1e-12)


@pytest.mark.parametrize("ratio", [0.97, 0.995, 1.005, 1.03, 2.0])
def test_sleeping_lagrange_top_threshold(ratio):
    I1, Mgl = 1.3, 0.8
    L = ratio * np.sqrt(4 * I1 * Mgl)  # I₃ω₃, the spin angular momentum
    top = heavy_top(I1, Mgl)
    eq = pk.relative_equilibrium(top, [0.02, -0.01, 1.0, 0.01, 0.0, L],
                                 casimir_values=[1.0, L])
    assert np.allclose(eq.state, [0, 0, 1, 0, 0, L], atol=1e-9)
    s = pk.linear_stability(eq)
    assert s.reduced_dimension == 4
    stable = bool(L ** 2 > 4 * I1 * Mgl)
    assert s.spectrally_stable is stable
    if stable:
        root = np.sqrt(L ** 2 - 4 * I1 * Mgl)
        expected = [(L - root) / (2 * I1), (L + root) / (2 * I1)]
        assert np.allclose(s.frequencies, expected, rtol=1e-6)
    else:
        assert s.growth_rate == pytest.approx(np.sqrt(4 * I1 * Mgl - L ** 2) / (2 * I1),
                                              rel=1e-6)
    # the energy alone (only Casimirs) cannot prove an upright top stable ...
    assert s.energy_casimir == INCONCLUSIVE
    # ... with the vertical momentum the energy–Casimir threshold is the classical one
    s2 = pk.linear_stability(top, eq.state, momenta=[vertical_momentum])
    assert s2.lyapunov_stable is stable
    assert np.allclose(np.sort(s2.eigenvalues.imag), np.sort(s.eigenvalues.imag), rtol=1e-6)


def test_hanging_top_is_an_energy_casimir_minimum():
    s = pk.linear_stability(heavy_top(1.0, -0.5), [0, 0, 1, 0, 0, 0.1])
    assert s.lyapunov_stable and s.spectrally_stable


def test_steady_precession_as_a_rotating_frame_equilibrium():
    I1, Mgl, L3, theta = 1.0, 1.0, 5.0, 0.6
    c = np.cos(theta)
    omega = (L3 - np.sqrt(L3 ** 2 - 4 * I1 * c * Mgl)) / (2 * I1 * c)  # slow precession
    nu = np.array([np.sin(theta), 0.0, c])
    m = L3 * nu + I1 * omega * (np.array([0.0, 0.0, 1.0]) - c * nu)
    guess = np.concatenate([nu, m]) + 0.01
    eq = pk.relative_equilibrium(heavy_top(I1, Mgl), guess, momenta=[vertical_momentum],
                                 omega=omega, casimir_values=[1.0, L3])
    assert np.arccos(eq.state[2]) == pytest.approx(theta, abs=1e-7)
    s = pk.linear_stability(eq)
    assert s.reduced_dimension == 2  # leaf 4, minus the momentum level and the orbit
    assert s.spectrally_stable


def test_singular_point_is_a_typed_error(euler_top):
    with pytest.raises(pk.SingularPointError):
        pk.linear_stability(euler_top, [0.0, 0.0, 0.0])


def test_undeclared_casimir_is_a_singular_point():
    top = pk.compile_system(pk.HamiltonianSystem(pk.so3(), "m_x**2/2 + m_y**2/4 + m_z**2/6"))
    with pytest.raises(pk.SingularPointError, match="declare"):
        pk.linear_stability(top, [1.0, 0.0, 0.0])


def test_no_equilibrium_is_a_typed_error():
    drift = pk.compile_system(pk.HamiltonianSystem(pk.canonical(1), "q_1 + p_1"))
    with pytest.raises(pk.NoConvergenceError) as err:
        pk.relative_equilibrium(drift, [0.0, 0.0], max_evaluations=50)
    assert err.value.residual > 1e-3


def test_state_that_is_not_an_equilibrium_is_refused(euler_top):
    with pytest.raises(pk.NotAnEquilibriumError):
        pk.linear_stability(euler_top, [1.0, 1.0, 0.0])


def test_bad_omega_is_an_input_error(euler_top):
    with pytest.raises(pk.PoissonkitError):
        pk.relative_equilibrium(euler_top, [1.0, 0, 0], omega=[1.0, 2.0])
