"""Fuzzing scene files: mutations of every shipped scene (``poissonkit/scene/shipped/*.toml``).

Mutations at random places of the parsed file: deleted keys and tables, swapped types,
NaN/inf/negative/zero values, unknown names (keys, potentials, integrators, models), huge sizes,
payload strings; plus raw-text damage of the TOML. Property (see ``fuzzkit``): a validated
:class:`~poissonkit.scene.Scene`, or a :class:`~poissonkit.errors.SceneError` whose message
names the mutated field.
"""

from __future__ import annotations

import copy
import math
import tomllib
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from fuzzkit import FAST, SLOW, outcome, payloads, slow, special_floats
from strategies import huge, values
from poissonkit.scene import Scene
from poissonkit.scene.loader import loads_scene
from poissonkit.scene.schema import scene_from_mapping

ROOT = Path(__file__).resolve().parents[2]
SCENE_FILES = sorted((ROOT / "poissonkit" / "scene" / "shipped").glob("*.toml"))
TEXTS = {p.name: p.read_text() for p in SCENE_FILES}
SCENES = {name: tomllib.loads(text) for name, text in TEXTS.items()}


def _paths(node, prefix=()):
    """Every (path, value) in a parsed scene; a path is a tuple of keys and list indices."""
    yield prefix, node
    if isinstance(node, dict):
        for k, v in node.items():
            yield from _paths(v, prefix + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from _paths(v, prefix + (i,))


_replacements = st.one_of(
    values, huge, st.sampled_from(special_floats()), st.sampled_from(payloads()),
    st.sampled_from(["no_such_potential", "no_such_integrator", "dipole", "splitting4", "",
                     [math.nan, 0, 0], [0, 0, 0], [1e308, 1e308, 1e308], [], [1, 2],
                     [0.0] * 1000, {"mass": -1}, -1, 0, -0.0, True]),
)


@st.composite
def mutated_scene(draw):
    name = draw(st.sampled_from(sorted(SCENES)))
    data = copy.deepcopy(SCENES[name])
    touched = []
    for _ in range(draw(st.integers(1, 3))):
        paths = [p for p, _ in _paths(data) if p]
        op = draw(st.sampled_from(["delete", "replace", "replace", "unknown", "rename"]))
        path = draw(st.sampled_from(paths)) if paths else ()
        if not path:
            continue
        parent = data
        for k in path[:-1]:
            parent = parent[k]
        last = path[-1]
        if op == "delete":
            gone = parent[last]
            del parent[last]
            # an error may name a required key that went with the deleted table
            touched += [k for p, _ in _paths(gone) for k in p if isinstance(k, str)]
        elif op == "replace":
            parent[last] = copy.deepcopy(draw(_replacements))  # later mutations edit it
        elif op == "unknown" and isinstance(parent, dict):
            parent[draw(st.sampled_from(["massive", "__class__", "eval", "mas", "Run"]))] = 1
        elif op == "rename" and isinstance(parent, dict):
            parent[str(last) + "_x"] = parent.pop(last)
        # the error must name a key on the path (or the table it sits in)
        touched += [str(k) for k in path if isinstance(k, str)] + \
            [f"[{k}]" for k in path if isinstance(k, int)]
    return name, data, touched


def _validate(data, touched):
    got = outcome("scenes", lambda: scene_from_mapping(data, source="fuzz"), touched)
    if got is not None:
        assert isinstance(got, Scene)
        for body in got.bodies:
            for v in body.values():
                if isinstance(v, float):
                    assert math.isfinite(v), body
                elif isinstance(v, tuple):
                    assert all(math.isfinite(x) for x in v), body


def test_every_shipped_scene_is_valid():
    # positive control: the mutations start from scenes that load
    assert len(SCENES) >= 3
    for name, data in SCENES.items():
        assert isinstance(scene_from_mapping(data, source=name), Scene)


@pytest.mark.timeout(300)
@FAST
@given(mutated_scene())
def test_mutated_scenes(case):
    _, data, touched = case
    _validate(data, touched)


@st.composite
def damaged_text(draw):
    text = TEXTS[draw(st.sampled_from(sorted(TEXTS)))]
    for _ in range(draw(st.integers(1, 3))):
        i = draw(st.integers(0, len(text)))
        j = i + draw(st.integers(0, 20))
        text = text[:i] + draw(st.sampled_from(["", "=", "[", "]]", "\"", "nan", "inf", "-",
                                                "1e999", "\n[run]\n", "\x00", "é"])) + text[j:]
    return text


@pytest.mark.timeout(300)
@FAST
@given(damaged_text())
def test_damaged_scene_text(text):
    outcome("scenes", lambda: loads_scene(text, source="fuzz"))


@slow
@pytest.mark.timeout(3600)
@SLOW
@given(st.one_of(mutated_scene(), damaged_text()))
def test_scenes_slow(case):
    if isinstance(case, str):
        outcome("scenes", lambda: loads_scene(case, source="fuzz"))
    else:
        _, data, touched = case
        _validate(data, touched)
