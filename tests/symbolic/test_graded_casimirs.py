"""The graded Casimir search of linear brackets against the ungraded one and the literature.

* Same normal-form generators and relations as the plain null space of the whole system (the
  previous method, forced here by switching the graded path off) on algebras whose gradings
  differ: Z-gradings that are inner (sl, sp, gl), outer ones (heisenberg's scaling), only Z/2
  ones (so(n) in the basis m_ij, where the Pfaffian of so(4) is Z/2-odd), and e(n).
* Degrees of the generators of sl(5) to degree 6 are the exponents + 1 = (2, 3, 4, 5)
  (Chevalley), and sp(6) to degree 6 gives (2, 4, 6).
"""

from __future__ import annotations

import pytest
import sympy as sp

import poissonkit as pk
from poissonkit.structure import Bivector
from poissonkit.structure import casimirs as cas
from poissonkit.structure._graded_casimirs import (
    _constraints,
    _inner,
    _z_weights,
    linear_terms,
)


@pytest.mark.parametrize("name,degree", [
    ("sl(3)", 4), ("sp(4)", 4), ("gl(3)", 3), ("heisenberg(2)", 3), ("so(4)", 4),
    ("so(3,2)", 4), ("e(4)", 4), ("se(3)", 3), ("u(2)", 3)])
def test_graded_equals_ungraded(name, degree, monkeypatch):
    g = pk.lie_algebra(name)
    fast = pk.find_casimirs(g.bivector, degree)
    monkeypatch.setattr(cas, "graded_casimir_rows", lambda *a: None)
    slow = pk.find_casimirs(g.bivector, degree)
    assert fast.generators == slow.generators and fast.relations == slow.relations


def test_outer_grading_keeps_weighted_casimirs():
    # heisenberg {x, y} = z: its gradings (x:1, y:0, z:1 and x:0, y:1, z:1) are outer (ad of
    # any element maps x, y to multiples of z), so they split the search but prune nothing
    x, y, z = sp.symbols("x y z")
    H = Bivector.from_matrix(sp.Matrix([[0, z, 0], [-z, 0, 0], [0, 0, 0]]), (x, y, z))
    rows = _constraints(linear_terms(H))
    zw = _z_weights(rows, 3)
    assert not all(_inner(linear_terms(H), [zw[a][k] for a in range(3)])
                   for k in range(len(zw[0])))
    assert list(pk.find_casimirs(H, 2)) == [z]


@pytest.mark.slow
@pytest.mark.parametrize("name,degree,degs", [("sl(5)", 6, [2, 3, 4, 5]),
                                              ("sp(6)", 6, [2, 4, 6])])
def test_large_algebras_to_degree_six(name, degree, degs):
    g = pk.lie_algebra(name)
    found = pk.find_casimirs(g.bivector, degree)
    assert [sp.Poly(c, *g.coords).total_degree() for c in found] == degs
    for c in found:
        assert pk.is_casimir(g.bivector, c)
