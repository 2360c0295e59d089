"""Hamiltonisation search against the survey's brackets (FORMULAS.md §2, §5, §7–§9, §12).

Every search starts from the equations of motion, the Hamiltonian, the Casimir claims and the
measure only: the systems' stated brackets are never handed in (``problem_from`` reads
``original``). The found bracket is compared with the project's builders in
``structure/deformed.py`` and with the oracle numbers of ``shared/reference/FORMULAS.md``, and
its Jacobi identity is re-proved with :func:`check_jacobi` (independent of the search's own
ring computation).
"""

from __future__ import annotations

import pytest
import sympy as sp

from poissonkit.errors import InputError, UnknownNameError
from poissonkit.structure import check_jacobi
from poissonkit.structure.deformed import chaplygin_ball as ball_bracket
from poissonkit.structure import e3
from poissonkit.structure.deformed import p_gf
from poissonkit.structure.casimirs import is_casimir
from poissonkit.structure.checks import is_conformally_hamiltonian
from poissonkit.structure.deformed import veselova as veselova_bracket
from poissonkit.structure.hamiltonize import (
    Ansatz,
    HamiltonizationProblem,
    hamiltonize,
    problem_from,
)
from poissonkit_nonholonomic.ball import (
    bmf_parts,
    chaplygin_ball,
    chaplygin_ball_sphere_bmf,
)
from poissonkit_nonholonomic.common import cross, dot, gamma_M
from poissonkit_nonholonomic.general import p_gf_system
from poissonkit_nonholonomic.suslov import suslov, suslov_potential
from poissonkit_nonholonomic.veselova import veselova

R = sp.Rational
GAMMA = (R(2, 3), R(1, 3), R(2, 3))


def _same(P, Q, factor=1) -> bool:
    """Entry-wise ``P == Q`` (``factor`` clears square roots before expanding)."""
    return all(sp.expand(sp.powsimp((a - b) * factor)) == 0 for a, b in zip(P.matrix, Q.matrix))


def _value(P, a, b, point):
    return sp.radsimp(P.matrix[P.index(a), P.index(b)].subs(dict(zip(P.coords, point))))


# ------------------------------------------------------------------ heavy top: e(3), §2
def _heavy_top(damping=0):
    gam, M = gamma_M("M")
    a = (R(1, 2), R(1, 3), R(1, 4))
    chi = (1, 2, 3)
    w = [a[i] * M[i] for i in range(3)]
    H = dot(M, w) / 2 + dot(chi, gam)
    # body-frame Euler-Poisson equations; the perturbation damps M (no invariant measure)
    X = cross(gam, w) + [x + y - damping * m for x, y, m in
                         zip(cross(M, w), cross(gam, chi), M)]
    return HamiltonizationProblem(gam + M, X, H, {"(gamma,gamma)": dot(gam, gam),
                                                  "(gamma,M)": dot(gam, M)}, 1, "heavy top")


def test_heavy_top_recovers_e3_and_its_multiples():
    res = hamiltonize(_heavy_top())
    assert res.found and res.parameters == ()
    # body frame: X = -P0 dH (FORMULAS.md §2), so the search returns -e(3)
    assert _same(res.solutions[0], -e3("gamma_M"))
    assert res.multiplier == 1
    # constant multiplier ansatz: exactly the line t * (-e(3)), N = 1/t
    multiples = hamiltonize(_heavy_top(), multiplier=("polynomial", 0))
    assert multiples.found and len(multiples.parameters) == 1
    t = multiples.parameters[0]
    assert _same(multiples.solutions[0], -t * e3("gamma_M"))
    assert sp.simplify(multiples.multipliers[0] * t) == 1


def test_damped_top_has_no_bracket_proved():
    prob = _heavy_top(damping=R(1, 10))
    fixed = hamiltonize(prob)
    assert fixed.status == "no_linear_solution" and fixed.proved_absent
    assert fixed.certificate.kind == "linear" and fixed.certificate.combination
    free_n = hamiltonize(prob, multiplier=("polynomial", 2))
    assert free_n.status == "no_multiplier" and free_n.certificate.kind == "multiplier"


# ------------------------------------------------------------------ Chaplygin ball (38), §7
def test_chaplygin_ball_bracket_and_multiplier_from_its_measure():
    system = chaplygin_ball()                              # I = (1, 2, 3), d = 1
    res = hamiltonize(system, degree=3)
    assert res.found and res.parameters == ()              # unique in the ansatz
    a, d = (R(1, 2), R(1, 3), R(1, 4)), 1
    g = sp.sqrt(1 - d * sum(ai * x**2 for ai, x in zip(a, system.coords[:3])))
    assert sp.simplify(res.multiplier - 1 / g) == 0        # N = g^{-1}
    P = res.solutions[0]
    # N = +g^{-1} goes with P = -P_g (FORMULAS.md §7, sign in (40))
    assert _same(P, -ball_bracket(I=(1, 2, 3), d=1), factor=g)
    point = GAMMA + (1, -2, R(1, 2))
    s = sp.sqrt(51)
    assert [-_value(P, "gamma_x", "M_y", point), -_value(P, "M_x", "M_z", point),
            -_value(P, "M_y", "M_z", point)] == [2 * s / 27, 143 * s / 612, 3 * s / 34]
    assert check_jacobi(P, method="exact").is_poisson
    # X = N P dH re-proved by the project's own check (random exact points, off the sphere too)
    rep = is_conformally_hamiltonian(system.original, P, system.hamiltonian, res.multiplier,
                                     method="random", trials=2, seed=3)
    assert rep.holds
    assert all(is_casimir(P, C).holds for C in system.casimirs.values())


def test_chaplygin_ball_needs_degree_three():
    res = hamiltonize(chaplygin_ball(), degree=2)
    assert res.status == "no_linear_solution"
    assert 0 < len(res.certificate.combination) < res.stats["equations"]


# ------------------------------------------------------------------ Veselova (65), §9
def test_veselova_bracket_from_its_equations():
    system = veselova()                                    # a = (1, 2, 3)
    res = hamiltonize(system, degree=3)
    assert res.found and res.parameters == ()
    g = sp.sqrt(dot((1, 2, 3), [x**2 for x in system.coords[:3]]))
    assert sp.simplify(res.multiplier - 1 / g) == 0
    P = res.solutions[0]
    assert _same(P, -veselova_bracket(a=(1, 2, 3)), factor=g)
    # FORMULAS.md §9 oracle: P_v at gamma = (2/3, 1/3, 2/3), K = (1, 2, -1), b = 2/3
    point = GAMMA + (1, 2, -1)
    r2 = sp.sqrt(2)
    assert [-_value(P, "K_x", "K_y", point), -_value(P, "K_x", "K_z", point),
            -_value(P, "K_y", "K_z", point), -_value(P, "K_x", "gamma_y", point)] == \
        [-11 * r2 / 9, -17 * r2 / 9, 7 * r2 / 9, 2 * r2 / 3]


# ------------------------------------------------------------------ Suslov rank 2, §7.1 / §12
def test_suslov_rank_two_family():
    system = suslov(I11=2, I22=1, I13=R(1, 2), I23=R(1, 3))
    res = hamiltonize(system, hamiltonian=None, degree=1, momentum_terms="linear",
                      casimirs=["H1", "H2=(gamma,gamma)", "H3=omega3"],
                      zero=("positions", "momenta"))
    assert res.found and len(res.parameters) == 3
    P = res.solutions[0]
    gam, w = system.coords[:3], system.coords[3:]
    # survey form: {gamma_i, omega_1} = -g_i I22 omega2, {gamma_i, omega_2} = g_i I11 omega1
    gvec = [-P.matrix[i, 3] / w[1] for i in range(3)]
    assert all(sp.expand(P.matrix[i, 4] - 2 * gvec[i] * w[0]) == 0 for i in range(3))
    assert all(P.matrix[i, 5] == 0 for i in range(6))
    assert sp.expand(dot(gvec, gam)) == 0                  # (g, gamma) = 0
    assert all(g.is_polynomial(*gam) and sp.Poly(g, *gam).total_degree() <= 1 for g in gvec)
    assert check_jacobi(P, method="exact").is_poisson


# ------------------------------------------------------------------ P_{g,f}, Theorem 2, §4/§5
def test_p_gf_family_f_is_free():
    """The Theorem-2 system with ``f = f0 + f1 gamma_y`` (f0, f1 symbols): the search over
    ``QQ(f0, f1)`` returns ``P_{g,f}`` for every such f at once."""
    f0, f1 = sp.symbols("f0 f1", real=True)
    gam = gamma_M("M")[0]
    g, f = 2 + gam[0], f0 + f1 * gam[1]
    system = p_gf_system(g=g, f=f)
    a = sp.symbols("a1 a2 a3", positive=True)
    U = sp.Function("U")(*gam)

    def fix(e):  # A = diag(1, 2, 3), U = gamma_z
        return sp.expand(e.subs(dict(zip(a, (1, 2, 3)))).subs(U, gam[2]).doit())

    prob = HamiltonizationProblem(system.coords, [fix(system.original[c]) for c in system.coords],
                                  fix(system.hamiltonian), dict(system.casimirs), 1 / g, "P_gf")
    res = hamiltonize(prob, degree=4, prefactor=1)
    assert res.found and res.parameters == ()
    assert _same(res.solutions[0], -p_gf(g, f))
    assert {f0, f1} <= set().union(*(e.free_symbols for e in res.solutions[0].matrix))


# ------------------------------------------------------------------ BMF ball, §8 / Prop. 3
def test_bmf_not_conformally_hamiltonian_with_energy_h1():
    """Survey §3.1 (after (55)): with H1 as Hamiltonian the BMF field is not conformally
    Hamiltonian for a bracket linear in M. Proved here for ``P = g^{-1} Q``, ``Q`` of degree
    <= 3 in gamma, with ``N = g^{-1}`` and with ``N = g^{-1}/mu``, ``mu`` of degree <= 2."""
    system = chaplygin_ball_sphere_bmf()
    H1 = bmf_parts()["H1"]
    fixed = hamiltonize(system, degree=3, hamiltonian=H1)
    assert fixed.status == "no_linear_solution"
    free_n = hamiltonize(system, degree=3, hamiltonian=H1, multiplier=("polynomial", 2, "measure"))
    assert free_n.status == "no_multiplier"


def test_bmf_positive_control_prop3():
    """The same search space at degree 5 finds P_b (54) for Prop. 3's Hamiltonian."""
    system = chaplygin_ball_sphere_bmf()
    p = bmf_parts()
    res = hamiltonize(system, degree=5, multiplier=system.multiplier, prefactor=1 / p["g"])
    assert res.found and res.parameters == ()
    assert _same(res.solutions[0], system.structure, factor=p["g"])


@pytest.mark.slow
def test_bmf_h1_degree_five_and_multiplier_search():
    system = chaplygin_ball_sphere_bmf()
    H1 = bmf_parts()["H1"]
    assert hamiltonize(system, degree=5, hamiltonian=H1).status == "no_linear_solution"
    res = hamiltonize(system, degree=5, hamiltonian=H1, multiplier=("polynomial", 4, "measure"))
    assert res.status == "no_multiplier"
    # and with Prop. 3's Hamiltonian the multiplier search finds N = 1/(g mu), mu ~ s (56)
    found = hamiltonize(system, degree=5, multiplier=("polynomial", 4, "measure"))
    assert found.found and len(found.parameters) == 1
    t = found.parameters[0]
    s = bmf_parts()["s"]
    ratio = sp.simplify(1 / (found.multipliers[0] * bmf_parts()["g"] * s))
    assert not ratio.free_symbols - {t}


# ------------------------------------------------------------------ input errors
def test_bad_input_is_typed():
    prob = _heavy_top()
    with pytest.raises(InputError):
        hamiltonize(prob, degree=-1)
    with pytest.raises(InputError):
        hamiltonize(prob, multiplier="sometimes")
    with pytest.raises(InputError):
        hamiltonize(prob, multiplier=("polynomial", -2))
    with pytest.raises(InputError):
        hamiltonize(prob, multiplier=0)
    with pytest.raises(InputError):
        hamiltonize(prob, momentum_terms="quadratic")
    with pytest.raises(InputError):   # no measure for multiplier="measure"
        hamiltonize(HamiltonizationProblem(prob.coords, prob.field, prob.hamiltonian),
                    multiplier="measure")
    with pytest.raises(InputError):   # a radical left in X/(N s)
        hamiltonize(chaplygin_ball(), degree=1, prefactor=1)
    with pytest.raises(InputError, match="undefined functions"):   # arbitrary g, f, U
        hamiltonize(p_gf_system())
    with pytest.raises(UnknownNameError):
        problem_from(chaplygin_ball(), casimirs=["no such integral"])
    with pytest.raises(InputError):
        hamiltonize(42)
    with pytest.raises(InputError):
        HamiltonizationProblem(prob.coords, prob.field[:3], prob.hamiltonian)
    with pytest.raises(InputError):
        Ansatz(prob.coords[:3], prob.coords[:3])
    with pytest.raises(InputError):
        hamiltonize(prob, ansatz=Ansatz(prob.coords[:3], prob.coords[3:]), degree=2)
    with pytest.raises(InputError):   # nothing to search for
        hamiltonize(prob, hamiltonian=None, casimirs={})


# ------------------------------------------------------------------ Suslov in a potential, §7.2
def test_suslov_potential_jacobi_selects_the_survey_bracket():
    """U = 3 gamma3 + gamma1^2 gamma2 (Poisson case): the linear conditions leave 9 free
    parameters at degree 3; Jacobi (Groebner basis) fixes them to the survey's bracket, checked
    against the FORMULAS.md §12 oracle matrix."""
    system = suslov_potential(I11=2, I22=1, U="3*gamma_z + gamma_x**2*gamma_y")
    res = hamiltonize(system, degree=3)
    assert res.found and len(res.parameters) == 9 and len(res.solutions) == 1
    P = res.solutions[0]
    assert not set().union(*(e.free_symbols for e in P.matrix)) & set(res.parameters)
    point = dict(zip(P.coords, GAMMA + (1, -2, 0)))
    oracle = sp.Matrix([[0, 0, 2, 0, 3, 0], [0, 0, 1, R(-3, 2), 0, 0],
                        [-2, -1, 0, R(2, 9), R(-4, 9), 0], [0, R(3, 2), R(-2, 9), 0, 0, 0],
                        [-3, 0, R(4, 9), 0, 0, 0], [0, 0, 0, 0, 0, 0]])
    assert P.matrix.subs(point) == oracle


def test_suslov_potential_quadratic_in_gamma3_is_not_poisson_proved():
    """U = gamma3^2/2 + gamma1^2 gamma2: the survey states Jacobi fails (FORMULAS.md §12). At
    degree 2 the linear conditions fix P and [P,P] != 0; at degree 3 the Jacobi equations in
    the 7 free parameters generate the unit ideal."""
    system = suslov_potential(I11=2, I22=1, U="gamma_z**2/2 + gamma_x**2*gamma_y")
    unique = hamiltonize(system, degree=2)
    assert unique.status == "no_jacobi_solution" and unique.parameters == ()
    family = hamiltonize(system, degree=3)
    assert family.status == "no_jacobi_solution" and len(family.parameters) == 7
    assert family.certificate.equations == (1,)


# ------------------------------------------------------------------ symbolic parameters
def test_veselova_for_all_moments_of_inertia():
    """Solved over QQ(a1, a2, a3): the bracket (65) for every A at once."""
    a = sp.symbols("a1:4", positive=True)
    system = veselova(*a)
    res = hamiltonize(system, degree=3)
    assert res.found and res.parameters == ()
    g = sp.sqrt(sum(ai * x**2 for ai, x in zip(a, system.coords[:3])))
    assert _same(res.solutions[0], -veselova_bracket(a=a), factor=g)


@pytest.mark.slow
def test_chaplygin_ball_for_all_parameters():
    """Solved over QQ(I1, I2, I3, d) (about 30 s)."""
    I = sp.symbols("I1:4", positive=True)
    d = sp.Symbol("d", positive=True)
    system = chaplygin_ball(*I, d)
    res = hamiltonize(system, degree=3)
    assert res.found and res.parameters == ()
    a = [1 / (Ii + d) for Ii in I]
    g = sp.sqrt(1 - d * sum(ai * x**2 for ai, x in zip(a, system.coords[:3])))
    diff = (res.solutions[0].matrix + ball_bracket(I=I, d=d).matrix) * g
    assert all(sp.simplify(sp.powsimp(e)) == 0 for e in diff)


# ------------------------------------------------------------------ gyrostats (49), (70)
@pytest.mark.parametrize("name", ["nh.chaplygin_gyrostat", "nh.veselova_gyrostat"])
def test_gyrostat_brackets_from_their_equations(name):
    """The registry's stated brackets P_sg (49) and P_k (70) (checked against FORMULAS.md
    §7, §10 by the plugin's tests) are recovered, unique in the ansatz, with N = 1/g."""
    from poissonkit.plugin import system as entry

    e = entry(name)
    system = e.build(**e.resolve_params({}))
    res = hamiltonize(name, degree=3)
    assert res.found and res.parameters == ()
    g = 1 / res.multiplier
    assert sp.simplify(res.multiplier + system.multiplier) == 0     # N = -(-1/g)
    assert _same(res.solutions[0], -system.structure, factor=g)
