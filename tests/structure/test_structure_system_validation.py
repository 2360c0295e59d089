"""HamiltonianSystem validates its fields; bivectors with non-finite entries are named as such.

Truth: the so(3) bracket {m_x, m_y} = m_z (FORMULAS.md §2's e(3) restricted to m) and the
rigid body's equations for H = sum m_i^2 / (2 I_i) in poissonkit's convention
(poissonkit.conventions: mdot = dH/dm x m = omega x m).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

from poissonkit.errors import InputError, ParseError, UnknownNameError
from poissonkit.structure import Bivector, HamiltonianSystem, so3

I1, I2, I3 = sp.symbols("I1 I2 I3", positive=True)


def _rigid_body(**kw):
    P = so3()
    mx, my, mz = P.coords
    H = mx ** 2 / (2 * I1) + my ** 2 / (2 * I2) + mz ** 2 / (2 * I3)
    return HamiltonianSystem(P, H, **kw)


def test_valid_system_converts_numbers_and_keeps_euler_equations():
    S = _rigid_body(multiplier=1, measure=1, casimirs={"C": so3().coords[0] ** 2},
                    constraints=[0], params={"I1": 1.0, "I2": sp.Rational(2), "I3": np.float64(3)})
    assert S.multiplier == 1 and isinstance(S.multiplier, sp.Expr)
    assert isinstance(S.measure, sp.Expr) and S.constraints == (sp.Integer(0),)
    mx, my, mz = S.coords
    # poissonkit.conventions: mdot = omega x m with omega_i = dH/dm_i = m_i / I_i
    X = S.vector_field()
    omega = (mx / I1, my / I2, mz / I3)
    expected = sp.Matrix(omega).cross(sp.Matrix([mx, my, mz]))
    assert sp.simplify(X - expected) == sp.zeros(3, 1)


@pytest.mark.parametrize("field, value, error", [
    ("structure", sp.eye(3), InputError),
    ("params", {"I1": math.nan}, InputError),
    ("params", {"I1": math.inf}, InputError),
    ("params", {"I1": sp.oo}, InputError),
    ("params", {"I1": (1.0, math.nan)}, InputError),
    ("params", {"I1": object()}, InputError),
    ("params", {"I1": True}, InputError),
    ("params", [("I1", 1.0)], InputError),
    ("casimirs", [sp.Integer(1)], InputError),
    ("constraints", "gamma**2 - 1", InputError),
    ("hamiltonian", "m_w**2", ParseError),          # text: only known names are read
])
def test_invalid_fields_raise_typed_errors(field, value, error):
    kw = {"structure": so3(), "hamiltonian": so3().coords[0] ** 2, field: value}
    with pytest.raises(error):
        HamiltonianSystem(**kw)


def test_with_params_accepts_known_names_and_rejects_unknown_ones():
    S = _rigid_body(params={"I1": 1.0})
    assert S.with_params(I1=2.0).params == {"I1": 2.0}
    assert S.with_params(I2=5.0).params == {"I1": 1.0, "I2": 5.0}   # symbolic parameter of H
    with pytest.raises(UnknownNameError) as info:
        S.with_params(I4=1.0)                       # a typo would otherwise be silently ignored
    assert "I4" in str(info.value) and all(n in str(info.value) for n in ("I1", "I2", "I3"))
    assert "m_x" not in info.value.available          # coordinates are not parameters
    with pytest.raises(InputError):
        S.with_params(I1=math.nan)


@pytest.mark.parametrize("bad", [math.nan, math.inf, sp.nan, sp.zoo])
def test_non_finite_bivector_entry_is_reported_as_non_finite(bad):
    with pytest.raises(InputError, match="not finite") as info:
        Bivector.from_matrix([[0, bad], [1, 0]] if bad is not sp.zoo else [[0, bad], [bad, 0]],
                             ["a", "b"])
    assert "antisymmetric" not in str(info.value)
    with pytest.raises(InputError, match="not finite"):
        Bivector.from_matrix(np.array([[0.0, bad], [-1.0, 0.0]], dtype=object), ["a", "b"])
