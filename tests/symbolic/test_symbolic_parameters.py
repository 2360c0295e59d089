"""Parameters in text: declared once, the same sympy symbols in brackets, Hamiltonians and JSON.

Truth: the same objects built from sympy symbols by hand (no parser involved); the so(3)
Casimir |x|^2 and Plank's Lotka–Volterra bracket {x_i, x_j} = a_ij x_i x_j, which is Poisson
for every antisymmetric ``a`` (Plank, J. Math. Phys. 36 (1995) 3520).
"""

from __future__ import annotations

import json

import pytest
import sympy as sp

import poissonkit as pk
from poissonkit.errors import InputError, ParseError
from poissonkit.structure.parsing import declare_parameters
from poissonkit.structure.verification.loading import load_structure_json

X = sp.symbols("x1 x2 x3", real=True)


def test_from_components_reads_declared_parameters():
    a, b = sp.Symbol("a", real=True), sp.Symbol("b", positive=True)
    P = pk.Bivector.from_components({(1, 2): "-a*x1*x2/b"}, ["x1", "x2"],
                                    params={"a": None, "b": {"positive": True}})
    x1, x2 = X[:2]
    assert P.matrix[0, 1] == -a * x1 * x2 / b               # the very symbols, with assumptions
    assert P.matrix[0, 1].subs(b, 2) == -a * x1 * x2 / 2
    assert sp.sqrt(b ** 2) == b and (P.matrix[0, 1] * b).is_polynomial(x1, x2)


def test_unknown_name_lists_the_allowed_ones():
    with pytest.raises(ParseError) as info:
        pk.Bivector.from_components({(1, 2): "-a*x1*x2/c"}, ["x1", "x2"], params=["a", "b"])
    msg = str(info.value)
    assert "'c' is not allowed" in msg and "allowed: x1, x2, a, b" in msg and "params=" in msg
    # and without params the old message: the parameter itself is unknown
    with pytest.raises(ParseError, match="'a' is not allowed"):
        pk.Bivector.from_components({(1, 2): "-a*x1*x2"}, ["x1", "x2"])


@pytest.mark.parametrize("params, match", [
    ("a b", "sequence of names"),
    (["x1"], "name of a coordinate"),
    (["a", "a"], "declared twice"),
    (["sin"], "function or constant"),
    (["__class__"], "not an identifier"),
    (["a.b"], "not an identifier"),
    ({"a": {"positve": True}}, "assumption"),
    ({"a": {"positive": "yes"}}, "assumption"),
    ({"a": sp.Symbol("b")}, "declared as the symbol"),
])
def test_bad_parameter_declarations_are_typed(params, match):
    with pytest.raises(InputError, match=match):
        pk.Bivector.from_components({(1, 2): "x1"}, ["x1", "x2"], params=params)


def test_parse_expression_takes_params():
    k = sp.Symbol("k", positive=True)
    e = pk.parse_expression("sqrt(k**2)*x1", X, params={"k": {"positive": True}})
    assert e == k * X[0]                                     # positivity used: sqrt(k^2) = k
    assert declare_parameters([sp.Symbol("m", integer=True)])["m"].is_integer


def test_text_hamiltonian_uses_the_brackets_parameter_symbols():
    # Plank's bracket on R^3 with parameters, H = x1 + x2 + x3 as text
    P = pk.Bivector.from_components({(1, 2): "a*x1*x2", (1, 3): "b*x1*x3", (2, 3): "c*x2*x3"},
                                    ["x1", "x2", "x3"], params={"a": None, "b": None,
                                                                "c": {"positive": True}})
    S = pk.HamiltonianSystem(P, "x1 + x2 + x3 + c", casimirs={"logC": "c*log(x1)"})
    a, b = sp.symbols("a b", real=True)
    c = sp.Symbol("c", positive=True)
    assert S.hamiltonian == sum(X) + c                      # c of H *is* the bracket's c
    x1, x2, x3 = X
    expected = sp.Matrix([x1 * (a * x2 + b * x3), x2 * (-a * x1 + c * x3),
                          x3 * (-b * x1 - c * x2)])
    assert sp.expand(S.vector_field() - expected) == sp.zeros(3, 1)
    assert pk.check_jacobi(P).is_poisson
    # names of params (values) are allowed too; others are refused with the allowed list
    S2 = pk.HamiltonianSystem(P, "m*x1", params={"m": 2})
    assert S2.hamiltonian == sp.Symbol("m", real=True) * x1
    with pytest.raises(ParseError, match="'zz' is not allowed.*x1, x2, x3, a, b, c"):
        pk.HamiltonianSystem(P, "zz*x1")


def test_json_params_match_from_components(tmp_path):
    data = {"coords": ["x1", "x2"], "bivector": {"1,2": "-a*x1*x2/b"},
            "params": {"a": None, "b": {"positive": True}}}
    path = tmp_path / "lv.json"
    path.write_text(json.dumps(data))
    _, P = load_structure_json(str(path))
    Q = pk.Bivector.from_components({(1, 2): "-a*x1*x2/b"}, ["x1", "x2"],
                                    params={"a": None, "b": {"positive": True}})
    assert P.matrix == Q.matrix
    _, P_list = load_structure_json({**data, "params": ["a", "b"]})
    assert P_list.matrix == pk.Bivector.from_components(
        {(1, 2): "-a*x1*x2/b"}, ["x1", "x2"], params=["a", "b"]).matrix
    for bad in ({"a": 1}, "a", [1]):
        with pytest.raises(InputError, match='"params"'):
            load_structure_json({**data, "params": bad})
    with pytest.raises(InputError, match='"params".*coordinate'):
        load_structure_json({**data, "params": ["x1"]})


def test_parameter_payload_is_never_run(tmp_path):
    marker = tmp_path / "pwned"
    payload = f"__import__('pathlib').Path({str(marker)!r}).write_text('x')"
    with pytest.raises(InputError):
        pk.Bivector.from_components({(1, 2): "x1"}, ["x1", "x2"], params=[payload])
    with pytest.raises(ParseError):
        pk.Bivector.from_components({(1, 2): payload}, ["x1", "x2"], params=["a"])
    with pytest.raises(ParseError):
        pk.HamiltonianSystem(pk.so3(), payload, params={"a": 1})
    assert not marker.exists()
