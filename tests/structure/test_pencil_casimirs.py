"""Pencil Casimirs keep every factor that depends on the coordinates.

Truth is stated by hand for each case:

* so(3) against 2 so(3): the pencil is ``(2 - lam) so(3)``, whose Casimirs are the functions of
  ``|m|^2``;
* a central coordinate ``c`` of both brackets is a Casimir of the pencil;
* periodic Toda lattice, n = 3, in Flaschka variables (linear and quadratic brackets, indices
  mod 3; Damianou, *Rep. Math. Phys.* 34 (1994)): ``a1 a2 a3`` is a Casimir of both brackets,
  checked here by differentiating by hand;
* the Nambu pencil ``P_lam = star d(z (y + lam x))`` has Casimir ``z (y + lam x)``, and
  ``y + lam x`` is not one (``{x, y + lam x} = {x, y} = dF/dz = y + lam x != 0``).
"""

from __future__ import annotations

import pytest
import sympy as sp
from brackets import bivector_of  # type: ignore[import-not-found]

import poissonkit as pk
from poissonkit.structure import Bivector, so3
from poissonkit.structure.bihamiltonian import (
    ConstantCasimirError,
    lenard_magri_chain,
    lenard_magri_chains,
    pencil,
    pencil_casimirs,
)

LAM = sp.Symbol("lam")
x, y, z = sp.symbols("x y z")


def _nambu(F) -> Bivector:
    X = (x, y, z)
    return Bivector(X, sp.ImmutableMatrix(3, 3, lambda i, j: sum(
        sp.LeviCivita(i, j, k) * sp.diff(F, X[k]) for k in range(3))))


def _proportional(p, q, coords) -> bool:
    """``p = c q`` with ``c`` free of the coordinates and non-zero."""
    r = sp.cancel(p / q)
    return r != 0 and not (r.free_symbols & set(coords))


def periodic_toda3():
    a = list(sp.symbols("a1:4"))
    b = list(sp.symbols("b1:4"))
    lin, quad = {}, {}
    for i in range(3):
        j = (i + 1) % 3
        lin[(a[i], b[i])], lin[(a[i], b[j])] = -a[i], a[i]
        quad[(a[i], b[i])], quad[(a[i], b[j])] = -a[i] * b[i], a[i] * b[j]
        quad[(b[i], b[j])] = 2 * a[i] ** 2
        quad[(a[i], a[j])] = a[i] * a[j] / 2
    return bivector_of(a + b, lin), bivector_of(a + b, quad), a, b


def test_so3_against_twice_so3_gives_the_norm():
    m = so3().coords
    found = pencil_casimirs(so3(), so3() * 2, 2)
    assert len(found) == 1
    assert _proportional(found[0], sum(v ** 2 for v in m), m)


def test_central_coordinate_is_kept():
    c = sp.Symbol("c")
    X = [x, y, c]
    P1 = bivector_of(X, {(x, y): c})
    P2 = bivector_of(X, {(x, y): c ** 2})
    found = pencil_casimirs(P1, P2, 1)
    assert len(found) == 1 and _proportional(found[0], c, X)
    chains = lenard_magri_chains(P1, P2, 1)
    assert len(chains) == 1 and chains[0].integrals == (c,)


def test_periodic_toda_keeps_the_product_of_the_a():
    P1, P2, a, _b = periodic_toda3()
    prod = a[0] * a[1] * a[2]
    # truth by hand: {a_i, a_1 a_2 a_3} and {b_i, a_1 a_2 a_3} vanish for both brackets
    for P in (P1, P2):
        grad = sp.Matrix([sp.diff(prod, v) for v in P.coords])
        assert sp.expand(P.matrix * grad) == sp.zeros(6, 1)
    found = pencil_casimirs(P1, P2, 3, LAM)
    assert any(_proportional(C, prod, P1.coords) for C in found)
    assert all(C.free_symbols & set(P1.coords) for C in found)


def test_nambu_pencil_returns_a_true_casimir():
    P1, P2 = _nambu(-z * x), _nambu(z * y)
    Plam = pencil(P1, P2, LAM)
    assert Plam.matrix == _nambu(z * (y + LAM * x)).matrix
    assert not pk.is_casimir(Plam, y + LAM * x)  # the old, wrong answer fails the check
    found = pencil_casimirs(P1, P2, 2, LAM)
    assert len(found) == 1
    assert _proportional(found[0], z * (y + LAM * x), (x, y, z))
    assert pk.is_casimir(Plam, found[0])


def test_constant_casimir_is_refused():
    with pytest.raises(ConstantCasimirError, match="does not depend on the coordinates"):
        lenard_magri_chain(so3(), so3() * 2, 1 + LAM, LAM)
    assert issubclass(ConstantCasimirError, pk.PoissonkitError)
