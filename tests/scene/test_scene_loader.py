"""Scene files: the shipped examples load and build, and invalid files fail naming the field."""

from __future__ import annotations

import copy
import math
from pathlib import Path

import numpy as np
import pytest
from scene_magnet_truth import dumbbell_energy

from poissonkit.errors import SceneError
from poissonkit.scene import build_run, load_scene, loads_scene, scene_from_mapping
from poissonkit.scene.geometry import distance, shape_of

ROOT = Path(__file__).resolve().parents[2]  # the project root

EXAMPLES = sorted((ROOT / "poissonkit" / "scene" / "shipped").glob("*.toml"))

BASE = {
    "name": "pair",
    "defaults": {"mass": 7.658e-4, "inertia": 2.5827e-8, "moment": 0.15546875,
                 "radius": 1.25e-3, "length": 0.02},
    "bodies": [
        {"name": "a", "r": [0.0, 0.0, 0.0], "nu": [0.0, 0.0, 1.0]},
        {"name": "b", "r": [0.04, 0.0, 0.0], "nu": [0.0, 0.0, -1.0]},
    ],
    "interactions": {"potential": "dumbbell"},
    "run": {"method": "splitting4", "step": 1e-4, "duration": 0.01},
}


def variant(path: str, value, delete: bool = False) -> dict:
    """BASE with the field at ``path`` (dots, [k] indices) set to ``value`` or deleted."""
    data = copy.deepcopy(BASE)
    keys = path.replace("[", ".").replace("]", "").split(".")
    node = data
    for k in keys[:-1]:
        node = node[int(k)] if k.isdigit() else node[k]
    last = int(keys[-1]) if keys[-1].isdigit() else keys[-1]
    if delete:
        del node[last]
    else:
        node[last] = value
    return data


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_shipped_example_scenes_load_and_build(path):
    scene = load_scene(path)
    spec = build_run(scene)
    system = spec.system
    assert spec.y0.shape == (system.dim,)
    assert spec.t_end * spec.metadata["time_unit_s"] == pytest.approx(scene.run.duration)
    assert spec.step * spec.metadata["time_unit_s"] == pytest.approx(scene.run.step)
    assert spec.method == scene.run.method
    n_bodies = len(scene.bodies) if scene.bodies else scene.assembly[1]["n"]
    assert len(system.bodies) == n_bodies


def test_at_least_three_example_scenes_are_shipped():
    assert len(EXAMPLES) >= 3


def test_two_magnet_scene_energy_equals_the_pole_sum():
    """The built system's energy at t = 0 is the Coulomb energy of the four poles (SI)."""
    spec = build_run(load_scene(ROOT / "poissonkit" / "scene" / "shipped" / "two_magnets.toml"))
    E = spec.system.energy(spec.y0) * spec.system.scales.energy
    truth = dumbbell_energy(np.array([0.04, 0, 0]), [0, 0, 1], [0, 0, -1], 0.15546875, 0.01)
    assert E == pytest.approx(truth, rel=1e-12)


def test_listed_pair_parameters_follow_the_listed_body_order():
    data = copy.deepcopy(BASE)
    data["defaults"] = {"mass": 1e-3, "inertia": 1e-8}
    data["bodies"][0].update(moment=0.1, length=0.02)
    data["bodies"][1].update(moment=0.3, length=0.008)
    data["interactions"] = {"pairs": "listed", "pair": [
        {"bodies": ["b", "a"], "potential": "dumbbell",
         "params": {"half_length1": 0.004, "half_length2": 0.01}}]}
    from poissonkit_nbody import pairs_of

    from poissonkit.numerics.potentials import compile_potential
    from poissonkit.plugin import potential
    from poissonkit.scene import scene_graph

    (spec,) = pairs_of(scene_graph(scene_from_mapping(data)))
    assert (spec.i, spec.j) == (0, 1)  # stored in body order (a, b): the suffixes were swapped
    U = compile_potential(potential("dumbbell"), dict(spec.params))(0.04, 0.0, 0.0, -1.0)[0]
    truth = dumbbell_energy(np.array([0.04, 0, 0]), [0, 0, 1], [0, 0, -1], 0.1, 0.01, 0.3, 0.004)
    assert U == pytest.approx(truth, rel=1e-12)


@pytest.mark.parametrize("path, value, message", [
    ("interactions.potential", "dipol",
     r"^interactions\.potential: unknown potential 'dipol'; available: .*dipole"),
    ("bodies[1].mass", -1.0, r"^bodies\[1\]\.mass: must be > 0, got -1\.0"),
    ("bodies[0].mas", 1.0, r"^bodies\[0\]\.mas: unknown key; allowed: name, mass"),
    ("bodies[0].r", [0.0, 0.0], r"^bodies\[0\]\.r: must be a list of 3 numbers"),
    ("bodies[0].r", "origin", r"^bodies\[0\]\.r: must be a list of 3 numbers"),
    ("bodies[0].nu", [0, 0, 0], r"^bodies\[0\]\.nu: the axis must not be zero"),
    ("bodies[0].fixed", "yes", r"^bodies\[0\]\.fixed: must be true or false"),
    ("bodies[1].name", "a", r"^bodies\[1\]\.name: 'a' is already used by bodies\[0\]"),
    ("bodies[1].r", [0.0, 0.0, 0.015], r"^bodies\[1\]\.r: body 'b' overlaps body 'a'"),
    ("bodies[1].r", [0.002, 0.0, 0.0], r"^bodies\[1\]\.r: body 'b' overlaps body 'a'"),
    ("run.duration", "1 s", r"^run\.duration: must be a number"),
    ("run.method", "leapfrog", r"^run\.method: unknown integrator 'leapfrog'; available: "),
    ("run.step", 1.0, r"^run\.step: 1 s is longer than run\.duration"),
    ("run.steps", 10, r"^run\.steps: unknown key; allowed: method, step, tol, duration"),
    ("interactions.pairs", "some", r"^interactions\.pairs: must be 'all' or 'listed'"),
    ("interactions.pair", [{"bodies": ["a", "c"], "potential": "dipole"}],
     r"^interactions\.pair\[0\]\.bodies: unknown body 'c'; available: a, b"),
    ("colour", "red", r"^colour: unknown key"),
    ("planner", {"tol": -1}, r"^planner\.tol: must be > 0"),
    ("planner", {"tol": 1e-3, "models": ["dipole", "multipole"]},
     r"^planner\.models\[1\]: unknown potential 'multipole'"),
    ("assembly", {"name": "chain"}, r"^bodies, assembly: give one of them, not both"),
])
def test_invalid_fields_are_named_in_the_error(path, value, message):
    with pytest.raises(SceneError, match=message):
        scene_from_mapping(variant(path, value))


@pytest.mark.parametrize("path, message", [
    ("bodies[0].nu", r"^bodies\[0\]\.nu: missing axis"),
    ("run.duration", r"^run\.duration: missing"),
    ("run", r"^run: missing"),
    ("bodies", r"^bodies: missing \(or give an assembly\)"),
    ("interactions", r"^interactions\.potential: missing"),
])
def test_missing_fields_are_named_in_the_error(path, message):
    with pytest.raises(SceneError, match=message):
        scene_from_mapping(variant(path, None, delete=True))


def test_mass_must_be_given_somewhere():
    data = variant("defaults.mass", None, delete=True)
    with pytest.raises(SceneError, match=r"^bodies\[0\]\.mass: missing"):
        scene_from_mapping(data)


def test_assembly_scene_errors_name_the_assembly_fields():
    data = {k: v for k, v in BASE.items() if k not in ("bodies", "defaults")}
    data["assembly"] = {"name": "helix", "params": {}}
    with pytest.raises(SceneError, match=r"^assembly\.name: unknown assembly 'helix'; "
                                         r"available: ") as info:
        scene_from_mapping(data)
    # every built-in is listed (an installed third-party plugin may add more)
    assert all(n in str(info.value) for n in ("chain", "lattice", "random_cluster", "ring"))
    data["assembly"] = {"name": "chain", "params": {"n": 3, "spacing": 0.01, "mass": 1e-3,
                                                    "alpha": 1e7, "moment": 0.1,
                                                    "body_radius": 1e-3, "body_length": 0.02}}
    with pytest.raises(SceneError, match=r"^assembly\[1\]\.r: body 'b1' overlaps body 'b0'"):
        scene_from_mapping(data)  # head-to-tail 20 mm magnets 10 mm apart
    data["assembly"]["params"]["spacing"] = -0.01
    with pytest.raises(SceneError, match=r"^assembly\.params: .*'spacing' must be > 0"):
        scene_from_mapping(data)


def test_file_errors(tmp_path):
    with pytest.raises(SceneError, match="does not exist"):
        load_scene(tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("name = \n")
    with pytest.raises(SceneError, match="invalid TOML"):
        load_scene(bad)
    with pytest.raises(SceneError, match=r"^bodies\[0\]\.mass: must be > 0"):
        loads_scene('[[bodies]]\nmass = 0\nr = [0, 0, 0]\n[run]\nduration = 1.0\n')


@pytest.mark.parametrize("second, axis2, gap", [
    ((0, 0, 0.0201), (0, 0, 1), 1e-4),        # coaxial, faces 0.1 mm apart
    ((0, 0, 0.0199), (0, 0, 1), 0.0),         # coaxial, 0.1 mm overlap
    ((0.0026, 0, 0), (0, 0, 1), 1e-4),        # side by side, 0.1 mm apart
    ((0.0113, 0, 0), (1, 0, 0), 5e-5),        # T: end face of 2 vs side of 1
    ((0.0110, 0, 0), (1, 0, 0), 0.0),         # T, touching inside
    ((0.003, 0, 0.021), (0, 0, 1), math.hypot(5e-4, 1e-3)),  # rim to rim, diagonal
])
def test_cylinder_distance_against_hand_geometry(second, axis2, gap):
    a = shape_of((0, 0, 0), (0, 0, 1), 1.25e-3, 0.01)
    b = shape_of(second, axis2, 1.25e-3, 0.01)
    d = distance(a, b)
    assert d == pytest.approx(gap, abs=1e-9)


def test_cli_runs_a_scene_file(tmp_path):
    """``poissonkit run FILE.toml`` end to end, kept cheap: 20 steps, no plots, no progress bar.

    It reuses the pair kernels the energy test above compiled in this process; the only
    default-run test of the scene path through the CLI (tests/seed000 covers the seed scene).
    """
    import json

    from poissonkit.cli import main

    out = tmp_path / "out"
    code = main(["run", str(ROOT / "poissonkit" / "scene" / "shipped" / "two_magnets.toml"), "--duration",
                 "0.002", "--out", str(out), "--no-progress", "--no-plots"])
    assert code == 0
    assert (out / "trajectory.npz").is_file()
    assert not list(out.glob("*.png"))
    summary = json.loads((out / "summary.json").read_text())
    assert summary["scene"] == "two_magnets"
    assert summary["t_end_s"] == pytest.approx(0.002, rel=1e-12)
    # released from rest at 40 mm, the attracting (antiparallel, side by side) pair moves closer
    assert summary["min_distance_m"] < 0.04
    assert summary["max_distance_m"] == pytest.approx(0.04)
    assert summary["max_rel_casimir_drift"] < 1e-13
