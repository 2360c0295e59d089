"""Reduction maps to e(3): survey (45)/(46) (Chaplygin ball) and (69) (Veselova), reconstructed.

Truth: the e(3) bracket of the core (FORMULAS.md §2), the Chaplygin bracket P_g (FORMULAS.md §7)
and the Veselova bracket P_v (§9) as built by the plugin, Remark 6 (L = M/g on (gamma, M) = 0),
Prop. 4 / (67) (FORMULAS.md §9), a closed form of H2 on the leaf c = 0 derived by hand (survey
(47)), and an independent high-accuracy e(3) integration (scipy DOP853) after the time change.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from poissonkit_nonholonomic.reduction import (
    SingularReductionError,
    chaplygin_reduction,
    chaplygin_reduction_hamiltonian,
    chaplygin_reduction_inverse,
    chaplygin_reduction_poisson,
    check_reduction,
    composition_defects,
    poisson_defect,
    regular_points,
    veselova_reduction,
    veselova_reduction_inverse,
    veselova_reduction_poisson,
)
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from poissonkit.errors import DimensionError, InputError
from poissonkit.structure.jacobi import is_zero_expression


def _sphere(u, v):
    n = 1 + u**2 + v**2
    return (2 * u / n, 2 * v / n, (1 - u**2 - v**2) / n)


def test_chaplygin_45_is_a_poisson_map_to_e3_with_inverse_46_and_the_reduced_field():
    """Other parameters and another leaf relation than the claims' defaults."""
    R = chaplygin_reduction(2, sp.Rational(5, 2), 4, sp.Rational(3, 2), k=2, c0=sp.Rational(1, 3))
    res = check_reduction(R, "points", n=1, seed=1)
    assert res == {"poisson": (True, ""), "inverse": (True, ""), "field": (True, "")}


def test_veselova_69_is_a_poisson_map_to_e3_with_inverse():
    R = veselova_reduction(1, 2, 3, k=3, c0=-1)
    res = check_reduction(R, "points", n=1, seed=2)
    assert res == {"poisson": (True, ""), "inverse": (True, ""), "field": (True, "")}


def test_claims_in_the_verify_signature_pass():
    from poissonkit_nonholonomic.ball import chaplygin_ball
    from poissonkit_nonholonomic.veselova import veselova

    s, v = chaplygin_ball(1, 2, 3, 1), veselova(1, 2, 3)
    for claim, system in [(chaplygin_reduction_poisson, s), (chaplygin_reduction_inverse, s),
                          (chaplygin_reduction_hamiltonian, s), (veselova_reduction_poisson, v),
                          (veselova_reduction_inverse, v)]:
        ok, detail, method = claim(system)
        assert ok, (claim.__name__, detail)
        assert "random rational points" in method
        assert claim.__doc__.splitlines()[0].strip()


def test_wrong_readings_of_the_ocr_fail_the_poisson_check():
    """The check can fail: the opposite sign of the b-term, and Remark 6's L = M/g off the
    level (gamma, M) = 0, are not Poisson maps P_g -> e(3)."""
    from dataclasses import replace

    from poissonkit_nonholonomic.reduction import _vectors

    R = chaplygin_reduction(1, 2, 3, 1)
    gam, M = R.system.coords[:3], R.system.coords[3:]
    U, _, _ = _vectors(list(gam), R.g, R.kappa2)
    b = sum(x * y for x, y in zip(gam, M))
    flipped = tuple(gam) + tuple(R.forward[3 + i] - 2 * b * U[i] for i in range(3))
    naive = tuple(gam) + tuple(m / R.g for m in M)
    pt = regular_points(R, 1, seed=3)[0]
    assert all(is_zero_expression(e) for _, e in poisson_defect(R, pt))
    for fw in (flipped, naive):
        bad = [lab for lab, e in poisson_defect(replace(R, forward=fw), pt)
               if not is_zero_expression(e)]
        assert bad  # reported, e.g. "{L_x, L_y}"


def test_on_the_leaves_b_equals_c_equals_zero_the_map_is_remark_6():
    R = chaplygin_reduction(1, 2, 3, 1)
    gam, M = R.system.coords[:3], R.system.coords[3:]
    Mz = -(gam[0] * M[0] + gam[1] * M[1]) / gam[2]
    for i in range(3):
        e = (R.forward[3 + i] - M[i] / R.g).xreplace({M[2]: Mz})
        assert is_zero_expression(e.xreplace({M[2]: Mz}))


def test_casimirs_are_mapped_to_casimirs_identically():
    R = chaplygin_reduction(1, 2, 3, 1, k=2, c0=5)
    gam, M = R.system.coords[:3], R.system.coords[3:]
    L = R.forward[3:]
    b = sum(x * y for x, y in zip(gam, M))
    assert sp.cancel(sum(x * y for x, y in zip(gam, L)) - (2 * b + 5)) == 0
    assert R.forward[:3] == tuple(gam)


def _sphere_points(n, seed):
    import random

    rng = random.Random(seed)
    out = []
    while len(out) < n:
        u, v = (sp.Rational(rng.randint(-30, 30), rng.randint(7, 29)) for _ in range(2))
        s = _sphere(u, v)
        if s[0] ** 2 + s[1] ** 2 != 0 and s[2] != 0:
            out.append(s)
    return out


def test_veselova_69_is_45_under_the_parameter_map_67_on_the_unit_sphere():
    """Prop. 4 (FORMULAS.md §9): with a^Ves = 1 - d a^Chap, K = M, on (gamma, gamma) = 1."""
    d = sp.Integer(1)
    aC = [sp.Rational(1, 2), sp.Rational(1, 3), sp.Rational(1, 4)]  # I = (1, 2, 3), d = 1
    aV = [1 - d * a for a in aC]
    Rc, Rv = chaplygin_reduction(1, 2, 3, 1), veselova_reduction(*aV)
    mom = [sp.Rational(3, 2), sp.Rational(-7, 5), sp.Rational(2, 9)]
    for s in _sphere_points(3, seed=8):
        pc = dict(zip(Rc.system.coords, list(s) + mom))
        pv = dict(zip(Rv.system.coords, list(s) + mom))
        for fc, fv in zip(Rc.forward[3:], Rv.forward[3:]):
            assert is_zero_expression(fc.xreplace(pc) - fv.xreplace(pv))
    # and they differ off the sphere (Remark 10: the parameter map then depends on (gamma,gamma))
    pc = dict(zip(Rc.system.coords, [sp.Rational(1, 2), sp.Rational(1, 3), 1] + mom))
    pv = dict(zip(Rv.system.coords, [sp.Rational(1, 2), sp.Rational(1, 3), 1] + mom))
    assert not is_zero_expression(Rc.forward[3].xreplace(pc) - Rv.forward[3].xreplace(pv))


def test_hamiltonian_on_the_leaf_c_0_has_the_closed_form_of_47():
    """On (gamma, gamma) = 1, c = 0 (derived by hand from (46); the survey's (47) as far as the
    OCR is legible), checked in exact arithmetic at rational points of the leaf (b free):

    H1 = g^2 (L, A_g L) + 2 b g ((gamma, A L) - a3 gamma_3 L_3) / kappa^2
         + b^2 s (1 - d s) / kappa^4,   s = a1 gamma_1^2 + a2 gamma_2^2,
         g^2 (L, A_g L) = g^2 (L, A L) + d (L, A gamma)^2
    H2 = g^2 (L, L) - 2 b g gamma_3 L_3 / kappa^2 + b^2 (1 + gamma_3^2 (gamma_1^2 + gamma_2^2)
         / kappa^4)
    """
    R = chaplygin_reduction(1, 2, 3, 1)
    y = R.target.coords
    gam, L = y[:3], y[3:]
    tog = dict(zip(R.system.coords[:3], gam))
    g = R.g.xreplace(tog)
    kap2 = R.kappa2.xreplace(tog)
    rho2 = gam[0] ** 2 + gam[1] ** 2
    closed = g**2 * sum(w**2 for w in L) - 2 * R.b * g * gam[2] * L[2] / kap2 \
        + R.b**2 * (1 + gam[2] ** 2 * rho2 / kap2**2)
    to_leaf = dict(zip(R.system.coords, list(gam) + list(R.leaf_M)))
    H2 = R.system.integrals["H2=(M,M)"].xreplace(to_leaf)
    H1 = R.system.integrals["H1=(M,omega)"].xreplace(to_leaf)
    a, d = [sp.Rational(1, 2), sp.Rational(1, 3), sp.Rational(1, 4)], 1  # I = (1, 2, 3), d = 1
    sA = a[0] * gam[0] ** 2 + a[1] * gam[1] ** 2
    LAg = sum(a[i] * gam[i] * L[i] for i in range(3))
    closed1 = g**2 * sum(a[i] * L[i] ** 2 for i in range(3)) + d * LAg**2 \
        + 2 * R.b * g * (LAg - a[2] * gam[2] * L[2]) / kap2 + R.b**2 * sA * (1 - d * sA) / kap2**2
    for i, s in enumerate(_sphere_points(3, seed=9)):
        l1, l2 = sp.Rational(2 + i, 3), sp.Rational(-5, 7 + i)
        l3 = -(s[0] * l1 + s[1] * l2) / s[2]  # c = 0
        pt = dict(zip(y, list(s) + [l1, l2, l3])) | {R.b: sp.Rational(5, 4 + i)}
        assert is_zero_expression(H2.xreplace(pt) - closed.xreplace(pt))
        assert is_zero_expression(H1.xreplace(pt) - closed1.xreplace(pt))
        # the + sign that the OCR of (47) seems to print is not the composition
        flipped = closed + 4 * R.b * g * gam[2] * L[2] / kap2
        assert not is_zero_expression(H2.xreplace(pt) - flipped.xreplace(pt))


# --------------------------------------------------------------------------------------------
# numerics: a DOP853 trajectory of the ball, mapped, against an independent e(3) solve in tau

Y0 = np.array([0.6, 0.0, 0.8, 1.0, -0.5, 0.2])  # on the unit sphere, away from the axis


@pytest.fixture(scope="module")
def mapped_run():
    R = chaplygin_reduction(1, 2, 3, 1)
    x = R.system.coords
    X = sp.lambdify([x], list(R.system.vector_field()), "numpy")
    T = 4.0
    ts = np.linspace(0.0, T, 41)
    sol = solve_ivp(lambda t, y: X(y), (0.0, T), Y0, method="DOP853", t_eval=ts,
                    rtol=1e-12, atol=1e-13)
    assert sol.success
    return R, ts, sol.y.T


def test_mapped_ball_trajectory_keeps_the_e3_casimirs(mapped_run):
    R, _, traj = mapped_run
    rho2 = traj[:, 0] ** 2 + traj[:, 1] ** 2
    assert rho2.min() > 0.05  # the run stays off the singular axis
    img = R.to_e3(traj)
    gg = np.sum(img[:, :3] ** 2, axis=1)
    c = np.sum(img[:, :3] * img[:, 3:], axis=1)
    b0 = Y0[:3] @ Y0[3:]
    assert np.max(np.abs(gg - 1)) < 1e-10
    assert np.max(np.abs(c - b0)) < 1e-9  # c = k b, k = 1
    back = R.from_e3(img)
    assert np.max(np.abs(back - traj)) < 1e-10


def test_mapped_trajectory_is_the_e3_euler_poisson_flow_after_the_time_change(mapped_run):
    """Independent solve: dx/dtau = -P_e3 dH~ (body-frame Euler–Poisson, FORMULAS.md §0) with
    dt/dtau = g(gamma); the ball's trajectory mapped by (45) must coincide with it. The other
    sign (+P_e3 dH~) is a different flow (the comparison can fail)."""
    R, ts, traj = mapped_run
    y = R.target.coords
    dH = sp.lambdify([y], [sp.diff(R.hamiltonian, yi) for yi in y], "numpy")
    gfun = sp.lambdify([y[:3]], R.g.xreplace(dict(zip(R.system.coords[:3], y[:3]))), "numpy")
    P0 = sp.lambdify([y], R.target.matrix, "numpy")
    img = R.to_e3(traj)

    def max_error(sign):
        def rhs(tau, z):
            f = sign * np.asarray(P0(z[:6]), float) @ np.asarray(dH(z[:6]), float)
            return np.concatenate([f, [gfun(z[:3])]])

        z0 = np.concatenate([img[0], [0.0]])
        sol = solve_ivp(rhs, (0.0, 8.0), z0, method="DOP853", dense_output=True,
                        rtol=1e-12, atol=1e-13)
        assert sol.success and sol.y[6, -1] > ts[-1]
        err = 0.0
        for t, target in zip(ts[1:], img[1:]):
            tau = brentq(lambda s, t=t: sol.sol(s)[6] - t, 0.0, sol.t[-1], xtol=1e-14)
            err = max(err, float(np.max(np.abs(sol.sol(tau)[:6] - target))))
        return err

    assert max_error(-1.0) < 1e-8
    assert max_error(+1.0) > 1e-2


def test_mapped_veselova_trajectory_keeps_the_e3_casimirs():
    R = veselova_reduction(1, 2, 3)
    X = sp.lambdify([R.system.coords], list(R.system.vector_field()), "numpy")
    sol = solve_ivp(lambda t, y: X(y), (0.0, 3.0), Y0, method="DOP853",
                    t_eval=np.linspace(0, 3, 31), rtol=1e-12, atol=1e-13)
    traj = sol.y.T
    assert (traj[:, 0] ** 2 + traj[:, 1] ** 2).min() > 0.01  # passes near, not on, the axis
    img = R.to_e3(traj)
    c = np.sum(img[:, :3] * img[:, 3:], axis=1)
    assert np.max(np.abs(c - Y0[:3] @ Y0[3:])) < 1e-9
    assert np.max(np.abs(R.from_e3(img) - traj)) < 1e-10


def test_bad_input_is_a_typed_error():
    R = chaplygin_reduction(1, 2, 3, 1)
    with pytest.raises(SingularReductionError):
        R.to_e3([0.0, 0.0, 1.0, 1.0, 2.0, 3.0])
    with pytest.raises(DimensionError):
        R.to_e3([0.0, 1.0, 1.0])
    with pytest.raises(SingularReductionError):
        R.to_e3([np.nan, 0.6, 0.8, 1.0, 2.0, 3.0])
    with pytest.raises(InputError):
        chaplygin_reduction(1, 2, 3, 1, k=0).from_e3([0.6, 0.0, 0.8, 1.0, 2.0, 3.0])
    with pytest.raises(InputError):
        check_reduction(R, mode="guess")
    with pytest.raises(InputError):
        chaplygin_reduction(1, 2, 3, 1, k="two")


def test_k_zero_maps_every_leaf_onto_c0_and_is_still_poisson():
    R = chaplygin_reduction(1, 2, 3, 1, k=0)
    res = check_reduction(R, "points", n=1, seed=4)
    assert res["poisson"] == (True, "")
    assert res["inverse"][0] is False


@pytest.mark.slow
@pytest.mark.parametrize("maker", [lambda: chaplygin_reduction(1, 2, 3, 1),
                                   lambda: veselova_reduction(1, 2, 3)])
def test_symbolic_proof_on_R6(maker):
    R = maker()
    for name, e in poisson_defect(R) + composition_defects(R):
        assert is_zero_expression(e), name
