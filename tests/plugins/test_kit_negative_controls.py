"""Negative controls of the kit beyond potentials: a model family whose estimate is too
optimistic or whose costs are out of order, a field whose force is off its gradient or that
reads another attribute than it declares, an assembly that is not deterministic or lets a bad
value through, an integrator that declares the wrong order, an outcome of the wrong dtype —
each fails with a message naming the defect."""

from __future__ import annotations

import math
import random
from dataclasses import replace

import networkx as nx
import numba
import numpy as np
import pytest

from poissonkit.numerics.fields import CompiledField
from poissonkit.plugin import Assembly, ExternalField, OutcomeEntry, Param, model_family
from poissonkit.plugin import integrator as integrator_entry
from poissonkit.testing import (
    CheckFailed,
    check_assembly,
    check_field,
    check_integrator,
    check_model_family,
    check_outcome,
)

MAGNET = {"radius": 1.25e-3, "length": 0.02, "moment": 0.155}


def _failed(run, *args, **kwargs) -> str:
    with pytest.raises(CheckFailed) as info:
        run(*args, **kwargs)
    return str(info.value)


def test_an_optimistic_error_estimate_is_named():
    family = model_family("magnets")
    # dipole against dumbbells only (both closed forms), the estimate a hundred times too small
    cheap = replace(family, name="too_optimistic", models=("dipole", "dumbbell"), costs=(),
                    defaults=(), estimate=lambda m, r, a, b: 0.01 * family.estimate(m, r, a, b))
    text = _failed(check_model_family, cheap, bodies=(MAGNET, MAGNET))
    assert "model family 'too_optimistic'" in text and "exceeds its estimate" in text
    assert "'dipole' at r = " in text


def test_models_out_of_cost_order_are_named():
    family = model_family("magnets")
    reversed_costs = replace(family, name="reversed", costs=tuple(reversed(family.costs)))
    assert "[cost_order]" in _failed(check_model_family, reversed_costs,
                                     bodies=(MAGNET, MAGNET))


@numba.njit
def _skewed_trap(x, y, z, n0, n1, n2, c, P):
    k = c * P[0]
    return 0.5 * k * (x * x + y * y + z * z), 1.01 * k * x, k * y, k * z, 0.0, 0.0, 0.0


def _skewed(params, request, source=None):
    return CompiledField("skewed", _skewed_trap, np.array([params["omega"] ** 2]), reads="mass")


def test_a_field_force_off_its_gradient_and_another_attribute_are_named():
    entry = ExternalField("skewed", "a trap whose x force is 1 % off",
                          params=(Param("omega", "float", "rate [1/s]", unit="1/s"),),
                          reads="charge", build=_skewed)
    text = _failed(check_field, entry)
    assert "[gradient]" in text and "[reads]" in text and "'charge'" in text


def _random_line(n):
    G = nx.Graph()
    for k in range(n):  # an unseeded generator: two builds differ
        G.add_node(k, name=f"b{k}", mass=1.0, r=(random.random(), 0.0, 10.0 * k))
    return G


def _picky(n, shape):
    if shape not in ("line", "ring"):
        raise KeyError(shape)  # not a typed error naming the parameter
    return _random_line(n)


def test_an_assembly_that_is_not_deterministic_or_lets_an_error_through_is_named():
    entry = Assembly("picky", "a line of bodies at random offsets",
                     params=(Param("n", "int", "bodies", positive=True),
                             Param("shape", "str", "line or ring", default="line")),
                     build=_picky)
    text = _failed(check_assembly, entry)
    assert "[deterministic]" in text and "two builds" in text
    assert "[validation] shape = '__not_a_choice__' raises KeyError" in text


@pytest.mark.slow
def test_a_wrong_declared_order_is_named():
    wrong = replace(integrator_entry("splitting4"), order=2)
    text = _failed(check_integrator, wrong, checks=("order",))
    observed = float(text.split("observed order ")[1].split()[0])
    assert abs(observed - 4) < 0.3 and "declared 2" in text


@pytest.mark.slow
def test_an_outcome_of_the_wrong_dtype_is_named():
    entry = OutcomeEntry("half", "always one half", dtype="i1", unit="", fill=math.nan,
                         compute=lambda record: 0.5)
    text = _failed(check_outcome, entry)
    assert "[unit]" in text and "[fill]" in text and "[compute]" in text
