"""A run that stops on an error keeps what it did: summary, trajectory up to the last good
state and figures, messages in seconds (``poissonkit.report.run_abort``).

Before, a body leaving a tabulated field's region left an empty ``trajectory.parts/`` and the
message "non-finite state produced at step 331 (t = 2.34052)" in internal time units."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from poissonkit import cli
from poissonkit.report.run_abort import in_seconds

#: A small magnet falling from z = 0 under gravity through the tabulated field of a weak coil
#: tabulated for z >= -0.534 m: it leaves the table at t = sqrt(2 * 0.534 / 9.81) = 0.32995 s
FALLING = """
name = "falling_out_of_table"
[[bodies]]
name = "top"
mass = 0.02
inertia = 2.0e-6
moment = 1.0e-3
r = [0.0, 0.0, 0.0]
nu = [0.0, 0.0, 1.0]

[[fields]]
source = "magpylib"
class = "Circle"
params = { current = 1.0, diameter = 0.1 }
position = [0.0, 0.0, 1.0]
mode = "table"
tol = 1e-3
grow = false  # the region stays: the body leaves it
region = [-0.01, -0.01, -0.534, 0.01, 0.01, 0.01]

[[fields]]
source = "gravity"
g = [0.0, 0.0, -9.81]

[run]
method = "splitting4"
step = 1e-3
duration = 1.0
"""
EXIT_FAILED = 5
LEAVES = math.sqrt(2 * 0.534 / 9.81)


@pytest.mark.slow
def test_a_run_failing_at_033_s_keeps_summary_trajectory_and_figures(tmp_path, capsys):
    scene = tmp_path / "falling.toml"
    scene.write_text(FALLING)
    out = tmp_path / "out"
    assert cli.main(["run", str(scene), "--out", str(out), "--no-progress"]) == EXIT_FAILED
    err = capsys.readouterr().err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "failed"
    failure = summary["failure"]
    # the body and the field it left, named from the last good state (the state at the failure
    # is NaN); at t = 0.33 s it is 0.154 mm below the region, within the table's margin
    assert failure["kind"] == "FieldRegionError" and failure["body"] == "top"
    assert failure["field"] == "magpylib" and "-0.534154" in failure["reason"]
    # it fails on the first step past the table's edge, and says so in seconds
    assert LEAVES <= failure["time_s"] <= LEAVES + 2e-3
    assert "t = 0.331 s" in failure["reason"] and "2.34" not in failure["reason"]
    assert "t = 0.331 s" in err
    with np.load(out / "trajectory.npz") as z:
        t = z["t_si"]
        assert len(t) == summary["saved_rows"] == 331
        assert abs(t[-1] - LEAVES) <= 1e-3 and np.all(np.isfinite(z["y"]))
        # the free fall, independently: z = -g t^2 / 2 (the coil's force is ~1e-7 of gravity)
        z_top = z["y"][:, 2]
    assert np.allclose(z_top, -9.81 * t**2 / 2, rtol=1e-5, atol=1e-12)
    assert (out / "trajectory.nc").is_file() and list(out.glob("*.png"))
    assert not (out / "trajectory.parts").exists()


@pytest.mark.parametrize(("message", "unit", "expected"), [
    ("non-finite state at step 3 (t = 2.34052)", 0.1414, "(t = 0.33095 s)"),
    ("interrupted at step 9 (t = 1.5)", 2.0, "(t = 3 s)"),
    ("stalled (Δt = 1e-20)", 1.0, "(Δt = 1e-20 s)"),
    ("already t = 5 s", 2.0, "already t = 5 s"),
    # seconds already: not read as "t = 0.33" followed by "1 s" (was "t = 0.0466602 s1 s")
    ("left at t = 0.331 s: at t = 0.33 s", 0.1414, "left at t = 0.331 s: at t = 0.33 s"),
    ("Δt = 2.5e-05 s", 3.0, "Δt = 2.5e-05 s"),
])
def test_internal_times_are_given_in_seconds(message, unit, expected):
    assert expected in in_seconds(message, unit)
