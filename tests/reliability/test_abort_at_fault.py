"""An aborted run names what went wrong where it is known: the body and field of a body leaving
a tabulated field's region (from the last good state, the state at the failure being NaN), the
typed state of the loop (``IntegrationError.abort``), a step limit reached mid-run.

Before, a body leaving a table stopped the run with "non-finite state produced at step 212
(t = 0.1499)" (no field, no body, internal time), and ``explain_nonfinite`` was not called:
at the failure the positions are NaN too (the kick that read the table outside its region is
followed by drifts), so it could not find the body."""

from __future__ import annotations

import json

import numpy as np
import pytest

import poissonkit as pk
from poissonkit import cli
from poissonkit.errors import AbortState, InterruptedRun, NonFiniteStateError, StepLimitReached
from poissonkit.numerics.fields.regions import FieldRegionError

EXIT_FAILED = 5
#: the table's region [m] (the known truth the reported position is compared with)
LO, HI = np.array([-0.01, -0.01, 0.02]), np.array([0.01, 0.01, 0.03])
STEP_S = 1e-4  # 0.01 internal time units of 0.01 s


def _dipole_b(p):
    """B [T] of a 1 A m² point dipole along z at the origin (closed form)."""
    p = np.asarray(p, float).reshape(-1, 3)
    m = np.array([0.0, 0.0, 1.0])
    r = np.linalg.norm(p, axis=1)[:, None]
    n = p / r
    return 1e-7 * (3 * n * (n @ m)[:, None] - m) / r ** 3


@pytest.fixture(scope="module")
def rising_top():
    """A top thrown up at 0.5 m/s through a dipole's table covering z <= 0.03 m."""
    from poissonkit.numerics.fields.tabulated import tabulated_field
    from poissonkit.numerics.nbody import Body, NBodySystem
    from poissonkit.numerics.units import Scales

    field = tabulated_field("dipole", _dipole_b, LO, HI, 1e-3, grow=False)
    s = NBodySystem([Body("top", 0.02, alpha=1 / 2e-6, attributes={"moment": 0.1})],
                    scales=Scales(length=0.01, mass=0.02, time=0.01), fields=[field])
    y0 = s.pack([[0.0, 0.0, 0.025]], [[0.0, 0.0, 0.02 * 0.5]], [[0.0, 0.0, -1.0]],
                [[0.0, 0.0, -2e-5]], si=True)
    return s, y0


def test_a_body_leaving_a_table_is_named_from_its_last_good_state(rising_top):
    s, y0 = rising_top
    with pytest.raises(FieldRegionError) as info:
        pk.solve(s, y0, 5.0, method="splitting4", step=STEP_S / 0.01)
    err = info.value
    assert isinstance(err, NonFiniteStateError)  # old handlers still catch it
    assert (err.field, err.body) == ("dipole", "top")
    # the last good state is one step before the failure, inside the table, and the body's
    # straight path over that step crosses its top face z = 0.03 m
    assert err.time_s - err.position_time_s == pytest.approx(STEP_S, rel=1e-9)
    z, vz = err.position[2], err.velocity[2]
    assert np.all(LO[:2] <= err.position[:2]) and np.all(np.array(err.position[:2]) <= HI[:2])
    assert 0.0 < vz < 1.0 and z <= HI[2] + 1e-12 < z + vz * STEP_S  # (repelled: > 0.5 m/s)
    msg = str(err)
    assert "body 'top' left the region of field 'dipole'" in msg
    assert f"t = {err.time_s:.6g} s" in msg and "m/s" in msg and "0.03] m" in msg
    # the typed abort state: the rows up to the last good state, all finite
    abort = err.abort
    assert isinstance(abort, AbortState) and abort.body == "top"
    t_rows, y_rows = abort.held_rows
    assert np.all(np.isfinite(y_rows))
    assert t_rows[-1] * 0.01 == pytest.approx(err.position_time_s, rel=1e-12)
    assert np.allclose(s.unpack(y_rows[-1], si=True)["r"][0], err.position, rtol=0, atol=0)
    assert abort.bad_components  # the state at the failure is not finite
    assert abort.steps_done == err.step


def test_a_second_ctrl_c_keeps_the_loop_state(rising_top):
    """The stop callable raising KeyboardInterrupt (what the second Ctrl-C does): the error is
    still a KeyboardInterrupt, and carries the rows the loop held."""
    s, y0 = rising_top
    calls = []

    def stop():
        calls.append(1)
        if len(calls) == 3:
            raise KeyboardInterrupt
        return False

    with pytest.raises(KeyboardInterrupt) as info:
        pk.solve(s, y0, 0.9, method="splitting4", step=1e-4, stop=stop)  # inside the table
    assert isinstance(info.value, InterruptedRun)
    abort = info.value.abort
    assert abort.steps_done > 0 and len(abort.held_rows[0]) == abort.steps_done + 1
    assert abort.time_reached == pytest.approx(abort.steps_done * 1e-4, rel=1e-9)
    assert abort.held_rows[0][-1] == abort.time_reached and np.all(np.isfinite(abort.held_rows[1]))


def test_a_step_limit_cuts_the_run_with_its_rows(rising_top):
    from poissonkit.numerics.integrators.driver import step_limit

    s, y0 = rising_top
    full = pk.solve(s, y0, 0.2, method="splitting4", step=0.01)
    with step_limit(7), pytest.raises(StepLimitReached) as info:
        pk.solve(s, y0, 0.2, method="splitting4", step=0.01, save_every=3)
    err = info.value
    assert err.limit == 7 and err.abort.steps_done == 7
    assert err.time == pytest.approx(0.07, rel=1e-12) and "max_steps = 7" in str(err)
    t_rows, y_rows = err.abort.held_rows
    # rows 0, 3, 6 and the state where it stopped (7): the uncut run's numbers, bit for bit
    assert np.allclose(t_rows, [0.0, 0.03, 0.06, 0.07], rtol=1e-12, atol=0)
    assert np.array_equal(y_rows, full.y.T[[0, 3, 6, 7]] if full.y.shape[0] == y0.size
                          else full.y[[0, 3, 6, 7]])
    with step_limit(20):  # a run that ends within its limit is untouched
        again = pk.solve(s, y0, 0.2, method="splitting4", step=0.01)
    assert np.array_equal(again.y, full.y)


#: A top pushed up out of a small table of a magpylib CylinderSegment (no exact kernel: it is
#: tabulated over the region given)
SEGMENT = """
name = "top_pushed_out_of_a_small_table"

[[bodies]]
name = "top"
mass = 0.02
inertia = 2.0e-6
moment = 0.1
r = [0.0, 0.0, 0.03]
p = [0.0, 0.0, 0.01]
nu = [0.0, 0.0, -1.0]
m = [0.0, 0.0, -2.0e-4]

[[fields]]
source = "magpylib"
class = "CylinderSegment"
params = { polarization = [0.0, 0.0, 1.0], dimension = [0.005, 0.025, 0.01, 0.0, 360.0] }
tol = 1e-3
grow = false  # the region stays: the body leaves it
region = [-0.004, -0.004, 0.026, 0.004, 0.004, 0.034]

[[fields]]
source = "gravity"
g = [0.0, 0.0, -9.81]

[run]
method = "splitting6"
step = 2e-4
duration = 0.05
"""


@pytest.mark.slow
def test_a_top_pushed_out_of_a_cylinder_segment_table_keeps_its_run(tmp_path, capsys):
    scene = tmp_path / "segment.toml"
    scene.write_text(SEGMENT)
    out = tmp_path / "out"
    assert cli.main(["run", str(scene), "--out", str(out), "--no-progress", "--no-plot"]) \
        == EXIT_FAILED
    err = capsys.readouterr().err
    summary = json.loads((out / "summary.json").read_text())
    failure = summary["failure"]
    assert summary["status"] == "failed" and failure["kind"] == "FieldRegionError"
    assert (failure["body"], failure["field"]) == ("top", "magpylib")
    assert "left the region of field 'magpylib' at t = " in failure["reason"]
    assert failure["reason"] in err
    # it fails on the first step whose end is past the top face z = 0.034 m, and says so in s
    length = summary["units"]["internal_unit_in_si"]["length"]
    with np.load(out / "trajectory.npz") as z:
        t, zs = z["t_si"], z["y"][:, 2] * length
        assert np.all(np.isfinite(z["y"]))
    assert len(t) == summary["saved_rows"] and t[-1] == pytest.approx(
        failure["last_saved_time_s"], rel=1e-12)
    assert failure["time_s"] == pytest.approx(t[-1] + 2e-4, rel=1e-9)
    assert np.all(zs <= 0.034) and zs[-1] > 0.034 - 0.6 * 2e-4  # rising at < 0.6 m/s
    assert zs[-1] > zs[0]  # pushed up
    assert f"{zs[-1]:.6g}" in failure["quantity"] and "0.034] m" in failure["reason"]


@pytest.mark.slow
def test_an_adaptive_run_past_max_steps_is_cut_with_its_outputs(tmp_path, capsys):
    """logh4's physical steps shrink as the two magnets close in: the 500 steps that the plan
    counts (duration / step) pass the limit up front, the run needs more and is cut at 500."""
    cut, full = tmp_path / "cut", tmp_path / "full"
    args = ["run", "two_magnets", "--method", "logh4", "--no-progress", "--no-plot"]
    assert cli.main([*args, "--out", str(cut), "--max-steps", "500"]) == EXIT_FAILED
    assert "stopped at the step limit max_steps = 500 (t = 0.04" in capsys.readouterr().err
    summary = json.loads((cut / "summary.json").read_text())
    failure = summary["failure"]
    assert summary["status"] == "failed" and failure["kind"] == "StepLimitReached"
    assert failure["step"] == 500 and " s of t = 0.05 s)" in failure["reason"]
    assert cli.main([*args, "--out", str(full)]) in (0, 4)  # uncut: to the end or a contact
    with np.load(cut / "trajectory.npz") as a, np.load(full / "trajectory.npz") as b:
        n = len(a["t"])
        assert n == summary["saved_rows"] == 501 and len(b["t"]) > n
        # the cut run is the uncut one up to its last state, bit for bit
        assert np.array_equal(a["y"], b["y"][:n]) and np.array_equal(a["t"], b["t"][:n])
        assert a["t_si"][-1] == pytest.approx(failure["time_s"], rel=1e-12)
        assert failure["time_s"] < 0.05 == pytest.approx(b["t_si"][-1], rel=1e-12)


def test_a_failure_of_a_scene_in_days_also_says_the_time_in_days():
    from poissonkit.errors import IntegrationError
    from poissonkit.numerics.runspec import RunSpec
    from poissonkit.report.run_abort import failure_record

    days = {"length": "AU", "time": "day", "mass": "Msun"}
    spec = RunSpec("orbit", None, np.zeros(6), 10.0, metadata={"units": days,
                                                                "scales": {"time": 86400.0}})
    exc = IntegrationError("the method failed at t = 2.5")
    exc.abort = AbortState((np.zeros(0), np.zeros((0, 6))), 2.5, 40)
    record = failure_record(spec, exc, 86400.0, 2.0)
    assert record["time_s"] == 2.5 * 86400.0 and record["step"] == 40
    assert (record["time_scene"], record["time_scene_unit"]) == (2.5, "day")
    assert record["reason"] == "the method failed at t = 216000 s (that is 2.5 day)"
