"""Jacobi checks: positive and negative controls, both methods, constraint surfaces, bad input.

Independent truths: FORMULAS.md (§0 oracle, §1 "Jacobi of (15)", §5 "without the (grad g, M)
term Jacobi fails", §6 "with the opposite sign of {p_i, p_j} Jacobi fails"), matrix commutators
(se(3) is built from 4x4 matrices, so it satisfies Jacobi by construction), the poissongeometry
package, and a hand computation (``v . curl v`` for 3-d brackets ``[v]_eps``).
"""

from __future__ import annotations

import random

import pytest
import sympy as sp

from poissonkit.errors import InputError, NotPoissonError
from poissonkit.structure import (
    Bivector,
    canonical,
    canonical_deformation,
    chaplygin_ball,
    check_jacobi,
    direct_sum,
    e3,
    eps_matrix,
    lie_poisson,
    p_gf,
    se3,
    so3,
)
from poissonkit.structure.deformed import gamma_symbols
from poissonkit.structure.jacobi import is_zero_expression, require_poisson

METHODS = ("exact", "random")


def two_tops() -> Bivector:
    """Seed 000 eq. (15)."""
    return direct_sum(("orbit", canonical(3, "r", "p")), ("top1", e3()), ("top2", e3()))


def random_lie_poisson(n: int, seed: int) -> Bivector:
    """Random antisymmetric structure constants: almost surely not a Lie algebra."""
    rng = random.Random(seed)
    C = [[[0] * n for _ in range(n)] for _ in range(n)]
    for i in range(n):
        for j in range(i + 1, n):
            for k in range(n):
                v = rng.randint(-3, 3)
                C[i][j][k], C[j][i][k] = v, -v
    return lie_poisson(C)


def p_gf_without_grad_term() -> Bivector:
    """FORMULAS.md §5 with the essential (grad g, M) term dropped."""
    P = p_gf(None, None)
    gamma, M = gamma_symbols()
    g = sp.Function("g")(*gamma)
    mat = sp.Matrix(P.matrix)
    mat[3:6, 3:6] -= sum(sp.diff(g, c) * m for c, m in zip(gamma, M)) * eps_matrix(gamma)
    return Bivector.from_matrix(mat, P.coords)


def canonical_deformation_wrong_sign() -> Bivector:
    """FORMULAS.md §6 with the opposite sign of {p_i, p_j}."""
    P = canonical_deformation()
    mat = sp.Matrix(P.matrix)
    mat[3:6, 3:6] = -mat[3:6, 3:6]
    return Bivector.from_matrix(mat, P.coords)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("build", [so3, e3, se3, lambda: canonical(3), two_tops,
                                   lambda: e3("gamma_M")],
                         ids=["so3", "e3", "se3", "canonical", "two_tops_18", "e3_gamma_M"])
def test_positive_controls(build, method):
    res = check_jacobi(build(), method=method, seed=1)
    assert res.is_poisson and not res.failures
    assert res.method == method
    if method == "random":
        # three points of the 10^6 sample set: (D / (2*10^6 + 1))^3 with D of a few hundred
        assert 0 < res.false_positive_bound < 1e-9
    else:
        assert res.false_positive_bound == 0


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("build", [lambda: random_lie_poisson(5, 1), lambda: random_lie_poisson(6, 2),
                                   p_gf_without_grad_term, canonical_deformation_wrong_sign],
                         ids=["random5", "random6", "p_gf_no_grad_g", "canonical_def_wrong_sign"])
def test_negative_controls(build, method):
    res = check_jacobi(build(), method=method, seed=3)
    assert not res.is_poisson
    assert res.failures and all(v != 0 for v in res.failures.values())
    assert res.false_positive_bound == 0


def test_failure_value_matches_oracle_and_names():
    y = sp.symbols("y1:4", real=True)
    Q = Bivector.from_matrix([[0, y[0] * y[1], 0], [-y[0] * y[1], 0, y[2]], [0, -y[2], 0]], y)
    res = check_jacobi(Q, method="exact")
    assert sp.expand(res.failures[(0, 1, 2)] + y[0] * y[2]) == 0     # FORMULAS.md §0
    assert list(res.named_failures()) == ["Jac(y1, y2, y3)"]
    assert not bool(res)


def test_agrees_with_poissongeometry_on_small_brackets():
    poisson = pytest.importorskip("poisson.poisson")
    pg = poisson.PoissonGeometry(4)
    x = sp.symbols("x1:5", real=True)
    cases = [{(1, 2): "x3", (1, 3): "-x2", (2, 3): "x1"},
             {(1, 2): "x1*x2", (2, 3): "x3", (3, 4): "x4**2"},
             {(1, 3): "x2*x4", (2, 4): "x1*x3"},
             {(1, 2): "x1*x2", (1, 4): "x2", (3, 4): "1"}]
    for case in cases:
        ours = check_jacobi(Bivector.from_components(case, x), method="exact").is_poisson
        assert ours == pg.is_poisson_bivector(case), case


def test_arbitrary_function_families_pass_exactly():
    for P in (p_gf(None, None, None), canonical_deformation(), chaplygin_ball()):
        res = check_jacobi(P, method="exact")
        assert res.is_poisson, res.failures


def test_random_method_randomises_function_jets():
    # Jacobi of p_gf fails for the wrong bracket *for some g*: the random check must see it
    # although the entries only contain g through undefined-function atoms.
    res = check_jacobi(p_gf_without_grad_term(), method="random", trials=1, seed=0)
    assert not res.is_poisson
    assert all(v.is_number for v in res.failures.values())


def sphere_example() -> Bivector:
    """``[v]_eps`` with ``v = u + s y``, ``u = (-y2, y1, 0)``, ``s = |y|^2 - 1``.

    ``curl v = curl u = (0, 0, 2)`` because ``curl(s y) = grad s x y = 0``, so
    ``v . curl v = 2 s y3``: Jacobi fails off the unit sphere and holds on it.
    """
    y = sp.symbols("y1:4", real=True)
    s = y[0] ** 2 + y[1] ** 2 + y[2] ** 2 - 1
    v = [-y[1] + s * y[0], y[0] + s * y[1], s * y[2]]
    return Bivector.from_matrix(eps_matrix(v), y)


def test_jacobi_modulo_constraint_surface_exact():
    P = sphere_example()
    y = P.coords
    sphere = y[0] ** 2 + y[1] ** 2 + y[2] ** 2 - 1
    assert not check_jacobi(P, method="exact").is_poisson
    assert check_jacobi(P, method="exact", constraints=[sphere]).is_poisson
    assert not check_jacobi(P, method="exact", constraints=[sphere - 3]).is_poisson
    assert check_jacobi(P, method="auto", constraints=[sphere]).is_poisson


def test_jacobi_modulo_constraint_surface_random_with_parametrisation():
    P = sphere_example()
    y = P.coords
    u, v = sp.symbols("u v", real=True)
    den = 1 + u ** 2 + v ** 2
    stereo = {y[0]: 2 * u / den, y[1]: 2 * v / den, y[2]: (1 - u ** 2 - v ** 2) / den}
    sphere = y[0] ** 2 + y[1] ** 2 + y[2] ** 2 - 1
    res = check_jacobi(P, method="random", constraints=[sphere], parametrization=stereo, seed=2)
    assert res.is_poisson and res.false_positive_bound < 1e-9
    off = {y[0]: 2 * u / den, y[1]: 2 * v / den, y[2]: 2 * (1 - u ** 2 - v ** 2) / den}
    with pytest.raises(InputError):
        check_jacobi(P, method="random", constraints=[sphere], parametrization=off)
    with pytest.raises(InputError):
        check_jacobi(P, method="random", constraints=[sphere])


def test_radical_aware_zero_test():
    x, d = sp.symbols("x d", positive=True)
    g = sp.sqrt(1 - d * x ** 2)
    # g * (1/g) - 1 and g**2 - (1 - d x^2) only vanish through the relation G^2 = u
    assert is_zero_expression(g * g - (1 - d * x ** 2))
    assert is_zero_expression(sp.diff(g, x) * g + d * x)
    assert not is_zero_expression(sp.diff(g, x) * g - d * x)
    # modulo a constraint: x^2 + d^2 - 1 vanishes on the circle x^2 + d^2 = 1 only
    assert is_zero_expression(x ** 2 + d ** 2 - 1, constraints=[x ** 2 + d ** 2 - 1])
    assert not is_zero_expression(x ** 2 - 1, constraints=[x ** 2 + d ** 2 - 1])


def test_bad_input_is_typed():
    with pytest.raises(InputError):
        check_jacobi(so3(), method="fast")
    with pytest.raises(InputError):
        check_jacobi(so3(), trials=0)
    with pytest.raises(InputError):
        check_jacobi(so3().matrix)
    y = so3().coords
    with pytest.raises(InputError):
        check_jacobi(so3(), method="exact", constraints=[sp.sin(y[0])])
    with pytest.raises(NotPoissonError):
        require_poisson(random_lie_poisson(5, 1))


def test_random_check_is_reproducible_with_seed():
    a = check_jacobi(random_lie_poisson(5, 4), method="random", seed=11)
    b = check_jacobi(random_lie_poisson(5, 4), method="random", seed=11)
    assert a.failures == b.failures


def test_chaplygin_bracket_with_wrong_correction_sign_fails():
    # P_g = P_{g,0} needs the (grad g, M) = -d (M, A gamma)/g term (FORMULAS.md §5, §7);
    # flipping its sign must be caught, by the polynomial-ring path and by random points
    a = sp.symbols("a1:4", positive=True)
    d = sp.Symbol("d", positive=True)
    P = chaplygin_ball(a=a, d=d)
    gamma, M = P.coords[:3], P.coords[3:]
    g = sp.sqrt(1 - d * sum(ai * gi ** 2 for ai, gi in zip(a, gamma)))
    corr = d * sum(ai * gi * mi for ai, gi, mi in zip(a, gamma, M)) / g * eps_matrix(gamma)
    mat = sp.Matrix(P.matrix)
    mat[3:6, 3:6] += 2 * corr
    bad = Bivector.from_matrix(mat, P.coords)
    assert check_jacobi(P, method="exact").is_poisson
    assert not check_jacobi(bad, method="exact").is_poisson
    assert not check_jacobi(bad, method="random", seed=5).is_poisson
