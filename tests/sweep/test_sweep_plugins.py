"""Sweeps are open to plugins: any object following the ``SweepScene`` protocol is swept, and
outcomes registered by a plugin's ``poissonkit_outcomes`` hook are named like built-in ones
(and computed on workers that do not have the plugin)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from poissonkit.contracts import SweepScene
from poissonkit.errors import InputError, SceneError, UnknownNameError
from poissonkit.sweeps import sweep
from poissonkit.sweeps.outcomes import DEFAULT_OUTCOMES, OUTCOMES, resolve_outcomes
from poissonkit.sweeps.targets import TomlScene, sweep_scene
from poissonkit_magnets.seed000_sweep import SeedScene
from sweep_outcome_plugin import EchoScene

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture
def outcome_plugin(monkeypatch):
    from poissonkit.plugin import manager, reset

    monkeypatch.setattr(manager, "BUILTIN_PLUGINS",
                        (*manager.BUILTIN_PLUGINS, ("test-outcomes", "sweep_outcome_plugin")))
    reset()
    yield
    reset()


def test_sweep_scenes_follow_the_protocol():
    toml = TomlScene.from_file(ROOT / "poissonkit" / "scene" / "shipped" / "two_magnets.toml")
    for scene in (toml, SeedScene(), EchoScene()):
        assert isinstance(scene, SweepScene)
        assert sweep_scene(scene) is scene
    with pytest.raises(InputError, match="sweep scene"):
        sweep_scene(object())


def test_builtin_outcomes_are_registered_through_the_hook():
    from poissonkit.plugin import plugin_reports

    report = next(r for r in plugin_reports() if r.name == "core-outcomes")
    assert report.status == "ok" and "fate" in report.contributions["outcome"]
    assert set(DEFAULT_OUTCOMES) < set(OUTCOMES)


def test_plugin_outcome_is_named_like_a_builtin(outcome_plugin):
    assert "test_twice_min" in OUTCOMES and "test_twice_min" not in DEFAULT_OUTCOMES
    assert resolve_outcomes("test_twice_min") == ("fate", "test_twice_min")


def test_unknown_outcome_lists_the_plugin_ones(outcome_plugin):
    with pytest.raises(UnknownNameError, match="test_twice_min"):
        resolve_outcomes(["twice"])


def test_plugin_scene_and_outcome_on_workers_without_the_plugin(outcome_plugin, dask_client):
    ds = sweep(EchoScene(), {"x": [0.5, 1.0, 3.0]}, outcomes=["test_twice_min"],
               client=dask_client, progress=False)
    assert not ds["failed"].any()
    np.testing.assert_array_equal(ds["test_twice_min"].values, [1.0, 2.0, 6.0])
    assert ds["test_twice_min"].attrs["units"] == "m"


def test_a_declared_body_attribute_is_a_sweep_parameter(monkeypatch):
    """``bodies.<name>.charge`` of a plugin potential: checked, given the potential's unit,
    set in the scene and integrated (energy kept by the symplectic splitting)."""
    from poissonkit.plugin import manager, reset
    from poissonkit.sweeps.outcomes import reduce_run

    monkeypatch.syspath_prepend(str(ROOT / "tests" / "scene"))
    monkeypatch.setattr(manager, "BUILTIN_PLUGINS",
                        (*manager.BUILTIN_PLUGINS, ("test-yukawa", "scene_yukawa_plugin")))
    reset()
    text = """
name = "charged pair"
[interactions]
potential = "test_yukawa"
[[bodies]]
name = "a"
mass = 1e-3
r = [0.0, 0.0, 0.0]
charge = 2e-8
[[bodies]]
name = "b"
mass = 1e-3
r = [0.03, 0.0, 0.0]
p = [0.0, 1e-4, 0.0]
[run]
duration = 0.02
step = 0.0005
"""
    scene = TomlScene(text)
    assert scene.check("bodies.b.charge") == "bodies.b.charge"
    assert scene.units("bodies.b.charge") == "C"
    assert scene.scene_with({"bodies.b.charge": -1e-8}).bodies[1]["charge"] == -1e-8
    with pytest.raises(SceneError, match="body 'b' has no 'charge', which test_yukawa reads"):
        scene.prepare()  # body b has no charge until the sweep sets one
    scene = TomlScene(text, fixed={"bodies.b.charge": 1e-8})
    prep = scene.prepare()
    out = reduce_run(scene.run(prep, {"bodies.b.charge": 2e-8}), ["fate", "max_rel_energy_error"])
    assert out["fate"] == 0 and out["max_rel_energy_error"] < 1e-6
    reset()
