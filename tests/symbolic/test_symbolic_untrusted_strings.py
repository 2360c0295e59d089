"""No entry point of the symbolic layer evaluates a string (sympy's ``sympify`` would ``eval`` it).

Every entry point that takes "an expression" must refuse a string with ParseError (pointing to
``parse_expression``) or InputError -- and, the real point, must not run it: the payload writes a
marker file, whose absence is checked. Also: ``parse_expression`` refuses exponent towers and
over-long text quickly (they would make sympy compute for hours), and the shared helpers behave
as the duplicated ones should have (repeated coordinates refused everywhere).
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import sympy as sp

from poissonkit.errors import InputError, ParseError
from poissonkit.structure import (
    Bivector,
    HamiltonianSystem,
    check_jacobi,
    parse_expression,
    so3,
)
from poissonkit.structure.casimirs import rank
from poissonkit.structure.checks import divergence, is_first_integral, vanishes
from poissonkit.structure.jacobi import is_zero_expression
from poissonkit.structure.schouten import Multivector

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture
def payload(tmp_path):
    """A string that, if evaluated, creates ``tmp_path / 'pwned'``; the test checks it did not."""
    marker = tmp_path / "pwned"
    yield f"__import__('pathlib').Path({str(marker)!r}).write_text('PWNED')"
    assert not marker.exists(), "the string was executed"


def _so3():
    P = so3()
    mx, my, mz = P.coords
    return P, mx, my, mz


ENTRY_POINTS = {
    "gradient": lambda P, s: P.gradient(s),
    "bracket F": lambda P, s: P.bracket(s, P.coords[0]),
    "bracket G": lambda P, s: P.bracket(P.coords[0], s),
    "hamiltonian_vector_field H": lambda P, s: P.hamiltonian_vector_field(s),
    "hamiltonian_vector_field N": lambda P, s: P.hamiltonian_vector_field(P.coords[0], s),
    "equations_of_motion": lambda P, s: P.equations_of_motion(s),
    "mul": lambda P, s: P * s,
    "rmul": lambda P, s: s * P,
    "subs new": lambda P, s: P.subs(P.coords[0], s),
    "subs old": lambda P, s: P.subs(s, 1),
    "subs dict": lambda P, s: P.subs({P.coords[0]: s}),
    "subs pairs": lambda P, s: P.subs([(P.coords[0], s)]),
    "rank point mapping": lambda P, s: rank(P, point={"m_x": s, "m_y": 1, "m_z": 2}),
    "rank point sequence": lambda P, s: rank(P, [s, 1, 2]),
    "check_jacobi constraints": lambda P, s: check_jacobi(P, constraints=[s]),
    "check_jacobi parametrization": lambda P, s: check_jacobi(
        P, method="random", constraints=[P.coords[2]], parametrization={"m_x": s}),
    "vanishes": lambda P, s: vanishes(s),
    "vanishes constraints": lambda P, s: vanishes(P.coords[0], [s]),
    "is_zero_expression": lambda P, s: is_zero_expression(s),
    "is_first_integral": lambda P, s: is_first_integral(
        HamiltonianSystem(P, P.coords[0] ** 2), s),
    "multivector component": lambda P, s: Multivector(1, P.coords, {(0,): s}),
    "system hamiltonian": lambda P, s: HamiltonianSystem(P, s),
    "system multiplier": lambda P, s: HamiltonianSystem(P, P.coords[0], multiplier=s),
    "system casimirs": lambda P, s: HamiltonianSystem(P, P.coords[0], casimirs={"C": s}),
    "system integrals": lambda P, s: HamiltonianSystem(P, P.coords[0], integrals={"F": s}),
    "system measure": lambda P, s: HamiltonianSystem(P, P.coords[0], measure=s),
    "system constraints": lambda P, s: HamiltonianSystem(P, P.coords[0], constraints=(s,)),
    "system original": lambda P, s: HamiltonianSystem(P, P.coords[0],
                                                      original={P.coords[0]: s}),
}


@pytest.mark.parametrize("entry", sorted(ENTRY_POINTS))
def test_string_expression_is_refused_and_never_executed(entry, payload):
    P = so3()
    with pytest.raises(ParseError, match="parse_expression"):
        ENTRY_POINTS[entry](P, payload)


def test_string_refusal_keeps_non_string_inputs_working():
    # the same entry points with sympy / Python numbers still give the so(3) brackets
    P, mx, my, mz = _so3()
    assert P.bracket(mx, my) == mz                       # {m_x, m_y} = m_z (so3 convention)
    assert (2 * P).matrix == 2 * P.matrix and (P * sp.Rational(1, 2)).matrix == P.matrix / 2
    assert rank(P, point={"m_x": 1.5, "m_y": 0, "m_z": 0}) == 2
    assert rank(P, [0, 0, 0]) == 0
    assert P.subs(mx, 0).matrix[1, 2] == 0
    assert vanishes(P.bracket(mx * mx + my * my + mz * mz, mx))   # |m|^2 is a Casimir


def test_non_expression_objects_get_a_typed_error():
    P, mx, _, _ = _so3()
    with pytest.raises(InputError, match="Hamiltonian"):
        P.hamiltonian_vector_field(object())
    with pytest.raises(InputError, match="scalar"):
        P.gradient(sp.Matrix([mx]))


# ------------------------------------------------------------------ parse_expression DoS
@pytest.mark.timeout(20)
@pytest.mark.parametrize("text, why", [
    ("9**9**9", "tower"),
    ("2**(3**5)", "tower"),
    ("x**(2**3)", "tower"),
    ("x**1001", "exceeds 1000"),
    ("x**-5000", "exceeds 1000"),
    ("2**(400*3)", "exceeds 1000"),
    ("(10**1000)**1000", "digits"),
    ("x + " * 2600 + "x", "characters long"),
], ids=["tower", "tower2", "tower-symbolic-base", "exponent", "negative-exponent",
        "product-exponent", "huge-constant", "too-long"])
def test_parse_expression_refuses_runaway_sizes_quickly(text, why):
    with pytest.raises(ParseError, match=why):
        parse_expression(text, [sp.Symbol("x", real=True)])


def test_parse_expression_keeps_ordinary_powers():
    x, y = sp.symbols("x y", real=True)
    assert parse_expression("x**1000", [x]) == x ** 1000
    assert parse_expression("x^-3 + 2**10", [x]) == x ** -3 + 1024
    assert parse_expression("x**(1/2) * y**y", [x, y]) == sp.sqrt(x) * y ** y
    assert parse_expression("(x + 1)**3 / 2", [x]) == (x + 1) ** 3 / 2


# ------------------------------------------------------------------ shared helpers
def test_repeated_coordinates_refused_by_the_checks_as_by_bivector():
    with pytest.raises(InputError, match="repeated coordinate"):
        Bivector.from_matrix(sp.zeros(2, 2), ["x", "x"])
    x = sp.Symbol("x", real=True)
    with pytest.raises(InputError, match="repeated coordinate"):
        divergence([x, 2 * x], coords=["x", "x"])
    with pytest.raises(InputError, match="repeated coordinate"):
        is_first_integral([x, x], x, coords=["x", "x"])


def test_architecture_doc_names_are_exported_by_poissonkit_structure():
    # docs/architecture.md lists these under poissonkit.structure; all must import from there
    from poissonkit import structure

    text = (ROOT / "docs" / "architecture.md").read_text()
    section = text.split("## Symbolic layer (`poissonkit.structure`)", 1)[1].split("\n## ", 1)[0]
    bullets = re.findall(r"^\* `(?:casimirs|checks|poisson_map)\.py`:(.*?)(?=^\* |\Z)", section,
                         flags=re.MULTILINE | re.DOTALL)
    names = {n for b in bullets for n in re.findall(r"`([A-Za-z_]\w*)[`(]", b)}
    assert {"rank", "find_casimirs", "is_casimir", "divergence", "push_forward"} <= names
    missing = sorted(n for n in names if not hasattr(structure, n))
    assert not missing, f"not exported by poissonkit.structure: {missing}"
    assert set(names) <= set(structure.__all__)
