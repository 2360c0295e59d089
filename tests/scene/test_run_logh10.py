"""``poissonkit run --method logh10``: the order-10 time-transformed splitting is reachable by
its registry name from the command line and from a scene, with its options.

Truth used: the seed 000 scene with no tilt is the exact circular orbit of radius 10 mm
(test_seed000_cli.py), so the run must stay on that circle and go round twice in two periods.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from poissonkit import cli


def test_run_seed_with_logh10_and_its_options(tmp_path):
    out = tmp_path / "out"
    code = cli.main(["run", "seed000", "--method", "logh10", "--option", "track_kinetic=true",
                     "--periods", "2", "--no-plot", "--no-progress", "--out", str(out)])
    assert code == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["method"] == "logh10"
    assert s["t_end_s"] == pytest.approx(2 * s["T_orb"], rel=1e-12)
    # order 10 at the default step T_orb/200: (2 pi/200)^10 ~ 1e-15 per unit time
    assert s["min_distance_m"] == pytest.approx(0.01, rel=1e-9)
    assert s["max_distance_m"] == pytest.approx(0.01, rel=1e-9)
    assert s["max_rel_casimir_drift"] < 1e-12
    assert s["max_rel_angular_momentum_drift"] < 1e-12
    r = np.load(out / "trajectory.npz")["r_rel_si"]
    phase = np.unwrap(np.arctan2(r[:, 1], r[:, 0]))
    assert phase[-1] - phase[0] == pytest.approx(4 * math.pi, rel=1e-9)


def test_logh10_options_are_checked(tmp_path, capsys):
    code = cli.main(["run", "seed000", "--method", "logh10", "--option", "exponent=7",
                     "--periods", "0.1", "--no-plot", "--no-progress",
                     "--out", str(tmp_path / "o")])
    assert code == 1
    assert "exponent must be in (0, 3]" in capsys.readouterr().err


def _circular_scene(options: str) -> str:
    """A star and a planet (SI) on a circular relative orbit of radius 1.496e11 m, centre of
    mass at rest: the relative speed is sqrt(G (M + m) / r)."""
    G, M, m, r = 6.6743e-11, 1.98847e30, 5.9722e24, 1.496e11
    p = math.sqrt(G * (M + m) / r) * M * m / (M + m)
    return f"""
name = "circular"
description = "a star and a planet on a circular orbit"

[[bodies]]
name = "star"
mass = {M!r}
r = [0.0, 0.0, 0.0]
p = [0.0, {-p!r}, 0.0]

[[bodies]]
name = "planet"
mass = {m!r}
r = [{r!r}, 0.0, 0.0]
p = [0.0, {p!r}, 0.0]

[interactions]
potential = "gravity"
pairs = "all"

[run]
method = "logh10"
step = 8.64e5
duration = 3.15576e7
{options}"""


@pytest.mark.slow  # compiles the N-body loop of logh10 (about 30 s on a cold cache)
def test_a_scene_names_logh10_with_options(tmp_path):
    from poissonkit.scene import loads_scene

    options = "[run.options]\ntrack_kinetic = true\nshift = 0.0\n"
    scene = loads_scene(_circular_scene(options))
    assert scene.run.method == "logh10"
    assert dict(scene.run.options) == {"track_kinetic": True, "shift": 0.0}
    path = tmp_path / "circular.toml"
    path.write_text(_circular_scene(options))
    out = tmp_path / "out"
    assert cli.main(["run", str(path), "--no-plot", "--no-progress", "--out", str(out)]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["method"] == "logh10"
    # the exact orbit: a rotation of the relative position at the mean motion n
    G, M, m, r0 = 6.6743e-11, 1.98847e30, 5.9722e24, 1.496e11
    n = math.sqrt(G * (M + m) / r0 ** 3)
    data = np.load(out / "trajectory.npz")
    t, r = data["t_si"], data["r_rel_si"]
    assert t[-1] == pytest.approx(3.15576e7, rel=1e-12)
    exact = r0 * np.stack([np.cos(n * t), np.sin(n * t), np.zeros_like(t)], axis=1)
    assert np.abs(r - exact).max() < 1e-9 * r0
