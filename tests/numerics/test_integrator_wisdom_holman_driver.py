"""Wisdom–Holman on the shared driver: resume is bit-identical (after a stop, from any
checkpoint), streamed rows are the in-memory rows, events are located inside the step.

The event tests use two equal point masses: Wisdom–Holman's interaction Hamiltonian is then zero
(up to round-off), its map is exact Kepler motion, and Kepler's equation gives the true times.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from poissonkit.numerics import AllPairs, Body, NBodySystem, solve
from poissonkit.numerics.checkpoint import Checkpoint, checkpoints, read_trajectory
from poissonkit.numerics.events import ClosestApproach, Collision, Escape

METHODS = [("wisdom_holman", {"stages": 2}), ("wisdom_holman_corrected", {"stages": 3}),
           ("wisdom_holman", {"table": "10_6_4"}), ("wisdom_holman", {"correctors": 11}),
           ("wisdom_holman_corrected", {"stages": 1, "correctors": 5})]


def three_body(eps: float = 1e-2):
    """A star and two planets of mass ``eps`` on eccentric, inclined orbits (G = 1)."""
    m = np.array([1.0, eps, eps])
    x = np.array([[0.0, 0.0, 0.0], [0.95, 0.31, 0.0], [-1.2, 1.1, 0.15]])
    v = np.array([[0.0, 0.0, 0.0], [-0.33, 0.98, 0.0], [-0.55, -0.5, 0.05]])
    x -= (m[:, None] * x).sum(0) / m.sum()
    v -= (m[:, None] * v).sum(0) / m.sum()
    system = NBodySystem([Body(n, mk) for n, mk in zip(("star", "b", "c"), m)],
                         [AllPairs("gravity", {"G": 1.0})])
    return system, system.pack(x, m[:, None] * v)


def pair(x: np.ndarray, v: np.ndarray):
    """Two unit masses with relative position ``x`` and velocity ``v`` (G = 1, mu = 2)."""
    system = NBodySystem([Body("a", 1.0), Body("b", 1.0)], [AllPairs("gravity", {"G": 1.0})])
    return system, system.pack(np.array([-x / 2, x / 2]), np.array([-v / 2, v / 2]))


class StopAfter:
    """A stop request that becomes true at its ``n``-th look."""

    def __init__(self, n: int) -> None:
        self.n, self.looks = n, 0

    def __call__(self) -> bool:
        self.looks += 1
        return self.looks >= self.n


@pytest.mark.parametrize("method,opts", METHODS)
def test_stop_then_resume_is_bit_identical(tmp_path, method, opts):
    system, y0 = three_body()
    # save_every and checkpoint spacing are coprime: chunks end between saves, where the
    # merged drift / corrector of consecutive steps is carried over (not flushed)
    ref = solve(system, y0, 20.0, method, step=0.05, save_every=7, options=opts)
    ck = Checkpoint(tmp_path / "ck", 37)
    part = solve(system, y0, 20.0, method, step=0.05, save_every=7, options=opts,
                 checkpoint=ck, stop=StopAfter(3))
    assert part.extra["interrupted"] and part.t[-1] < 20.0
    assert part.steps == 3 * 37
    done = solve(system, y0, 20.0, method, step=0.05, save_every=7, options=opts,
                 checkpoint=ck, resume=True)
    assert "resumed_from" in done.extra
    assert done.y[-1].tobytes() == ref.y[-1].tobytes()  # bit-identical, not merely close
    assert np.array_equal(done.t, ref.t) and np.array_equal(done.y, ref.y)


@pytest.mark.parametrize("method,opts", METHODS)
def test_resume_from_an_early_checkpoint_is_bit_identical(tmp_path, method, opts):
    system, y0 = three_body()
    ck = Checkpoint(tmp_path / "ck", 50, keep=100)
    ref = solve(system, y0, 20.0, method, step=0.05, save_every=3, options=opts, checkpoint=ck)
    files = checkpoints(ck.folder)
    assert len(files) == 7  # steps 50 ... 350 of 400
    for f in files[1:]:  # as if the run had been killed after its first checkpoint
        f.unlink()
    done = solve(system, y0, 20.0, method, step=0.05, save_every=3, options=opts,
                 checkpoint=ck, resume=True)
    assert done.extra["resumed_from"].endswith(files[0].name)
    assert done.y[-1].tobytes() == ref.y[-1].tobytes()
    assert np.array_equal(done.t, ref.t) and np.array_equal(done.y, ref.y)


def test_checkpoint_of_another_wisdom_holman_run_is_refused(tmp_path):
    from poissonkit.numerics.checkpoint import CheckpointError

    system, y0 = three_body()
    ck = Checkpoint(tmp_path / "ck", 50)
    solve(system, y0, 5.0, "wisdom_holman", step=0.05, checkpoint=ck)
    with pytest.raises(CheckpointError, match="differs"):
        solve(system, y0, 5.0, "wisdom_holman_corrected", step=0.05, checkpoint=ck, resume=True)
    for other in ({"table": "10_6_4"}, {"correctors": 11}):  # same method name, other scheme
        with pytest.raises(CheckpointError, match="differs"):
            solve(system, y0, 5.0, "wisdom_holman", step=0.05, checkpoint=ck, resume=True,
                  options=other)


@pytest.mark.parametrize("method,opts", METHODS)
def test_streamed_rows_are_the_in_memory_rows(tmp_path, method, opts):
    from poissonkit.numerics.checkpoint import TrajectoryStream

    system, y0 = three_body()
    ref = solve(system, y0, 20.0, method, step=0.05, save_every=3, options=opts)
    # parts of 16 rows: the compiled chunks end many times between the 135 saved rows
    sol = solve(system, y0, 20.0, method, step=0.05, save_every=3, options=opts,
                stream=TrajectoryStream(tmp_path / "parts", max_rows=16))
    t, y = read_trajectory(tmp_path / "parts")
    assert len(t) == len(ref.t) == 135
    assert np.array_equal(t, ref.t) and np.array_equal(y, ref.y)
    assert sol.extra["stream"] and sol.extra["peak_rows_in_memory"] <= 2 * 16 + 1
    assert sol.y[-1].tobytes() == ref.y[-1].tobytes() and len(sol.t) == 2


def test_progress_chunks_do_not_change_the_trajectory():
    system, y0 = three_body()
    ref = solve(system, y0, 20.0, "wisdom_holman_corrected", step=0.05, save_every=7,
                options={"stages": 3})
    shown = solve(system, y0, 20.0, "wisdom_holman_corrected", step=0.05, save_every=7,
                  options={"stages": 3}, progress=True)
    assert np.array_equal(shown.y, ref.y)


@pytest.mark.parametrize("method,opts", [("wisdom_holman", {})] + METHODS[2:])
def test_collision_is_located_at_the_time_of_keplers_equation(method, opts):
    """e = 0.9 ellipse from apocentre: the separation reaches 0.2 at the eccentric anomaly
    E with 1 - e cos E = 0.2, at time (E - e sin E - pi)/n."""
    mu, a, e, h = 2.0, 1.0, 0.9, 0.01
    ra = a * (1 + e)
    system, y0 = pair(np.array([-ra, 0.0, 0.0]),
                      np.array([0.0, -math.sqrt(mu / a * (1 - e) / (1 + e)), 0.0]))
    sol = solve(system, y0, 10.0, method, step=h, events=(Collision(0.2),), options=opts)
    (ev,) = sol.events
    E = 2 * math.pi - math.acos((1 - 0.2 / a) / e)
    t_true = (E - e * math.sin(E) - math.pi) / math.sqrt(mu / a**3)
    assert ev.kind == "collision" and ev.time_error < 1e-9 * 10
    assert abs(ev.time - t_true) < 1e-9  # inside the step of 0.01, to the Kepler solver
    assert sol.t[-1] == ev.time and sol.message == "event"
    r = system.unpack(sol.y[-1])["r"]
    assert np.linalg.norm(r[1] - r[0]) == pytest.approx(0.2, abs=1e-8)


def test_escape_is_located_on_a_hyperbola():
    """e = 1.5 hyperbola from pericentre; each body is at r/2 from the centre of mass, so
    Escape(2) fires at r = 4, i.e. cosh F = (r/a + 1)/e, t = (e sinh F - F)/n."""
    mu, a, e = 2.0, 1.0, 1.5
    p = a * (e * e - 1)
    system, y0 = pair(np.array([a * (e - 1), 0.0, 0.0]),
                      np.array([0.0, math.sqrt(mu / p) * (1 + e), 0.0]))
    sol = solve(system, y0, 20.0, "wisdom_holman_corrected", step=0.05,
                options={"stages": 2}, events=(Escape(2.0),))
    (ev,) = sol.events
    F = math.acosh((4.0 / a + 1) / e)
    t_true = (e * math.sinh(F) - F) / math.sqrt(mu / a**3)
    assert ev.kind == "escape" and abs(ev.time - t_true) < 1e-8
    assert ev.value == pytest.approx(2.0, abs=1e-8)


def test_closest_approach_is_recorded_at_pericentre():
    mu, a, e, h = 2.0, 1.0, 0.9, 0.01
    ra = a * (1 + e)
    system, y0 = pair(np.array([-ra, 0.0, 0.0]),
                      np.array([0.0, -math.sqrt(mu / a * (1 - e) / (1 + e)), 0.0]))
    sol = solve(system, y0, 3.0, "wisdom_holman", step=h, events=(ClosestApproach(0.5),))
    (ev,) = sol.events  # one pericentre passage in 3 < period = 4.44
    assert ev.kind == "closest_approach"
    assert ev.value == pytest.approx(a * (1 - e), abs=1e-9)
    assert ev.time == pytest.approx(math.pi / math.sqrt(mu / a**3), abs=1e-6)
    assert sol.t[-1] == 3.0  # not terminal: the run goes on
