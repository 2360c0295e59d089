"""The cheaper evaluation of two tops (issue 33): the 4-lane dumbbell kernel and the two-body
kick, against independent truth (mpmath at 40 digits, the seed's sympy expression)."""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
from numba import njit

from poissonkit.numerics.kernels import inverse_powers4
from poissonkit_magnets import analytic
from poissonkit_magnets.seed000.two_body import two_body_system


@njit(error_model="numpy")
def _powers(x0, x1, x2, x3):
    return inverse_powers4(x0, x1, x2, x3)


def test_inverse_powers4_has_the_bits_of_the_scalar_operations_and_is_correctly_rounded():
    rng = np.random.default_rng(33)
    xs = 10.0 ** rng.uniform(-200, 200, size=(400, 4))
    mpmath.mp.dps = 40
    for x in xs:
        got = _powers(*x)
        for k in range(4):
            root = math.sqrt(x[k])
            assert got[k] == 1.0 / root and got[4 + k] == 1.0 / (x[k] * root)
            exact = 1 / mpmath.sqrt(mpmath.mpf(x[k]))
            assert abs(got[k] - exact) <= 1.5 * math.ulp(got[k])  # one rounding after sqrt's
            assert abs(got[4 + k] - exact ** 3) <= 2.5 * math.ulp(got[4 + k])


def test_inverse_powers4_edges_follow_ieee():
    got = _powers(0.0, -1.0, math.inf, 4.0)
    assert got[0] == math.inf and got[4] == math.inf
    assert math.isnan(got[1]) and math.isnan(got[5])
    assert got[2] == 0.0 and got[6] == 0.0
    assert got[3] == 0.5 and got[7] == 0.125


def _mp_dumbbell(r, c1, c2, c3, kap, l1, l2):
    """U and its four partials at 40 digits, by differentiating the pole sum numerically in
    mpmath (independent of the compiled formulas), and the sum of |pole terms| of each."""
    mpmath.mp.dps = 40
    args = [mpmath.mpf(v) for v in (r, c1, c2, c3)]
    a, b, k = mpmath.mpf(l1), mpmath.mpf(l2), mpmath.mpf(kap)

    def term(s1, s2, R, C1, C2, C3):
        rr2 = R ** 2 + a ** 2 + b ** 2 + 2 * R * (s2 * b * C2 - s1 * a * C1) - 2 * s1 * s2 * a * b * C3
        return k * s1 * s2 / mpmath.sqrt(rr2)

    pairs = [(1, 1), (1, -1), (-1, 1), (-1, -1)]
    values, sizes = [], []
    for order in ((0, 0, 0, 0), (1, 0, 0, 0), (0, 1, 0, 0), (0, 0, 1, 0), (0, 0, 0, 1)):
        parts = [mpmath.diff(lambda *v, s=s: term(s[0], s[1], *v), args, order) for s in pairs]
        values.append(sum(parts))
        sizes.append(sum(abs(p) for p in parts))
    return values, sizes


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_dumbbell_kernel_matches_mpmath_pole_sum(seed):
    rng = np.random.default_rng(seed)
    for _ in range(6):
        l1, l2 = rng.uniform(0.2, 1.0, 2)
        r = rng.uniform(1.05, 6.0) * (l1 + l2)
        e, n1, n2 = (v / np.linalg.norm(v) for v in rng.normal(size=(3, 3)))
        c1, c2, c3 = float(e @ n1), float(e @ n2), float(n1 @ n2)
        kap = rng.uniform(0.5, 2.0)
        got = analytic.dumbbell_core_k(r, c1, c2, c3, kap, l1, l2)
        ref, size = _mp_dumbbell(r, c1, c2, c3, kap, l1, l2)
        for g, v, s in zip(got, ref, size):
            assert abs(g - float(v)) <= 1e-14 * float(s)


def test_seed_kick_adds_h_times_the_forces_of_the_sympy_expression():
    # the seed pair through the kick (no scratch array) against the same pair given as the
    # seed's sympy fallback expression (compiled from sympy, not from analytic.py)
    from poissonkit.numerics.twobody import TwoBodySystem
    from poissonkit_magnets.seed000.table import parameter_table
    from poissonkit_magnets.seed000.two_body import dumbbell_expression

    system = two_body_system()
    t = parameter_table()
    expr = dumbbell_expression(t)
    reference = TwoBodySystem(None, None, float(t.alpha), float(t.alpha), expr, {},
                              scales=system.scales, reduced_mass=float(t.m))
    rng = np.random.default_rng(5)
    k = system.kernels
    for _ in range(5):
        n1, n2 = (v / np.linalg.norm(v) for v in rng.normal(size=(2, 3)))
        y = np.concatenate([rng.uniform(0.8, 1.5) * rng.normal(size=3), rng.normal(size=3),
                            n1, rng.normal(size=3), n2, rng.normal(size=3)])
        h = 1e-3
        kicked = y.copy()
        k.kick(kicked, h, system.data, system.work())
        compensated, c = y.copy(), np.zeros(18)
        k.kick_compensated(compensated, c, h, system.data, system.work())
        want = reference.rhs(0.0, y)
        slots = np.r_[3:6, 9:12, 15:18]
        # y + h F, to 1e-12 of h|F| plus the rounding of the sum
        tol = 1e-12 * h * np.max(np.abs(want[slots])) + 4 * np.spacing(np.max(np.abs(y)))
        assert np.allclose(kicked[slots], y[slots] + h * want[slots], rtol=0, atol=tol)
        assert np.allclose(compensated - c, kicked, rtol=0, atol=tol)
        # the other slots are untouched by a kick
        assert np.array_equal(np.delete(kicked, slots), np.delete(y, slots))
