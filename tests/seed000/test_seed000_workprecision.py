"""Work-precision machinery: error measure, time-to-error interpolation, CSV, the bench command.

The interpolation is checked on synthetic points that lie exactly on a power law (the known
answer follows from the law, not from the code); the reference is checked on a problem with a
closed-form solution (the seed's circular orbit, uniform rotation).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from poissonkit.errors import InputError
from poissonkit.numerics import workprecision as wp


def _points(method, c, slope, walls):
    # error = c * wall^-slope, exactly
    return [wp.WorkPoint(method, "step", 0.0, 1, w, c * w ** (-slope), 0.0) for w in walls]


def test_time_to_error_interpolates_on_a_power_law():
    pts = _points("a", 1e-4, 4.0, [0.1, 1.0, 10.0]) + _points("b", 1.0, 2.0, [1.0, 10.0])
    got = wp.time_to_error(pts, 1e-6)
    # a: 1e-4 w^-4 = 1e-6  <=>  w = 100^(1/4), between the points at 1 and 10 s
    assert got["a"] == pytest.approx((1e-4 / 1e-6) ** 0.25, rel=1e-12)
    assert got["b"] is None  # never reaches 1e-6 (1e-2 at its slowest point)
    assert wp.time_to_error(pts, 1.0)["b"] == pytest.approx(1.0)


def test_final_state_error_is_block_relative():
    y_ref = np.array([1.0, 0, 0, 0, 1e-3, 0])  # second block is small
    y = y_ref + np.array([0, 0, 0, 0, 1e-6, 0])
    assert wp.final_state_error(y, y_ref) == pytest.approx(1e-3)  # not diluted by block 1
    assert math.isinf(wp.final_state_error(np.full(6, np.nan), y_ref))
    with pytest.raises(InputError):
        wp.final_state_error(np.zeros(5), np.zeros(6))


def test_csv_round_trip_and_table(tmp_path):
    pts = _points("a", 1e-4, 4.0, [0.1, 1.0, 10.0])
    path = wp.write_csv(tmp_path / "wp.csv", pts)
    back = wp.read_csv(path)
    assert [p.wall_time for p in back] == [p.wall_time for p in pts]
    assert [p.final_error for p in back] == pytest.approx([p.final_error for p in pts])
    tab = wp.table(pts, (1e-6, 1e-9))
    assert "| a |" in tab and "—" in tab  # 1e-9 not reached
    png = wp.plot(tmp_path / "wp.png", pts)
    assert png.stat().st_size > 1000


def test_reference_agrees_with_closed_form_circular_orbit():
    from poissonkit_magnets import seed000

    spec = seed000.default_run(periods=2)
    ref = wp.reference(spec.system, spec.y0, spec.t_end)
    t = spec.t_end
    exact = np.array(spec.y0, dtype=float)
    c, s = math.cos(t), math.sin(t)
    exact[0:3] = [c, s, 0.0]
    exact[3:6] = [-s, c, 0.0]
    assert wp.final_state_error(ref.y_end, exact) < 1e-11
    assert ref.agreement < 1e-9  # DOP853 at tol 1e-13 confirms it


@pytest.mark.slow
def test_bench_command_quick(tmp_path):
    from poissonkit import cli

    out = tmp_path / "bench"
    code = cli.main(["bench", "--quick", "--periods", "2", "--out", str(out),
                     "--methods", "splitting4,splitting8,dop853"])
    assert code == 0
    pts = wp.read_csv(out / "workprecision.csv")
    assert {p.method for p in pts} == {"splitting4", "splitting8", "dop853"}
    # each method converges: the finest setting beats the coarsest by orders of magnitude
    for m in ("splitting4", "splitting8", "dop853"):
        errs = [p.final_error for p in pts if p.method == m]
        assert errs[-1] < 1e-3 * errs[0]
    assert (out / "workprecision.png").is_file()
    assert "time to 1e-06" in (out / "workprecision.md").read_text()
