"""The example plugin's external field (``harmonic_trap``), discovered through its entry point,
drives a scene run by the CLI: the trapped mass oscillates as cos(ωt)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from poissonkit.cli import main as cli_main

SCENE = """
name = "trapped"

[[bodies]]
name = "atom"
mass = 1e-3
r = [0.002, 0.0, 0.0]

[[fields]]
source = "harmonic_trap"
omega = 20.0

[run]
method = "splitting6"
step = 1e-3
duration = 0.5
"""


def test_the_example_plugins_field_runs_in_a_scene(example_discoverable, tmp_path):
    path = tmp_path / "trap.toml"
    path.write_text(SCENE)
    out = tmp_path / "run"
    assert cli_main(["run", str(path), "--out", str(out), "--no-progress", "--no-plot"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["parameters"]["fields"] == [{"source": "harmonic_trap", "omega_per_s": 20.0,
                                               "centre_m": [0.0, 0.0, 0.0]}]
    assert summary["max_rel_energy_error"] < 1e-10
    traj = np.load(out / "trajectory.npz")
    t = traj["t"] * summary["parameters"]["time_unit_s"]
    x = traj["y"][:, 0] * summary["parameters"]["scales"]["length"]
    assert x == pytest.approx(0.002 * np.cos(20.0 * t), abs=1e-9)
    assert math.isclose(float(t[-1]), 0.5, rel_tol=1e-12)
