"""Sweeps that say what happened: a failing outcome keeps the point's fate, MEGNO survives a run
cut short by a collision, and ``poissonkit sweep`` exits non-zero with the failures by kind.

Reproduced first on the code before the fix: the docs' example grid
``spin_ratio=2:30:5, tilt=0.01:0.3:4`` with ``megno`` reported "7 bounded, 3 collision,
10 failed" and exited 0, every failure ``InputError: step 0.0157…967 is longer than t_end − t0
= 0.0157…877`` (a chunk of MEGNO's shadow run one round-off short of a step). Truth: the same
points without ``megno`` (13 collisions, 0 failures), and for MEGNO's value the chunk whose span
is one step: one step of ``h = span`` is what the solver's fixed grid takes for any step in
``[span, span (1 + 1e-12)]``, so the clamped call equals the call with the step ``span``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from poissonkit_magnets.seed000_sweep import SeedScene

from poissonkit import cli
from poissonkit.plugin.contributions import OutcomeEntry
from poissonkit.sweeps.execute import run_batch
from poissonkit.sweeps.failures import (
    failure_kinds,
    failure_table,
    kinds_of,
    point_table,
)
from poissonkit.sweeps.outcomes import OUTCOMES, reduce_run, reduce_run_kept
from poissonkit.sweeps.targets import FATES

#: a point of the docs' grid that collided and whose MEGNO raised before the fix
COLLIDING = {"spin_ratio": 2.0, "tilt": 0.2033333333333333}


@pytest.fixture(scope="module")
def seed():
    scene = SeedScene()  # 20 periods, as `poissonkit sweep seed000`
    return scene, scene.prepare()


def test_megno_of_a_run_cut_by_a_collision_is_computed(seed):
    scene, prep = seed
    rec = scene.run(prep, COLLIDING)
    assert rec.fate == "collision"
    without = reduce_run(rec, ["fate", "min_distance"])  # the truth for the fate
    out = reduce_run(rec, ["fate", "min_distance", "megno"])  # raised InputError before
    assert out["fate"] == without["fate"] == FATES.index("collision")
    assert out["min_distance"] == without["min_distance"]
    assert math.isfinite(out["megno"]) and out["megno"] > 0


def test_megno_chunk_short_of_a_step_by_round_off_is_one_step_of_the_span(seed):
    from poissonkit.errors import InputError
    from poissonkit.numerics.solver import solve

    scene, prep = seed
    system, y0, _t, method, step = scene.run(prep, COLLIDING).megno_inputs
    t = next(k * step for k in range(1, 100) if (k * step + step) - k * step < step)
    span = (t + step) - t
    assert span < step  # what MEGNO's chunk met: refused as "longer than" before
    one = solve(system, y0, t + step, method=method, step=step, t0=t)
    exact = solve(system, y0, t + step, method=method, step=span, t0=t)
    assert one.steps == 1 and one.t[-1] == t + step
    assert np.array_equal(one.y, exact.y)  # one step of the span, as the grid takes anyway
    with pytest.raises(InputError, match="longer than"):  # a real excess is still refused
        solve(system, y0, t + step, method=method, step=1.5 * span, t0=t)


def test_megno_of_a_run_cut_at_its_first_sample_is_nan(seed):
    scene, prep = seed
    rec = scene.run(prep, COLLIDING)
    rec.megno_inputs = (*rec.megno_inputs[:2], 0.0, *rec.megno_inputs[3:])
    assert math.isnan(reduce_run(rec, ["megno"])["megno"])


def _boom(rec: object) -> float:
    raise RuntimeError("no value here")


BOOM = OutcomeEntry(name="boom", doc="always fails", dtype="f8", unit="1", fill=math.nan,
                    compute=_boom)


def test_a_failing_outcome_keeps_the_others(seed):
    scene, prep = seed
    rec = scene.run(prep, {"spin_ratio": 0.0, "tilt": 0.02})
    values, errors = reduce_run_kept(rec, [OUTCOMES["fate"], BOOM, OUTCOMES["min_distance"]])
    assert FATES[values["fate"]] == "collision"  # tests/sweep/test_sweep_outcomes.py's truth
    assert math.isnan(values["boom"]) and values["min_distance"] < 0.01
    assert errors == {"boom": "RuntimeError: no value here"}
    # through a worker's batch: the point is not failed, its message names the outcome
    (idx, found, msg), = run_batch(scene, [(3, {"spin_ratio": 0.0, "tilt": 0.02})],
                                   (OUTCOMES["fate"], BOOM))
    assert idx == 3 and found is not None and FATES[int(found["fate"])] == "collision"
    assert msg == "outcome boom: RuntimeError: no value here"
    assert kinds_of(False, msg) == ["outcome boom (RuntimeError)"]


def _dataset(failed, errors, fate):
    import xarray as xr

    shape = (2, 2)
    return xr.Dataset(
        {"fate": (("a", "b"), np.array(fate, dtype="i1").reshape(shape)),
         "min_distance": (("a", "b"), np.arange(4.0).reshape(shape), {"units": "m"}),
         "completed": (("a", "b"), np.ones(shape, dtype=bool)),
         "failed": (("a", "b"), np.array(failed).reshape(shape)),
         "error": (("a", "b"), np.array(errors, dtype=object).reshape(shape))},
        coords={"a": [1.0, 2.0], "b": [10.0, 20.0]})


def test_failures_are_grouped_by_kind_with_the_first_example():
    ds = _dataset([False, True, False, True],
                  ["", "InputError: bad point", "outcome megno: InputError: short",
                   "IntegrationError: singular"], [0, -1, 1, -1])
    kinds = {f.kind: f for f in failure_kinds(ds)}
    assert set(kinds) == {"run InputError", "run IntegrationError", "outcome megno (InputError)"}
    assert kinds["run InputError"].values == {"a": 1.0, "b": 20.0}
    assert kinds["outcome megno (InputError)"].values == {"a": 2.0, "b": 10.0}
    assert kinds["outcome megno (InputError)"].example == "outcome megno: InputError: short"
    table = failure_table(ds)
    assert table.splitlines()[0].split() == ["kind", "count", "first", "example"]
    assert "a=2, b=10: outcome megno: InputError: short" in table
    rows = point_table(ds, FATES).splitlines()
    assert rows[0].split() == ["a", "b", "fate", "min_distance", "[m]", "status"]
    assert len(rows) == 5 and rows[1].split() == ["1", "10", "bounded", "0", "ok"]
    assert "failed: outcome megno (InputError)" in rows[3]
    summary = point_table(ds, FATES, limit=3)
    assert summary.startswith("4 points (more than 3") and "collision" in summary


@pytest.mark.slow  # a one-worker cluster (about 20 s); tests/sweep/test_sweep_paths.py checks
# the exit code on a prepared dataset in the default suite
def test_cli_exits_non_zero_with_a_table_when_a_point_failed(tmp_path, capsys):
    # orbit_radius = -1 is refused by the run (InputError), the other point runs
    code = cli.main(["sweep", "seed000", "--param", "orbit_radius=-1,0.5", "--param",
                     "tilt=0.01", "--periods", "0.5", "--workers", "1", "--no-progress",
                     "--no-plot", "--out", str(tmp_path / "o")])
    captured = capsys.readouterr()
    assert code == 5, captured.err
    assert "1 of 2 runs failed" in captured.err
    assert "run InputError  1" in captured.err and "orbit_radius=-1" in captured.err
    assert "1 bounded" in captured.out and "1 failed" in captured.out
    assert "orbit_radius  tilt [rad]  fate" in captured.out  # the per-point table


@pytest.mark.slow  # the docs' 20-point grid with MEGNO on a local cluster
def test_docs_megno_grid_reports_13_collisions_and_exits_0(tmp_path, capsys):
    grid = ["--param", "spin_ratio=2:30:5", "--param", "tilt=0.01:0.3:4"]
    code = cli.main(["sweep", "seed000", *grid, "--outcomes", "fate,min_distance,megno",
                     "--workers", "2", "--no-progress", "--no-plot", "--out",
                     str(tmp_path / "m")])
    out = capsys.readouterr().out
    assert code == 0
    assert "7 bounded, 13 collision, 0 escape, 0 failed" in out
    code = cli.main(["sweep", "seed000", *grid, "--outcomes", "fate,min_distance", "--workers",
                     "2", "--no-progress", "--no-plot", "--out", str(tmp_path / "n")])
    assert code == 0 and "7 bounded, 13 collision, 0 escape, 0 failed" in capsys.readouterr().out


def test_bounded_points_outside_the_regime_are_counted(tmp_path, capsys, monkeypatch):
    from poissonkit import sweeps

    ds = _dataset([False] * 4, [""] * 4, [0, 0, 1, 0])
    ds["left_regime"] = (("a", "b"), np.array([[1, 0], [1, 1]], dtype="i1"))
    monkeypatch.setattr(sweeps, "sweep", lambda *a, **k: ds)
    code = cli.main(["sweep", "seed000", "--param", "tilt=0,1", "--no-plot", "--no-progress",
                     "--out", str(tmp_path / "o")])
    out = capsys.readouterr().out
    assert code == 0  # a flag, not a failure: the numbers were computed
    assert "3 bounded (2 outside the integrator's regime: left_regime = 1), 1 collision" in out
