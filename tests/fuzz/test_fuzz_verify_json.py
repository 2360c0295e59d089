"""Fuzzing PoissonGeometry-format JSON structures read by ``poissonkit verify``.

Mutations of valid files (so(3), e(3) with parameters, a 5-dim non-Poisson bracket): deleted
keys, swapped types, hostile values, unknown keys, huge dimensions, payload strings, broken
JSON text. Property (see ``fuzzkit``): a Bivector, or a typed error naming the field.
"""

from __future__ import annotations

import copy
import json

import pytest
import sympy as sp
from hypothesis import given
from hypothesis import strategies as st

from fuzzkit import FAST, SLOW, outcome, slow
from strategies import expressions, huge, plain_expressions, values
from poissonkit.commands.verify import JSON_KEYS, load_structure_json
from poissonkit.structure import Bivector

VALID = [
    {"dim": 3, "bivector": {"1,2": "x3", "1,3": "-x2", "2,3": "x1"}},
    {"coords": ["g1", "g2", "g3", "L1", "L2", "L3"], "params": ["k"], "name": "e3",
     "bivector": {"4,5": "L3", "4,6": "-L2", "5,6": "L1", "1,5": "k*g3", "1,6": "-k*g2",
                  "2,4": "-g3", "2,6": "g1", "3,4": "g2", "3,5": "-g1"}},
    {"dim": 5, "variable": "y", "bivector": {"(1,2)": "y1*y2", "2 3": "y3", "4,5": 1,
                                            "1,5": 2.5}},
]


@st.composite
def mutated(draw):
    data = copy.deepcopy(draw(st.sampled_from(VALID)))
    touched = []
    for _ in range(draw(st.integers(1, 3))):
        op = draw(st.sampled_from(["delete", "replace", "unknown", "entry", "entry", "entry",
                                   "key", "huge", "coords"]))
        keys = list(data) if isinstance(data, dict) else []
        if op == "delete" and keys:
            k = draw(st.sampled_from(keys))
            del data[k]
            touched.append(k)
        elif op == "replace" and keys:
            k = draw(st.sampled_from(keys))
            data[k] = draw(values)
            touched.append(k)
        elif op == "unknown":
            k = draw(st.sampled_from(["dims", "Bivector", "__class__", "eval"]))
            data[k] = draw(values)
            touched.append(k)
        elif op == "entry" and isinstance(data.get("bivector"), dict) and data["bivector"]:
            k = draw(st.sampled_from(sorted(data["bivector"])))
            data["bivector"][k] = draw(st.one_of(plain_expressions, expressions, values))
            touched += [k, "bivector"]
        elif op == "key" and isinstance(data.get("bivector"), dict):
            k = draw(st.one_of(st.text(max_size=8), st.sampled_from(
                ["1,1", "0,1", "1,99", "1,2,3", "-1,2", "1e3,2", "9" * 5000 + ",1"])))
            data["bivector"][k] = "1"
            touched += [k[:50], "bivector"]
        elif op == "huge":
            k = draw(st.sampled_from(["dim", "coords", "params"]))
            data[k] = draw(st.one_of(huge, st.just(["x%d" % i for i in range(5000)])))
            touched.append(k)
        elif op == "coords":
            touched += ["coords", "coordinate", "bivector", "dim", "params", "parameter"]
            data["coords"] = draw(st.lists(st.one_of(st.sampled_from(
                ["x1", "x1", "I", "E", "pi", "sin", "lambda", "True", "None", "__import__",
                 "_a", ""]), st.text(max_size=4)), max_size=5))
    return data, touched


def _load(data, as_text=None, tmp=None, fields=()):
    def run():
        if as_text is None:
            return load_structure_json(data)
        path = tmp / "s.json"
        path.write_text(as_text)
        return load_structure_json(path)
    got = outcome("verify JSON", run, fields)
    if got is not None:
        name, P = got
        assert isinstance(name, str) and isinstance(P, Bivector)
        for e in P.matrix:
            assert not e.has(sp.nan, sp.zoo, sp.oo, -sp.oo)


@pytest.mark.timeout(300)
@FAST
@given(mutated())
def test_mutated_json_structures(case):
    data, touched = case
    _load(data, fields=touched)


@pytest.mark.timeout(300)
@FAST
@given(st.sampled_from(VALID).map(json.dumps), st.data())
def test_broken_json_text(tmp_path_factory, text, data):
    tmp = tmp_path_factory.mktemp("json")
    cut = data.draw(st.integers(0, len(text)))
    junk = data.draw(st.text(max_size=5))
    _load(None, text[:cut] + junk + text[cut + data.draw(st.integers(0, 3)):], tmp)


def test_every_valid_file_loads():
    # positive control: the mutations start from files that work
    for data in VALID:
        name, P = load_structure_json(data)
        assert P.dim == (data.get("dim") or len(data["coords"]))
    assert set().union(*VALID) <= set(JSON_KEYS)


@slow
@pytest.mark.timeout(3600)
@SLOW
@given(mutated())
def test_mutated_json_structures_slow(case):
    data, touched = case
    _load(data, fields=touched)
