"""Hypothesis strategies shared by the fuzz targets: expression texts and hostile values."""

from __future__ import annotations

import math

from hypothesis import strategies as st

from fuzzkit import payloads, special_floats
from poissonkit.structure.parsing import ALLOWED_FUNCTIONS

NAMES = ["x1", "x2", "x3", "pi", "E", "I", "nan", "inf", "oo", "zoo", "os", "self",
         "__import__", "__class__", "_x", "True", "None", "lambda", "Symbol", "Rational"]
FUNCS = sorted(ALLOWED_FUNCTIONS) + ["eval", "exec", "getattr", "open", "foo", "print"]
OPS = ["+", "-", "*", "/", "**", "^", "%", "//", "@", "&", "<", "==", "."]

_atoms = st.one_of(
    st.sampled_from(NAMES),
    st.integers(-10**12, 10**12).map(str),
    st.sampled_from(["0", "1", "2.5", "1e308", "1e400", "1e-320", "0.0", "10**999", "9**9**9",
                     "1/0", "0/0", "log(0)", "(-1)**Rational(1,2)", "Rational(1, 0)"]),
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.sampled_from(payloads()),
)


def _combine(children):
    return st.one_of(
        st.tuples(children, st.sampled_from(OPS), children).map(lambda t: f"({t[0]}){t[1]}({t[2]})"),
        st.tuples(st.sampled_from(FUNCS), st.lists(children, max_size=3)).map(
            lambda t: f"{t[0]}({', '.join(t[1])})"),
        children.map(lambda s: f"-{s}"),
        st.tuples(children, st.integers(-2000, 2000)).map(lambda t: f"({t[0]})**{t[1]}"),
    )


#: Well-formed expressions in x1, x2, x3 (most of them parse).
plain_expressions = st.recursive(
    st.one_of(st.sampled_from(["x1", "x2", "x3", "pi"]), st.integers(-9, 9).map(str)),
    lambda c: st.one_of(
        st.tuples(c, st.sampled_from(["+", "-", "*", "/", "**"]), c).map(
            lambda t: f"({t[0]}){t[1]}({t[2]})"),
        st.tuples(st.sampled_from(["sin", "cos", "exp", "sqrt", "atan"]), c).map(
            lambda t: f"{t[0]}({t[1]})")),
    max_leaves=6)

#: Texts in and around the expression grammar (plus arbitrary text).
expressions = st.one_of(
    plain_expressions,
    st.recursive(_atoms, _combine, max_leaves=10),
    st.text(max_size=40),
    st.text(alphabet="x123()+-*/^.,e_ '\"[]{}:;", max_size=60),
)

#: Values of any JSON/TOML-ish type, hostile ones included.
scalars = st.one_of(
    st.none(), st.booleans(), st.integers(-10**30, 10**30), st.sampled_from(special_floats()),
    st.floats(allow_nan=True, allow_infinity=True), st.text(max_size=20),
    st.sampled_from(payloads()), st.sampled_from(["", "nan", "inf", "1e999", "-0", "3"]),
)
values = st.recursive(scalars, lambda c: st.one_of(st.lists(c, max_size=4),
                                                   st.dictionaries(st.text(max_size=8), c,
                                                                   max_size=3)),
                      max_leaves=6)
#: Huge sizes: counts and magnitudes far beyond what any input should carry.
huge = st.sampled_from([10**6, 10**9, 10**18, 2**63, -2**63, 10**400, 1e300, -1e300,
                        math.ldexp(1.0, 1023)])
