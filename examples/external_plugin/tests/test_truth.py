"""The plugin's physics against its own truth: closed forms written out here."""

import math

import numpy as np
import pytest

from poissonkit.pairs import pair_interaction

K = 8.9875517923e9  # Coulomb's constant [N m^2/C^2]


def test_lennard_jones_well_is_minus_epsilon_at_two_to_the_sixth_sigma():
    eps, sigma = 1.65e-21, 3.4e-10
    r_min = 2 ** (1 / 6) * sigma
    out = pair_interaction("lennard_jones", (r_min, 0, 0), (0, 0, 1), (0, 0, 1),
                           epsilon=eps, sigma=sigma)
    assert out.energy == pytest.approx(-eps, rel=1e-12)
    assert np.linalg.norm(out.force) < 1e-12 * eps / sigma


def test_finite_dipole_is_four_coulomb_charges():
    q, d, r = 1e-8, 5e-3, np.array([0.012, 0.004, -0.003])
    nu1, nu2 = np.array([0.0, 0.0, 1.0]), np.array([0.6, 0.0, 0.8])
    charges = [(s1 * q, s1 * d / 2 * nu1, s2 * q, r + s2 * d / 2 * nu2)
               for s1 in (1, -1) for s2 in (1, -1)]
    truth = sum(K * qa * qb / np.linalg.norm(xb - xa) for qa, xa, qb, xb in charges)
    out = pair_interaction("finite_dipole", r, nu1, nu2, charge=q, dipole_length=d)
    assert out.energy == pytest.approx(truth, rel=1e-12)


def test_point_dipoles_far_apart_approach_the_finite_ones():
    q, d = 1e-8, 5e-3
    for r in (0.05, 0.5):
        nu = (0.0, 0.0, 1.0)
        exact = pair_interaction("finite_dipole", (r, 0, 0), nu, nu, charge=q, dipole_length=d)
        point = pair_interaction("point_dipole", (r, 0, 0), nu, nu, charge=q, dipole_length=d)
        assert point.energy == pytest.approx(K * (q * d) ** 2 / r ** 3, rel=1e-12)
        assert abs(point.energy / exact.energy - 1) < 2 * (d / r) ** 2


def test_trap_energy_is_half_m_omega_squared_r_squared():
    from poissonkit.numerics.fields import FieldRequest
    from poissonkit.plugin import external_field

    entry = external_field("harmonic_trap")
    built = entry.build(entry.resolve_params({"omega": 2.0, "centre": (0.1, 0, 0)}),
                        FieldRequest(), None)
    u = built.kernel(0.4, 0.0, 0.0, 0.0, 0.0, 1.0, 3.0, built.data)[0]
    assert u == pytest.approx(0.5 * 3.0 * 4.0 * 0.3 ** 2, rel=1e-14)
    assert math.isfinite(u)
