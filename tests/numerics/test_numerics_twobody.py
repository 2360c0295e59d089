"""Seed 000's two-body system against the FORMULAS.md §1 oracle vectors."""

from __future__ import annotations

from fractions import Fraction as Fr

import numpy as np
import pytest
import sympy as sp
from numerics_helpers import DIPOLE, ORACLE_STATE, dumbbell  # type: ignore[import-not-found]

from poissonkit.numerics import TwoBodySystem
from poissonkit.numerics.nbody import NonUnitAxisError

# FORMULAS.md §1, dipole–dipole oracle: X = J grad H at the oracle state
X_DIPOLE = [Fr(1, 4), Fr(-1, 2), Fr(1, 6), Fr(-56, 3645), Fr(-148, 3645), Fr(-121, 3645),
            Fr(6, 5), Fr(-3, 5), 0, Fr(-2, 81), Fr(2, 405), 0, -8, 6, Fr(-11, 2),
            Fr(4, 405), Fr(-1, 135), Fr(4, 405)]


def test_dipole_vector_field_matches_formulas_oracle(oracle_pair):
    X = oracle_pair.rhs(0.0, ORACLE_STATE)
    expected = np.array([float(v) for v in X_DIPOLE])
    assert np.max(np.abs(X - expected)) <= 1e-14


def test_dipole_energy_and_angular_momentum_match_oracle(oracle_pair):
    # FORMULAS.md §1: H = 98567/6480, j = (28/15, 47/30, 1), X(j) = 0
    assert oracle_pair.energy(ORACLE_STATE) == pytest.approx(98567 / 6480, rel=1e-15)
    j = oracle_pair.angular_momentum(ORACLE_STATE)
    assert np.allclose(j, [28 / 15, 47 / 30, 1.0], rtol=0, atol=1e-15)
    X = oracle_pair.rhs(0.0, ORACLE_STATE)
    r, p = ORACLE_STATE[:3], ORACLE_STATE[3:6]
    jdot = np.cross(X[:3], p) + np.cross(r, X[3:6]) + X[9:12] + X[15:18]
    assert np.max(np.abs(jdot)) <= 1e-15


def test_dumbbell_forces_and_torques_match_oracle():
    # FORMULAS.md §1 dumbbells: l' = 1/2, l'' = 1/4, kappa' = 1, kappa'' = 2, mu0 = 4 pi
    U = dumbbell(sp.Rational(1, 2), sp.Rational(1, 4), 1, 2)
    sys = TwoBodySystem(None, None, 3.0, 5.0, U, reduced_mass=2.0)
    X = sys.rhs(0.0, ORACLE_STATE)
    assert sys.energy(ORACLE_STATE) == pytest.approx(15.210584761652889796, rel=1e-14)
    assert np.allclose(X[3:6], [-0.016028577559716323, -0.042468382726585774,
                                -0.031920476851215500], rtol=1e-13, atol=1e-16)
    assert np.allclose(X[9:12], [-0.030926283545105293, 0.0075095321139907043, 0.0],
                       rtol=1e-13, atol=1e-16)
    assert np.allclose(X[15:18], [0.0098304717943647458, -0.0073728538457735593,
                                  0.010411227607153128], rtol=1e-13, atol=1e-16)
    # r-dot, nu-dots are kinematic: as in the dipole case
    expected = np.array([float(v) for v in X_DIPOLE])
    for sl in (slice(0, 3), slice(6, 9), slice(12, 15)):
        assert np.allclose(X[sl], expected[sl], rtol=0, atol=1e-15)


def test_two_body_equals_symbolic_bracket_at_random_states(oracle_pair):
    # x-dot = J grad H with the symbolic canonical(3) + e3 + e3 bracket (FORMULAS §1 eq. 15)
    P = oracle_pair.to_structure()
    x = P.coords
    r = sp.Matrix(x[0:3])
    p = sp.Matrix(x[3:6])
    n1, m1, n2, m2 = (sp.Matrix(x[k:k + 3]) for k in (6, 9, 12, 15))
    rn = sp.sqrt(r.dot(r))
    c1, c2, c3 = r.dot(n1) / rn, r.dot(n2) / rn, n1.dot(n2)
    H = p.dot(p) / 4 + sp.Rational(3, 2) * m1.dot(m1) + sp.Rational(5, 2) * m2.dot(m2) \
        + DIPOLE.subs({sp.Symbol("r", real=True): rn, sp.Symbol("c1", real=True): c1,
                       sp.Symbol("c2", real=True): c2, sp.Symbol("c3", real=True): c3})
    f = sp.lambdify([x], P.matrix * P.gradient(H), "numpy")  # = P.hamiltonian_vector_field(H)
    rng = np.random.default_rng(3)
    for _ in range(3):
        y = rng.normal(size=18)
        y[0:3] += 2.0
        y[6:9] /= np.linalg.norm(y[6:9])
        y[12:15] /= np.linalg.norm(y[12:15])
        ref = np.asarray(f(y), dtype=float).ravel()
        assert np.allclose(oracle_pair.rhs(0, y), ref, rtol=1e-12, atol=1e-12)


def test_non_unit_axis_is_rejected_or_normalised(oracle_pair):
    with pytest.raises(NonUnitAxisError):
        oracle_pair.pack([1, 0, 0], [0, 1, 0], [0, 0, 2], [0, 0, 0], [1, 0, 0], [0, 0, 0])
    y = oracle_pair.pack([1, 0, 0], [0, 1, 0], [0, 0, 2], [0, 0, 0], [1, 0, 0], [0, 0, 0],
                         normalize=True)
    assert np.allclose(y[6:9], [0, 0, 1])


def test_bad_masses_raise_typed_error():
    from poissonkit.errors import InputError

    with pytest.raises(InputError):
        TwoBodySystem(1.0, -1.0, 1.0, 1.0, DIPOLE)
