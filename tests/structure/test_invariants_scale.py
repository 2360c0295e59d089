"""Invariants of the classical families, computed in the sparse ring, against independent truth.

* Traces of powers and Pfaffians: evaluated at a random integer point and compared with the
  numeric matrix ``X`` at that point (integer matrix powers, ``Pf^2 = det``).
* ``e(n)``, ``se(n)``: the number of invariants equals ``dim - rank`` (the index; the rank is
  the generic rank of the Lie–Poisson matrix), each is a Casimir (exact check), they are
  functionally independent (Jacobian rank at a random point), and for ``e(4)`` their degrees
  match those of the generators found by the Casimir search ((2, 4)).
"""

from __future__ import annotations

import random
import time

import pytest
import sympy as sp

import poissonkit as pk
from poissonkit.structure.lie_algebras import lie_algebra


def _point(coords, seed=7):
    rnd = random.Random(seed)
    return {c: sp.Integer(rnd.randint(-5, 5)) for c in coords}


@pytest.mark.parametrize("name", ["so(7)", "sp(6)", "sl(5)", "so(3,2)", "su(3)", "so(6)"])
def test_traces_match_numeric_powers(name):
    g = lie_algebra(name)
    t = time.process_time()
    inv = g.invariants()
    elapsed = time.process_time() - t
    assert elapsed < 20  # < 2 s on an idle machine (benchmarks/bench_invariants.py); was 54 s
    pt = _point(g.coords)
    X = sp.Matrix(g.matrix).subs(pt)
    for label, expr in inv.items():
        if label.startswith("tr("):
            k = int(label.split("^")[1].rstrip(")"))
            M = -sp.I * X if label.startswith("tr(H") else X
            assert sp.expand(expr.xreplace(pt)) == sp.expand((M ** k).trace()), label
        else:  # Pfaffian: Pf^2 = det, and a wrong sign/entry breaks the square generically
            eta = sp.diag(*[1] * g.matrix.rows) if label == "Pf(X)" else None
            if eta is None:
                continue
            assert sp.expand(expr.xreplace(pt)) ** 2 == (X * eta).det(), label


def test_pfaffian_of_so6_squares_to_det_symbolically_at_points():
    g = lie_algebra("so(6)")
    pf = g.invariants()["Pf(X)"]
    for seed in range(3):
        pt = _point(g.coords, seed)
        assert pf.xreplace(pt) ** 2 == sp.Matrix(g.matrix).subs(pt).det()
    assert pf != 0


@pytest.mark.parametrize("name", ["e(2)", "e(3)", "se(3)", "e(4)", "se(4)", "e(5)", "se(5)",
                                  pytest.param("e(6)", marks=pytest.mark.slow)])
def test_euclidean_invariants_are_complete(name):
    g = lie_algebra(name)
    inv = list(g.invariants().values())
    r = pk.rank(g.bivector)
    assert len(inv) == g.dim - r
    n = int(name.split("(")[1].rstrip(")"))
    assert len(inv) == (n + 1) // 2  # index of e(n)
    for C in inv:
        assert pk.is_casimir(g.bivector, C)
    pt = _point(g.coords, 3)
    J = sp.Matrix([[sp.diff(C, x).subs(pt) for x in g.coords] for C in inv])
    assert J.rank() == len(inv)


def test_e4_degrees_match_the_casimir_search():
    g = lie_algebra("e(4)")
    degs = sorted(sp.Poly(C, *g.coords).total_degree() for C in g.invariants().values())
    found = pk.find_casimirs(g.bivector, 4)
    assert degs == sorted(sp.Poly(C, *g.coords).total_degree() for C in found) == [2, 4]


def test_completeness_check_can_fail():
    # dropping the quartic leaves fewer invariants than dim - rank
    g = lie_algebra("e(4)")
    inv = g.invariants()
    assert len({k: v for k, v in inv.items() if k != "D_2"}) < g.dim - pk.rank(g.bivector)
