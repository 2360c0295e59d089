"""Parameter designs and paths: grids, lists, seeded random samples, typed errors."""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pytest

from poissonkit.errors import InputError, PoissonkitError, SceneError, UnknownNameError
from poissonkit.sweeps.params import Axis, Range, design_from, grid, parse_param
from poissonkit_magnets.seed000_sweep import SeedScene

from poissonkit.sweeps.targets import TomlScene, set_path

TWO_MAGNETS = Path(__file__).resolve().parents[2] / "poissonkit" / "scene" / "shipped" / "two_magnets.toml"


def test_grid_list_and_range_parse():
    g = parse_param("spin_ratio=0:20:5")
    assert isinstance(g, Axis) and g.values == (0.0, 5.0, 10.0, 15.0, 20.0)
    lst = parse_param("bodies.right.r.0=0.03,0.05")
    assert lst == Axis("bodies.right.r.0", (0.03, 0.05))
    r = parse_param("tilt=0:0.2")
    assert isinstance(r, Range) and (r.low, r.high) == (0.0, 0.2)


def test_grid_design_points_in_c_order():
    d = design_from(["a=0:1:2", "b=5,6,7"])
    assert d.dims == ("a", "b") and d.shape == (2, 3) and d.size == 6
    pts = list(d.points())
    assert pts[0] == (0, {"a": 0.0, "b": 5.0}) and pts[5] == (5, {"a": 1.0, "b": 7.0})
    # the flat index is numpy's C-order index of the grid position
    assert np.ravel_multi_index((1, 2), d.shape) == 5


def test_random_design_is_seeded_and_inside_ranges():
    d1 = design_from({"tilt": (0.0, 0.2), "spin_ratio": (5, 25)}, samples=50, seed=7)
    d2 = design_from({"tilt": (0.0, 0.2), "spin_ratio": (5, 25)}, samples=50, seed=7)
    d3 = design_from({"tilt": (0.0, 0.2), "spin_ratio": (5, 25)}, samples=50, seed=8)
    v1, v2, v3 = d1.sample_values(), d2.sample_values(), d3.sample_values()
    assert d1.dims == ("sample",) and d1.shape == (50,)
    assert np.array_equal(v1["tilt"], v2["tilt"]) and not np.array_equal(v1["tilt"], v3["tilt"])
    assert v1["tilt"].min() >= 0 and v1["tilt"].max() <= 0.2
    assert v1["spin_ratio"].min() >= 5 and v1["spin_ratio"].max() <= 25


@pytest.mark.parametrize("text,needle", [
    ("spin_ratio", "PATH="),
    ("tilt=a,b", "numbers"),
    ("tilt=0:1:x", "count"),
    ("tilt=0:1:2:3", "start:stop:count"),
    ("tilt=1:0", "low < high"),
    ("tilt=nan,1", "finite"),
    ("tilt=1,1", "repeat"),
])
def test_bad_parameter_text_is_a_typed_error(text, needle):
    with pytest.raises(InputError, match=needle):
        design_from([text], samples=3 if text.count(":") == 1 else None)


def test_range_without_samples_and_grid_with_samples_are_refused():
    with pytest.raises(InputError, match="--random"):
        design_from(["tilt=0:1"])
    with pytest.raises(InputError, match="range"):
        design_from(["tilt=0:1:3"], samples=4)
    with pytest.raises(InputError, match="twice"):
        design_from([grid("tilt", 0, 1, 2), grid("tilt", 0, 1, 3)])


def test_seed_named_parameters_and_aliases():
    s = SeedScene()
    assert s.check("initial.tilt") == "tilt" and s.units("tilt") == "rad"
    assert s.units("spin_ratio") == "1"
    with pytest.raises(UnknownNameError, match="spin_ratio"):
        s.check("colour")


def test_scene_paths_set_the_right_numbers(tmp_path):
    from poissonkit.scene import load_scene

    src = TWO_MAGNETS
    scene = TomlScene.from_file(src)
    base = load_scene(src)
    moved = scene.scene_with({"bodies.right.r.0": 0.05, "run.step": 5e-5,
                              "bodies.right.spin": 2e-6})
    right = {b["name"]: b for b in moved.bodies}["right"]
    assert right["r"] == (0.05, 0.0, 0.0)
    # spin is |m| along the body's own axis (nu = -z in the file)
    assert right["m"] == (0.0, 0.0, -2e-6)
    assert moved.run.step == 5e-5
    assert {b["name"]: b for b in base.bodies}["right"]["r"] == (0.04, 0.0, 0.0)  # untouched
    assert scene.units("bodies.right.r.0") == "m" and scene.units("run.step") == "s"


def test_interaction_shorthand_path_reaches_the_pair_params():
    data = {"interactions": {"pair": [{"bodies": ["a", "b"], "potential": "dumbbell",
                                       "params": {"tol": 1.0}}]}}
    d = copy.deepcopy(data)
    set_path(d, "interactions.0.tol", 0.25)
    assert d["interactions"]["pair"][0]["params"]["tol"] == 0.25


@pytest.mark.parametrize("path,err,needle", [
    ("bodies.nobody.mass", UnknownNameError, "left, right"),
    ("bodies.right.r", SceneError, "append .0"),
    ("name", SceneError, "not a number"),
    ("run.colour", SceneError, "run.colour"),
    ("bodies.5.mass", SceneError, "out of range"),
])
def test_bad_scene_paths_name_the_path(path, err, needle):
    scene = TomlScene.from_file(TWO_MAGNETS)
    with pytest.raises(err, match=needle):
        scene.check(path)
    assert issubclass(err, PoissonkitError)


def test_invalid_value_is_a_scene_error_naming_the_field():
    scene = TomlScene.from_file(TWO_MAGNETS)
    with pytest.raises(SceneError, match=r"bodies\[1\].mass"):
        scene.scene_with({"bodies.right.mass": -1.0})
