"""The standalone Levitron reference (tests/reference_levitron.py) against magpylib and
against poissonkit's own relative-equilibrium and stability analysis.

The reference writes the on-axis field of a ring magnet, its near-axis expansion and the
linearisation ``P ∇²(H + λ·C)`` by hand; magpylib checks the field, a sympy/numba compilation
of the same Hamiltonian through :func:`pk.relative_equilibrium` / :func:`pk.linear_stability`
checks the spectrum with independent code (finite differences of a compiled vector field,
a least-squares equilibrium solve, the leaf computed from the declared Casimirs).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
import reference_levitron as ref  # noqa: E402

import poissonkit as pk  # noqa: E402

P = ref.LevitronParameters()


def magpylib_ring():
    magpy = pytest.importorskip("magpylib")
    # the polarisation J = μ₀M is what both share: no μ₀ enters the field of either
    return magpy.magnet.CylinderSegment(
        polarization=(0.0, 0.0, P.polarization),
        dimension=(P.inner_radius, P.outer_radius, P.thickness, 0.0, 360.0),
        position=(0.0, 0.0, -P.thickness / 2))


def test_on_axis_field_and_derivatives_match_magpylib():
    ring = magpylib_ring()
    zs = np.array([0.02, 0.03, ref.hover_height(P), 0.05, 0.08])
    b = ref.axis_field(zs, P)

    def bz(z: np.ndarray) -> np.ndarray:
        return ring.getB(np.column_stack([0 * z, 0 * z, z]))[:, 2]

    assert np.allclose(b[0], bz(zs), rtol=1e-9, atol=1e-12)
    h = 1e-6  # central differences of magpylib's field (they converge as h² to these)
    assert np.allclose(b[1], (bz(zs + h) - bz(zs - h)) / (2 * h), rtol=1e-7)
    h = 1e-5
    assert np.allclose(b[2], (bz(zs + h) - 2 * bz(zs) + bz(zs - h)) / h ** 2, rtol=1e-4)


def test_near_axis_expansion_matches_magpylib_off_axis():
    ring = magpylib_ring()
    z0 = ref.hover_height(P)
    for rho in (1e-3, 3e-3):
        r = np.array([rho * 0.6, rho * 0.8, z0])
        exact = ring.getB(r)
        approx = ref.near_axis_field(r, P)
        # the expansion is exact to O(ρ³) in B_ρ and O(ρ⁴) in B_z
        assert np.linalg.norm(approx - exact) < 50 * (rho / 0.01) ** 3 * np.linalg.norm(exact)


def test_hovering_height_balances_gravity_and_lies_in_the_trap():
    z0 = ref.hover_height(P)
    lo, hi = ref.height_window(P)
    assert lo < z0 < hi
    assert -P.moment * ref.axis_field(z0, P)[1] == pytest.approx(P.mass * P.g, rel=1e-12)


def test_lower_spin_limit_is_the_flip_threshold():
    lower, upper = ref.stability_window(P, points=120)
    assert lower == pytest.approx(ref.estimates(P)["flip"], rel=0.02)
    assert 1.5 * lower < upper


def _compiled_levitron(p: ref.LevitronParameters):
    """The reference Hamiltonian as a symbolic system (near-axis field, exact on the axis)."""
    struct = pk.direct_sum(("top", pk.canonical(3)), ("axis", pk.e3()))
    x, y, z, px, py, pz, nx, ny, nz, mx, my, mz = struct.coords
    u = sp.Symbol("u", real=True)
    f = sum(sign * ((u + p.thickness) / sp.sqrt((u + p.thickness) ** 2 + rho ** 2)
                    - u / sp.sqrt(u ** 2 + rho ** 2))
            for rho, sign in ((p.outer_radius, 1), (p.inner_radius, -1)))
    b = p.polarization / 2 * f
    b1, b2 = sp.diff(b, u), sp.diff(b, u, 2)
    B = [(-x * b1 / 2).subs(u, z), (-y * b1 / 2).subs(u, z),
         (b - (x ** 2 + y ** 2) * b2 / 4).subs(u, z)]
    H = ((px ** 2 + py ** 2 + pz ** 2) / (2 * p.mass) + (mx ** 2 + my ** 2 + mz ** 2) / (2 * p.I1)
         + p.mass * p.g * z - p.moment * (nx * B[0] + ny * B[1] + nz * B[2]))
    system = pk.HamiltonianSystem(struct, H, casimirs={
        "C1": nx ** 2 + ny ** 2 + nz ** 2, "C2": nx * mx + ny * my + nz * mz})
    return pk.compile_system(system)


def test_poissonkit_linear_stability_agrees_with_the_reference():
    system = _compiled_levitron(P)
    for rpm in (600.0, 1200.0, 2200.0):
        x = ref.equilibrium(P, rpm)
        guess = x + np.r_[1e-4, -1e-4, 2e-4, 0, 0, 0, 1e-3, 0, 0, 0, 0, 0]
        eq = pk.relative_equilibrium(system, guess, casimir_values=[1.0, x[6:9] @ x[9:12]])
        assert np.allclose(eq.state, x, rtol=1e-8, atol=1e-10)
        s = pk.linear_stability(eq)
        expected = ref.leaf_spectrum(P, rpm)
        assert s.reduced_dimension == 10
        assert np.allclose(np.sort(s.frequencies), np.sort(expected.imag[expected.imag >= 0]),
                           rtol=1e-5, atol=1e-6 * np.abs(expected).max())
        assert s.spectrally_stable is ref.is_stable(P, rpm)
        # gyroscopic stability: no energy–Casimir function proves it
        assert s.energy_casimir == "inconclusive"
