"""The exact sparse solver of the Hamiltonisation search against sympy's dense linsolve."""

from __future__ import annotations

import random

import sympy as sp

from poissonkit.structure._exact_linear import (
    check_certificate,
    inconsistency_certificate,
    solve_sparse,
)

QQ = sp.QQ


def _random_system(rng: random.Random, nrows: int, ncols: int):
    rows = [{c: QQ(rng.randint(-3, 3), rng.randint(1, 4)) for c in rng.sample(range(ncols), 3)}
            for _ in range(nrows)]
    rhs = [QQ(rng.randint(-2, 2)) for _ in range(nrows)]
    return rows, rhs


def _dense(rows, rhs, ncols):
    A = sp.Matrix([[sp.Rational(r.get(c, 0)) for c in range(ncols)] for r in rows])
    return A, sp.Matrix([sp.Rational(b) for b in rhs])


def test_solve_sparse_agrees_with_linsolve():
    rng = random.Random(7)
    seen = {True: 0, False: 0}
    for trial in range(40):
        nrows, ncols = rng.randint(3, 9), rng.randint(3, 9)
        rows, rhs = _random_system(rng, nrows, ncols)
        A, b = _dense(rows, rhs, ncols)
        xs = sp.symbols(f"x0:{ncols}")
        ref = sp.linsolve((A, b), *xs)
        sol = solve_sparse(rows, rhs, ncols, QQ)
        seen[sol.consistent] += 1
        assert sol.consistent == (ref != sp.EmptySet)
        if sol.consistent:
            assert sol.rank == A.rank()
            u0 = sp.Matrix([sp.Rational(sol.particular.get(c, 0)) for c in range(ncols)])
            assert A * u0 == b
            for d in sol.directions:
                v = sp.Matrix([sp.Rational(d.get(c, 0)) for c in range(ncols)])
                assert A * v == sp.zeros(nrows, 1)
            assert len(sol.directions) == ncols - A.rank()
        else:
            y = inconsistency_certificate(rows, rhs, ncols, QQ)
            assert check_certificate(rows, rhs, ncols, y, QQ)
            yv = sp.Matrix([[sp.Rational(y.get(r, 0)) for r in range(nrows)]])
            assert yv * A == sp.zeros(1, ncols) and (yv * b)[0] == 1
            # a tampered certificate is rejected
            r0 = next(iter(y))
            bad = dict(y)
            bad[r0] = y[r0] + 1
            assert not check_certificate(rows, rhs, ncols, bad, QQ) or \
                not any(rows[r0].values())
    assert seen[True] and seen[False]        # both branches exercised
