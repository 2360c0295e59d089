"""Fuzzing the limits of user JSON and TOML (``poissonkit.input_limits``), and huge numbers in
scenes.

Valid verify JSON and scene TOML texts with hostile pieces spliced in at any place: nesting
around and far past :data:`MAX_DEPTH`, number literals around and far past
:data:`MAX_NUMBER_DIGITS`, lone-surrogate escapes and characters, brackets and digits inside
strings and comments. Property (see ``fuzzkit``): a result or a typed error — never
``RecursionError``, Python's int digit limit or ``UnicodeEncodeError``. Scenes with any number
replaced by a huge or tiny value build or fail with a typed error and print no numpy warning.
"""

from __future__ import annotations

import copy
import json
import tomllib
import warnings
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from fuzzkit import FAST, SLOW, outcome, slow
from poissonkit.input_limits import MAX_DEPTH, MAX_NUMBER_DIGITS, loads_json
from poissonkit.scene import build_run
from poissonkit.scene.loader import loads_scene
from poissonkit.scene.schema import scene_from_mapping
from poissonkit.structure.verification.loading import load_structure_json

ROOT = Path(__file__).resolve().parents[2]
JSON_TEXTS = [json.dumps({"dim": 3, "bivector": {"1,2": "x3", "1,3": "-x2", "2,3": "x1"}},
                         indent=1),
              json.dumps({"coords": ["a", "b", "c", "d"], "params": ["k"],
                          "bivector": {"1,2": "k*c", "3,4": "a"}}, indent=1)]
TOML_TEXTS = {p.name: p.read_text() for p in sorted((ROOT / "poissonkit/scene/shipped").glob("*.toml"))}


def _nesting(draw, opener: str, closer: str) -> str:
    depth = draw(st.one_of(st.integers(MAX_DEPTH - 2, MAX_DEPTH + 2), st.integers(0, 10),
                           st.sampled_from([500, 5_000, 100_000])))
    inner = draw(st.sampled_from(["", "1", '"x"', "1e308"]))
    return opener * depth + inner + closer * depth


@st.composite
def hostile_piece(draw, toml: bool):
    kind = draw(st.sampled_from(["array", "object", "digits", "surrogate", "quoted", "raw"]))
    if kind == "array":
        return _nesting(draw, "[", "]")
    if kind == "object":
        return _nesting(draw, "{a=" if toml else '{"a":', "}")
    if kind == "digits":
        n = draw(st.one_of(st.integers(MAX_NUMBER_DIGITS - 2, MAX_NUMBER_DIGITS + 2),
                           st.sampled_from([4300, 4301, 10**6])))
        return draw(st.sampled_from(["", "-", "0."])) + "7" * n
    if kind == "surrogate":
        return draw(st.sampled_from(['"\\ud800"', '"x\\udfff"', '"\\ud83d\\ude00"', "\ud800",
                                     '"\udc80"']))
    if kind == "quoted":  # brackets and digits as text
        return '"' + draw(st.sampled_from(["[" * 200, "{" * 200, "9" * 3000])) + '"'
    return draw(st.text(max_size=8))


@st.composite
def spliced(draw, texts, toml: bool):
    """A valid text with hostile pieces: as the value of a new key at a line start (so the
    parser reaches them) or anywhere."""
    text = draw(st.sampled_from(texts))
    for _ in range(draw(st.integers(1, 2))):
        piece = draw(hostile_piece(toml))
        if draw(st.booleans()):
            lines = text.split("\n")
            at = draw(st.integers(0, len(lines)))
            entry = f"fuzz = {piece}" if toml else f' "fuzz": {piece},'
            text = "\n".join(lines[:at] + [entry] + lines[at:])
        else:
            at = draw(st.integers(0, len(text)))
            text = text[:at] + piece + text[at + draw(st.integers(0, 4)):]
    return text


def _verify_json(tmp: Path, text: str) -> None:
    path = tmp / "s.json"
    path.write_bytes(text.encode("utf-8", "surrogatepass"))
    outcome("verify JSON limits", lambda: load_structure_json(path))


@pytest.mark.timeout(600)
@FAST
@given(spliced(JSON_TEXTS, toml=False))
def test_verify_json_limits(tmp_path_factory, text):
    _verify_json(tmp_path_factory.mktemp("j"), text)


@pytest.mark.timeout(600)
@FAST
@given(spliced(list(TOML_TEXTS.values()), toml=True))
def test_scene_toml_limits(text):
    outcome("scene TOML limits", lambda: loads_scene(text))


HUGE = [1e300, -1e300, 1e308, 1e-320, 1e100, 1e-300, 10**400, 10**30, 2**63]


def _numbers(node, prefix=()):
    if isinstance(node, dict):
        for k, v in node.items():
            yield from _numbers(v, prefix + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from _numbers(v, prefix + (i,))
    elif isinstance(node, (int, float)) and not isinstance(node, bool):
        yield prefix


SCENES = {name: tomllib.loads(text) for name, text in TOML_TEXTS.items()}
PLACES = [(name, path) for name, data in SCENES.items() for path in _numbers(data)]


@st.composite
def huge_scene(draw):
    name, path = draw(st.sampled_from(PLACES))
    data = copy.deepcopy(SCENES[name])
    node = data
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = draw(st.sampled_from(HUGE))
    return data


@pytest.mark.timeout(600)
@FAST
@given(huge_scene())
def test_huge_scene_numbers_print_no_numpy_warnings(data):
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)  # a numpy warning is a failure
        outcome("scene huge numbers", lambda: build_run(scene_from_mapping(data)))


def test_limits_leave_valid_texts_alone():
    # positive control
    for text in JSON_TEXTS:
        assert loads_json(text, "t") == json.loads(text)
    for text in TOML_TEXTS.values():
        loads_scene(text)


@slow
@pytest.mark.timeout(7200)
@SLOW
@given(spliced(JSON_TEXTS, toml=False))
def test_verify_json_limits_slow(tmp_path_factory, text):
    _verify_json(tmp_path_factory.mktemp("j"), text)


@slow
@pytest.mark.timeout(7200)
@SLOW
@given(spliced(list(TOML_TEXTS.values()), toml=True))
def test_scene_toml_limits_slow(text):
    outcome("scene TOML limits", lambda: loads_scene(text))


@slow
@pytest.mark.timeout(7200)
@SLOW
@given(huge_scene())
def test_huge_scene_numbers_slow(data):
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        outcome("scene huge numbers", lambda: build_run(scene_from_mapping(data)))
