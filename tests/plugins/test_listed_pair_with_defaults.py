"""A listed pair of a plugin potential that reads a body attribute, next to pairs of another
potential, in a scene whose ``[defaults]`` give every body that attribute (issue: "body 'c'
has no 'moment'"). Truth: the textbook point-dipole energy and the plugin's closed form."""

from __future__ import annotations

import math

import numpy as np
import pytest

from poissonkit.scene import loads_scene
from poissonkit.scene.build import build_run

MOMENT = 0.01  # A m^2
POSITIONS = {"a": (0.0, 0.0, 0.0), "b": (0.02, 0.0, 0.0), "c": (0.0, 0.03, 0.0)}


@pytest.fixture
def moment_plugin(monkeypatch):
    from poissonkit.plugin import manager, reset

    monkeypatch.setattr(manager, "BUILTIN_PLUGINS",
                        (*manager.BUILTIN_PLUGINS, ("test-moment", "moment_pair_plugin")))
    reset()
    yield
    reset()


def _scene(rest: str) -> str:
    bodies = "".join(f'[[bodies]]\nname = "{n}"\nr = {list(r)}\nnu = [0.0, 0.0, 1.0]\n'
                     for n, r in POSITIONS.items())
    return f"""
name = "listed pair"
[defaults]
mass = 1e-3
inertia = 1e-9
moment = {MOMENT}
radius = 1e-3
length = 2e-3
{bodies}
[interactions]
pairs = "all"
{rest}
[[interactions.pair]]
bodies = ["a", "b"]
potential = "test_moment_central"
[run]
step = 1e-3
duration = 0.01
"""


def _truth() -> float:
    """Point dipoles along z: U = mu0/(4 pi) m^2 (1 - 3 cos^2)/r^3 with cos = 0 here (a-c, b-c);
    the listed pair: k m^2 / r^3."""
    k, pos = 1e-7, {n: np.array(r) for n, r in POSITIONS.items()}
    r_ab = np.linalg.norm(pos["b"] - pos["a"])
    dipoles = sum(k * MOMENT ** 2 / np.linalg.norm(pos["c"] - pos[n]) ** 3 for n in ("a", "b"))
    return k * MOMENT ** 2 / r_ab ** 3 + dipoles


@pytest.mark.parametrize("rest", ['[planner]\ntol = 1e-2\nmodels = ["dipole"]',
                                  'potential = "dipole"'], ids=["planner", "default-potential"])
def test_a_listed_plugin_pair_reads_the_defaults_of_every_body(moment_plugin, rest):
    run = build_run(loads_scene(_scene(rest)))
    energy = run.system.energy(run.y0) * run.system.scales.energy
    assert math.isclose(energy, _truth(), rel_tol=1e-10)
