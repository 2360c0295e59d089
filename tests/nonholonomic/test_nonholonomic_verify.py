"""The survey's claims, checked by verify_system, and the failures it must detect
(FORMULAS.md §0, §3–§12)."""

from __future__ import annotations

import json
from dataclasses import replace

import pytest
import sympy as sp
from poissonkit_nonholonomic import ball, general, routh, suslov, veselova
from poissonkit_nonholonomic.common import block, dot, eps_matrix, gamma_M
from poissonkit_nonholonomic.verify import format_report, jacobiator, verify_system

from poissonkit.errors import InputError

R = sp.Rational


def _claims(report):
    return {c["claim"]: c for c in report["checks"]}


def _check(report, prefix):
    found = [c for c in report["checks"] if c["claim"].startswith(prefix)]
    assert found, f"no check starting with {prefix!r} in {list(_claims(report))}"
    return found


QUICK = [
    (ball.chaplygin_ball, 2, 2),
    (ball.chaplygin_gyrostat, 2, 2),
    (veselova.veselova, 2, 2),
    (veselova.veselova_gyrostat, 2, 2),
    (suslov.suslov, 2, 1),
    (suslov.suslov_potential, 2, 0),
    (general.generalized_chaplygin, 0, 1),
    (general.p_gf_system, 2, 0),
]


@pytest.mark.parametrize("build,n_casimirs,n_integrals", QUICK,
                         ids=[b.__name__ for b, _, _ in QUICK])
def test_every_claim_of_the_survey_holds(build, n_casimirs, n_integrals):
    report = verify_system(build(), points=2)
    assert report["ok"], format_report(report)
    assert _check(report, "Jacobi identity")[0]["ok"]
    assert len(_check(report, "Casimir")) == n_casimirs if n_casimirs else True
    assert len([c for c in report["checks"] if c["claim"].startswith("first integral")]) \
        == n_integrals
    assert _check(report, "X = N P dH reproduces")[0]["ok"]
    json.dumps(report)  # the report is JSON-able (poissonkit verify --json)
    if build is veselova.veselova:
        assert _check(report, "Prop. 4/(68)")[0]["ok"]
        assert _check(report, "(62) is the push-forward")[0]["ok"]
    if build is ball.chaplygin_ball:  # the reduction map of Remark 6
        assert _check(report, "Remark 6")[0]["ok"]


def test_bmf_case_with_decomposition_55_and_proposition_3():
    report = verify_system(ball.chaplygin_ball_sphere_bmf(1, 2, 3, 1), points=1)
    assert report["ok"], format_report(report)
    assert _check(report, "BMF (55)")[0]["ok"]


@pytest.mark.slow
def test_chaplygin_ball_exact_symbolic_proof():
    report = verify_system(ball.chaplygin_ball(1, 2, 3, 1), mode="exact", extra=False)
    assert report["ok"] and report["mode"] == "exact"


def test_plus_sign_in_40_gives_the_time_reversed_flow():
    s = ball.chaplygin_ball()
    wrong = replace(s, multiplier=-s.multiplier)
    report = verify_system(wrong, jacobi=False, extra=False)
    assert not _check(report, "X = N P dH reproduces")[0]["ok"]


def test_gyrostat_with_M_plus_S_correction_does_not_reproduce_49():
    s = ball.chaplygin_gyrostat(S=(1, 0, -1))
    gam, M = s.coords[:3], s.coords[3:]
    a = [R(1, 2), R(1, 3), R(1, 4)]
    g = 1 / -s.multiplier
    MS = [M[0] + 1, M[1], M[2] - 1]
    G = eps_matrix(gam)
    P = block(sp.zeros(3), g * G, g * G,
              g * eps_matrix(MS) - dot(MS, [a[i] * gam[i] for i in range(3)]) / g * G)
    from poissonkit.structure.bivector import Bivector

    wrong = replace(s, structure=Bivector.from_matrix(P, s.coords))
    report = verify_system(wrong, extra=False, points=1)
    assert _check(report, "Jacobi identity")[0]["ok"]  # still Poisson (a Remark-5 term) ...
    assert not _check(report, "X = N P dH reproduces")[0]["ok"]  # ... but not (49)


def test_p_gf_without_grad_g_term_fails_jacobi():
    gam, M = gamma_M("M")
    g = 1 + gam[0] ** 2
    G = eps_matrix(gam)
    P = block(sp.zeros(3), g * G, g * G, g * eps_matrix(M))
    from poissonkit.structure.bivector import Bivector
    from poissonkit.structure.system import HamiltonianSystem

    s = HamiltonianSystem(Bivector.from_matrix(P, gam + M), sp.Integer(0), name="no-grad-term")
    report = verify_system(s)
    assert not report["ok"]
    assert "Jac(" in _check(report, "Jacobi identity")[0]["detail"]


def test_p_gf_with_remark5_phi_is_poisson():
    report = verify_system(general.p_gf_system(with_phi=True))
    assert report["ok"], format_report(report)


def test_suslov_potential_jacobi_iff_linear_in_gamma3():
    gam = sp.symbols("gamma_x gamma_y gamma_z", real=True)
    V = sp.Function("V")(gam[0], gam[1])
    ok = verify_system(suslov.suslov_potential(U=3 * gam[2] + V))
    assert ok["mode"] == "exact" and ok["ok"], format_report(ok)
    bad = verify_system(suslov.suslov_potential(U="3*gamma_z**2/2 + gamma_x**2*gamma_y"))
    assert not _check(bad, "Jacobi identity")[0]["ok"]
    assert _check(bad, "Casimir E=H1+U")[0]["ok"]


def test_suslov_linear_integral_125_needs_the_inertia_condition():
    good = suslov.suslov(I11=2, I22=1, I13=0, I23=1)  # I23^2 = (I11 - I22) I22
    assert verify_system(good, jacobi=False)["ok"]
    bad = suslov.suslov(I11=2, I22=1, I13=0, I23=R(1, 2))
    X = bad.original
    H4 = next(v for k, v in bad.integrals.items() if k.startswith("H4"))
    rate = sp.expand(sum(sp.diff(H4, x) * X[x] for x in bad.coords))
    g1, g2, g3, w1, w2, w3 = bad.coords
    I11, I22, I23 = 2, 1, R(1, 2)
    assert sp.expand(rate + g3 * w1 * w2 * (I11 * I22 - I22**2 - I23**2) / I22) == 0
    assert not _check(verify_system(bad, jacobi=False), "first integral H4")[0]["ok"]


def test_suslov_rank2_bivector_of_section_7_1():
    report = verify_system(suslov.suslov_rank2_bivector())
    assert report["ok"], format_report(report)
    # (gamma, gamma) is a Casimir only when (g, gamma) = 0: take g = e1 instead of gamma x c
    gam, w = report["coordinates"][:3], report["coordinates"][3:]
    s = suslov.suslov_rank2_bivector()
    P = s.structure.matrix
    c = s.coords
    row = [-1 * c[4], 2 * c[3], 0]
    P2 = sp.zeros(6, 6)
    for j in range(3):
        P2[0, 3 + j], P2[3 + j, 0] = row[j], -row[j]
    from poissonkit.structure.bivector import Bivector

    s2 = replace(s, structure=Bivector.from_matrix(P2, c))
    r2 = verify_system(s2)
    assert _check(r2, "Jacobi identity")[0]["ok"]
    assert not _check(r2, "Casimir (gamma,gamma)")[0]["ok"]
    assert P.shape == (6, 6) and len(gam) == len(w) == 3


@pytest.mark.slow
def test_routh_sphere_integrals_measure_and_field():
    report = verify_system(routh.routh_sphere(), jacobi=False)
    assert report["ok"], format_report(report)
    names = " ".join(c["claim"] for c in report["checks"])
    assert "Jellett" in names and "Routh" in names and "invariant measure" in names


@pytest.mark.slow
def test_routh_euler_bivector_is_poisson_without_gravity_only():
    assert _check(verify_system(routh.routh_sphere(u=0), points=1), "Jacobi")[0]["ok"]
    assert not _check(verify_system(routh.routh_sphere(u=10), points=1), "Jacobi")[0]["ok"]


@pytest.mark.slow
def test_chaplygin_ball_with_symbolic_parameters():
    """Random mode also samples free parameters: exact arithmetic at random rational
    (gamma, M, I1, I2, I3, d). (The fully symbolic proof with four symbolic parameters did not
    finish in 10 minutes.)"""
    I1, I2, I3, d = sp.symbols("I1 I2 I3 d", positive=True)
    report = verify_system(ball.chaplygin_ball(I1, I2, I3, d), mode="random", points=2,
                           extra=False)
    assert report["ok"], format_report(report)


def test_jacobiator_sign_matches_formulas_section0_oracle():
    y = sp.symbols("y1 y2 y3", real=True)
    Q = sp.Matrix([[0, y[0] * y[1], 0], [-y[0] * y[1], 0, y[2]], [0, -y[2], 0]])
    assert sp.expand(jacobiator(Q, y)[(0, 1, 2)] + y[0] * y[2]) == 0


def test_report_format_reads_like_the_maple_worksheet():
    text = format_report(verify_system(suslov.suslov_potential()))
    assert "Jacobi identity [P,P] = 0: OK" in text
    assert "{gamma_y,gamma_z} = omega_x" in text
    assert "domega_x/dt" in text


def test_bad_input_is_a_typed_error():
    with pytest.raises(InputError):
        verify_system(ball.chaplygin_ball(), mode="fast")
    with pytest.raises(InputError):
        verify_system("nh.chaplygin_ball")
    with pytest.raises(InputError):
        ball.chaplygin_ball(I1=-1)
    with pytest.raises(InputError):
        verify_system(general.p_gf_system(), mode="random")


def test_agrees_with_core_check_jacobi_when_available():
    jac = pytest.importorskip("poissonkit.structure.jacobi")
    s = ball.chaplygin_ball()
    res = jac.check_jacobi(s.structure)
    assert res.is_poisson
    gam, M = gamma_M("M")
    g = 1 + gam[0] ** 2
    G = eps_matrix(gam)
    from poissonkit.structure.bivector import Bivector

    bad = Bivector.from_matrix(block(sp.zeros(3), g * G, g * G, g * eps_matrix(M)), gam + M)
    assert not jac.check_jacobi(bad).is_poisson


def test_brackets_agree_with_the_structure_layer_when_available():
    deformed = pytest.importorskip("poissonkit.structure.deformed")
    for mine, theirs in ((ball.chaplygin_ball(1, 2, 3, 1),
                          deformed.chaplygin_ball(I=(1, 2, 3), d=1)),
                         (ball.chaplygin_gyrostat(1, 2, 3, 1, S=(1, 0, -1)),
                          deformed.chaplygin_gyrostat(S=(1, 0, -1), I=(1, 2, 3), d=1))):
        sub = dict(zip(theirs.coords, mine.coords))
        diff = (theirs.matrix.xreplace(sub) - mine.structure.matrix).applyfunc(
            lambda e: sp.simplify(e))
        assert diff == sp.zeros(6, 6)
