"""Routh sphere: the rank-4 Poisson bivector P^(k) of survey §5.2, Proposition 5 and the map (91).

The bivector is built by pulling e(3) back through a fibrewise-linear map; these tests judge it
with the core's checks (Jacobi, Casimirs, Poisson map) and independently in floating point
(numpy: rank, antisymmetry, the decomposition X = -P dH + mu X_S against the field (32) of
FORMULAS.md §11), with negative controls that must fail.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from poissonkit_nonholonomic import routh
from poissonkit_nonholonomic.revolution import e3_frame_map, e3_pullback, symmetry_field

from poissonkit.errors import InputError
from poissonkit.structure.checks import check_vanishing
from poissonkit.structure.jacobi import check_jacobi
from poissonkit.structure.poisson_map import is_poisson_map


@pytest.fixture(scope="module")
def jellett():
    return routh.routh_sphere_rank4()


@pytest.fixture(scope="module")
def numeric(jellett):
    p = routh.routh_parts()
    x = jellett.coords
    P = sp.lambdify(x, jellett.structure.matrix, "numpy")
    X = sp.lambdify(x, p["field"], "numpy")
    dH = sp.lambdify(x, [sp.diff(p["H"], v) for v in x], "numpy")
    grads = {k: sp.lambdify(x, [sp.diff(F, v) for v in x], "numpy")
             for k, F in (("C", sum(g**2 for g in x[:3])), ("J1", p["J1"]), ("J2", p["J2"]))}
    return P, X, dH, grads


def _states(n, seed=0):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        g = rng.normal(size=3)
        yield np.concatenate([g / np.linalg.norm(g), rng.normal(size=3) * 3])


def test_rank4_bivector_is_poisson_with_gravity(jellett):
    # the registered rank-2 bivector of nh.routh_sphere fails here for u != 0; this one does not
    assert jellett.params["u"] != 0
    res = check_jacobi(jellett.structure, method="random", seed=3)
    assert res.is_poisson, res.failures
    assert res.false_positive_bound < 1e-6


def test_rank_casimirs_and_integrals_in_floating_point(jellett, numeric):
    P, _, dH, grads = numeric
    for y in _states(5):
        Pv = np.array(P(*y), float)
        assert np.allclose(Pv, -Pv.T, atol=0)
        assert np.linalg.matrix_rank(Pv, tol=1e-9 * np.abs(Pv).max()) == 4
        for k in ("C", "J1"):  # Casimirs of P^(1)
            assert np.abs(Pv @ np.array(grads[k](*y), float)).max() < 1e-12 * np.abs(Pv).max()
        # J2 is not a Casimir but is in involution with H
        dJ2 = np.array(grads["J2"](*y), float)
        assert np.abs(Pv @ dJ2).max() > 1e-3
        assert abs(dJ2 @ Pv @ np.array(dH(*y), float)) < 1e-11 * np.abs(Pv).max()


def test_bivector_is_singular_at_the_poles_only(jellett):
    # survey: rank P^(k) drops at e±; here the entries have gamma1^2 + gamma2^2 in denominators
    P = jellett.structure.matrix
    gx, gy, gz = jellett.coords[:3]
    dens = {sp.denom(sp.together(e)) for e in P if e != 0}
    assert any(d.subs({gx: 0, gy: 0, gz: 1}) == 0 for d in dens)
    assert all(d.subs({gx: sp.Rational(3, 5), gy: 0, gz: sp.Rational(4, 5)}) != 0 for d in dens)


def test_prop5_decomposition_in_floating_point(numeric):
    """X_(32) + P dH is parallel to X_S (Prop. 5, N = -1); X_(32) - P dH is not (negative control)."""
    P, X, dH, _ = numeric
    for y in _states(5, seed=1):
        Pv, Xv, dHv = np.array(P(*y), float), np.array(X(*y), float), np.array(dH(*y), float)
        XS = np.array([float(v) for v in symmetry_field(y[:3], y[3:])])
        for sign, parallel in ((1, True), (-1, False)):
            Y = Xv + sign * Pv @ dHv
            mu = Y @ XS / (XS @ XS)
            resid = np.abs(Y - mu * XS).max() / np.abs(Xv).max()
            assert (resid < 1e-10) == parallel, (sign, resid)


def _claims_hold(system):
    for claim in routh.RANK4_CLAIMS:
        ok, detail, method = claim(system)
        assert ok, (system.params["casimir"], claim.__name__, detail)
        assert method


def test_claims_hold_for_the_jellett_bivector(jellett):
    _claims_hold(jellett)


@pytest.mark.slow
def test_claims_hold_for_the_routh_bivector():
    system = routh.routh_sphere_rank4(casimir="routh")
    assert check_jacobi(system.structure, method="random", seed=4).is_poisson
    _claims_hold(system)


def test_poisson_map_matches_e3_numerically(jellett):
    """J P J^T = Lambda_e(3)(phi) at float points: the map (91) is Poisson, checked without the
    random-point machinery, and a map with the latitude momentum doubled is not."""
    q = jellett.params
    P, A, _ = routh._rank4(q["R"], q["a"], q["m"], q["I1"], q["I3"], "jellett")
    x = jellett.coords
    phi = list(x[:3]) + list(A * sp.Matrix(x[3:]))
    Pf = sp.lambdify(x, P, "numpy")
    Jf = sp.lambdify(x, sp.Matrix([[sp.diff(f, v) for v in x] for f in phi]), "numpy")
    phif = sp.lambdify(x, phi, "numpy")

    def lhs(*y, scale=1.0):  # the Jacobian of (gamma, scale * L) is diag(1, scale) J
        J = np.array(Jf(*y), float)
        J[3:] *= scale
        return J @ np.array(Pf(*y), float) @ J.T

    def e3(z):
        g, L = z[:3], z[3:]
        out = np.zeros((6, 6))
        for i in range(3):
            for j in range(3):
                for k in range(3):
                    e = float(sp.LeviCivita(i, j, k))
                    out[3 + i, 3 + j] += e * L[k]
                    out[3 + i, j] += e * g[k]
                    out[j, 3 + i] -= e * g[k]
        return out

    for y in _states(4, seed=2):
        z = np.array(phif(*y), float)
        assert np.allclose(lhs(*y), e3(z), atol=1e-11, rtol=0)
        zb = z.copy()
        zb[3:] *= 2  # L doubled: the brackets scale wrongly, not a Poisson map
        assert not np.allclose(lhs(*y, scale=2.0), e3(zb), atol=1e-6)


def test_pullback_of_a_plain_rotation_is_e3():
    """The construction is generic: with c = gamma, p = e3 (L = M) it returns e(3) itself."""
    g = sp.symbols("g1:4", real=True)
    M = sp.symbols("M1:4", real=True)
    A, B = e3_frame_map(g, list(g), [0, 0, 1])
    assert (A - sp.eye(3)).applyfunc(sp.simplify) == sp.zeros(3, 3)
    P = e3_pullback(g, M, A, B)
    from poissonkit.structure.blocks import e3

    E = e3("gamma_M", names=("g", "M"))
    sub = dict(zip(E.coords, list(g) + list(M)))
    assert (P - E.matrix.xreplace(sub)).applyfunc(sp.simplify) == sp.zeros(6, 6)
    # and the core confirms the identity map is Poisson
    res = is_poisson_map(list(g) + list(M), __import__("poissonkit").structure.Bivector
                         .from_matrix(P, list(g) + list(M)), E)
    assert res.holds


def test_wrong_multiplier_sign_is_refused_by_the_core(jellett):
    # negative control through the core's random-point check: X - P dH is not parallel to X_S
    p = routh.routh_parts()
    x = jellett.coords
    Y = sp.Matrix(p["field"]) - jellett.structure.matrix * sp.Matrix([sp.diff(p["H"], v) for v in x])
    XS = symmetry_field(x[:3], x[3:])
    cross = [Y[3] * XS[4] - Y[4] * XS[3]]
    res = check_vanishing(cross, (sum(v**2 for v in x[:3]) - 1,), coords=list(x),
                          method="random", seed=1)
    assert not res.holds


def test_bad_casimir_choice_is_typed():
    with pytest.raises(InputError):
        routh.routh_sphere_rank4(casimir="energy")
