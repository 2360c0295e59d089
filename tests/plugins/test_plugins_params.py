"""Typed parameters of registry entries: ``Param.coerce`` refuses what it cannot take exactly."""

from __future__ import annotations

import math

import numpy as np
import pytest

from poissonkit.errors import InputError
from poissonkit.plugin.contributions import Entry, Param


@pytest.mark.parametrize("value", [2.7, -0.5, "2.7", "abc", None, True, math.nan, math.inf])
def test_int_param_rejects_non_integral_values_naming_the_parameter(value):
    with pytest.raises(InputError, match="'n'"):
        Param("n", "int").coerce(value, "chain")


@pytest.mark.parametrize("value", [3, 3.0, "3", " 3 ", np.int64(3), np.float64(3.0)])
def test_int_param_accepts_exact_integers(value):
    out = Param("n", "int").coerce(value)
    assert out == 3 and type(out) is int


@pytest.mark.parametrize("value", [(1.0, math.nan, 0.0), [math.inf, 0.0, 0.0],
                                   ("1", "-inf", "0"), np.array([0.0, 0.0, math.nan])])
def test_vector_param_rejects_non_finite_components(value):
    with pytest.raises(InputError, match="'I'.*finite"):
        Param("I", "vector").coerce(value)


@pytest.mark.parametrize("value", ["123", (), 5.0, None, {"x": 1.0}])
def test_vector_param_rejects_strings_scalars_and_empty(value):
    with pytest.raises(InputError, match="'I'"):
        Param("I", "vector").coerce(value)


def test_vector_param_converts_numeric_strings_from_the_command_line():
    assert Param("I", "vector").coerce(["1", "2", "3.5"]) == (1.0, 2.0, 3.5)


def test_positive_vector_param_requires_every_component_positive():
    param = Param("I", "vector", positive=True)
    assert param.coerce((1.0, 2.0, 3.0)) == (1.0, 2.0, 3.0)
    with pytest.raises(InputError, match="> 0"):
        param.coerce((1.0, 0.0, 3.0))


@pytest.mark.parametrize("value", [None, 3, 1.5, ("a",), b"dipole"])
def test_str_param_rejects_non_strings(value):
    with pytest.raises(InputError, match="'potential'"):
        Param("potential", "str").coerce(value)


@pytest.mark.parametrize("value", [True, math.nan, "inf"])
def test_float_param_rejects_bools_and_non_finite(value):
    with pytest.raises(InputError, match="'k'"):
        Param("k", "float").coerce(value)


def test_resolve_params_error_names_entry_and_parameter():
    entry = Entry("lattice", "doc", (Param("nx", "int", positive=True),))
    assert entry.resolve_params({"nx": "4"}) == {"nx": 4}
    with pytest.raises(InputError, match=r"lattice: parameter 'nx' must be int, got 2\.7"):
        entry.resolve_params({"nx": 2.7})
