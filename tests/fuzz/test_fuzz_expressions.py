"""Fuzzing the expression parser and the :class:`~poissonkit.structure.Bivector` constructors.

Property (see ``fuzzkit``): each input gives a finite sympy expression / a valid antisymmetric
bivector, or a typed :class:`~poissonkit.errors.PoissonkitError`; never another exception, a
hang, a NaN or the execution of a payload.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from hypothesis import given
from hypothesis import strategies as st

from fuzzkit import FAST, SLOW, assert_finite, outcome, payloads, slow, special_floats
from strategies import expressions, huge, plain_expressions, scalars
from poissonkit.structure import Bivector
from poissonkit.structure.parsing import parse_expression

X = sp.symbols("x1 x2 x3", real=True)


def _finite_expr(e: sp.Expr, what: str) -> None:
    assert isinstance(e, sp.Basic), f"{what}: not a sympy object: {e!r}"
    assert not e.has(sp.nan, sp.zoo, sp.oo, -sp.oo), f"{what}: non-finite {e}"


def _parse(text: str) -> None:
    e = outcome("parser", lambda: parse_expression(text, X))
    if e is not None:
        _finite_expr(e, repr(text))


@pytest.mark.timeout(300)
@FAST
@given(expressions)
def test_parser_returns_a_finite_expression_or_a_parse_error(text):
    _parse(text)


# ids by position: each payload names this process's random marker file, and xdist's workers
# must collect the same test ids
@pytest.mark.parametrize("payload", payloads(),
                         ids=[f"payload{i}" for i in range(len(payloads()))])
def test_parser_never_executes_a_payload(payload):
    _parse(payload)


# ------------------------------------------------------------------ Bivector from components
_keys = st.one_of(
    st.sampled_from([(1, 2), (1, 3), (2, 3)]),
    st.tuples(st.integers(-2, 5), st.integers(-2, 5)),
    st.tuples(st.integers(1, 3), st.integers(1, 3), st.integers(1, 3)),
    st.sampled_from([(1,), (), "12", (1.5, 2), (True, 2), ("1", "2"), (None, 1), (10**30, 1)]),
    st.tuples(huge, st.integers(1, 3)),
)
_component_values = st.one_of(plain_expressions, expressions, scalars, st.sampled_from([sp.nan, sp.zoo, sp.oo,
                                                                       sp.Symbol("x1"), X[0]]))


def _bivector(make):
    P = outcome("Bivector", make, fields=())
    if P is not None:
        assert isinstance(P, Bivector)
        M = P.matrix
        assert M.shape == (P.dim, P.dim)
        assert all(sp.expand(M[i, j] + M[j, i]) == 0 for i in range(P.dim) for j in range(P.dim))
        for e in M:
            _finite_expr(e, "bivector entry")


def _from_components(comps, coords):
    def make():
        # a dict can only hold hashable keys: unhashable ones never reach the constructor
        return Bivector.from_components(dict(comps), coords)
    _bivector(make)


_coords = st.one_of(st.just(["x1", "x2", "x3"]), st.just(list(X)),
                    st.lists(st.sampled_from(["x1", "x2", "x3", "a", "", "1x", "x y", "I"]),
                             max_size=4),
                    st.sampled_from([[], ["x1", "x1"], [1, 2], "x1", None, [None], [X[0], "x1"]]))


@pytest.mark.timeout(300)
@FAST
@given(st.lists(st.tuples(_keys, _component_values), max_size=4), _coords)
def test_bivector_from_components(comps, coords):
    _from_components(comps, coords)


# ------------------------------------------------------------------ Bivector from matrices
_entries = st.one_of(st.integers(-5, 5), st.sampled_from(special_floats()),
                     st.sampled_from([X[0], X[1], -X[0], sp.nan, sp.zoo, "x1", None, [1], b"x",
                                      1 + 2j, sp.Symbol("x1")]),
                     st.floats(allow_nan=True, allow_infinity=True))


@st.composite
def _matrices(draw):
    n = draw(st.integers(0, 4))
    if draw(st.booleans()):  # antisymmetric by construction, entries from the pool
        m = [[0] * n for _ in range(n)]
        for i in range(n):
            for j in range(i + 1, n):
                e = draw(_entries)
                m[i][j] = e
                try:
                    m[j][i] = -e
                except TypeError:
                    m[j][i] = e
    else:
        m = draw(st.lists(st.lists(_entries, max_size=4), max_size=4))
    kind = draw(st.sampled_from(["list", "numpy", "numpy_object", "sympy", "ragged"]))
    if kind == "numpy":
        try:
            return np.array(m, dtype=float), n
        except (TypeError, ValueError):
            return m, n
    if kind == "numpy_object":
        arr = np.empty((len(m),), dtype=object)
        for i, row in enumerate(m):
            arr[i] = row
        return arr, n
    if kind == "sympy":
        try:
            return sp.Matrix(m), n
        except Exception:  # noqa: BLE001 -- sympy refuses some pools; keep the raw list
            return m, n
    if kind == "ragged" and m:
        m = [row[: max(0, len(row) - 1)] for row in m]
    return m, n


@pytest.mark.timeout(300)
@FAST
@given(_matrices(), _coords)
def test_bivector_from_matrix(matrix_n, coords):
    matrix, _ = matrix_n
    _bivector(lambda: Bivector.from_matrix(matrix, coords))


@slow
@pytest.mark.timeout(3600)
@SLOW
@given(expressions)
def test_parser_slow(text):
    _parse(text)


@slow
@pytest.mark.timeout(3600)
@SLOW
@given(st.one_of(st.tuples(st.just("c"), st.lists(st.tuples(_keys, _component_values),
                                                     max_size=4), _coords),
                 st.tuples(st.just("m"), _matrices(), _coords)))
def test_bivector_slow(case):
    kind, data, coords = case
    if kind == "c":
        _from_components(data, coords)
    else:
        _bivector(lambda: Bivector.from_matrix(data[0], coords))
