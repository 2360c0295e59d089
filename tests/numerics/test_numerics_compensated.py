"""Compensated summation in the splitting loop (``Splitting(compensated=True)``).

On the seed-000 scenes round-off in the increments, amplified ~1e5x by the orbit, stops the
plain loops near a final-state error of 1e-10 whatever the step; with compensated increments
the error keeps falling. Checked against heyoka's Taylor integrator at tolerance 1e-16 (an
independent solver of the same ODE, written in heyoka's own expression system in
``benchmarks/bench_seed_orbit.py``). Also: off by default with the plain arithmetic bit for bit,
checkpoint/resume bit-identical, invariants at round-off, typed errors.
"""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

import numpy as np
import pytest

from poissonkit.errors import InputError
from poissonkit.numerics import solve
from poissonkit.numerics.checkpoint import Checkpoint, CheckpointError
from poissonkit.numerics.integrators.splitting import Splitting
from poissonkit.numerics.solver import make_integrator
from poissonkit.numerics.workprecision import final_state_error

BENCH = Path(__file__).resolve().parents[2] / "benchmarks"


def _bench(name: str):
    sys.path.insert(0, str(BENCH))
    try:
        return importlib.import_module(name)
    finally:
        sys.path.remove(str(BENCH))


def _seed():
    from poissonkit_magnets import seed000

    return seed000


def encounter(periods: int = 10):
    """The benchmark's close encounter (pericentre 0.43 l)."""
    return _seed().default_run(periods=periods, tilt=0.01, momentum_factor=0.8)


def seed_orbit(periods: int = 20):
    """The benchmark's seed orbit."""
    return _seed().default_run(periods=periods, tilt=0.05)


def heyoka_final(spec) -> np.ndarray:
    """Final state of heyoka at tol 1e-16 (agrees with its quadruple-precision run to ~1e-12
    on these scenes, docs/performance.md)."""
    hy = pytest.importorskip("heyoka")
    ode = _bench("bench_seed_orbit").heyoka_system(_seed().nondimensional_parameters())[0]
    ta = hy.taylor_adaptive(ode, np.array(spec.y0, dtype=float), tol=1e-16)
    ta.propagate_until(float(spec.t_end))
    return np.array(ta.state)


def final(spec, method: str, step: float, **opts) -> np.ndarray:
    sol = solve(spec.system, np.asarray(spec.y0, dtype=float), float(spec.t_end),
                method=make_integrator(method, opts), step=step, save_every=10**9)
    return sol.y[-1]


@pytest.mark.parametrize("scene, method", [("encounter", "splitting8"),
                                           ("encounter", "splitting6_bm"),
                                           ("seed_orbit", "splitting8")])
def test_compensated_splitting_passes_the_round_off_floor(scene, method):
    spec = encounter() if scene == "encounter" else seed_orbit()
    ref = heyoka_final(spec)
    steps = (0.005, 0.0025)  # truncation error ≤ 1e-13 here: what is left is round-off
    plain = [final_state_error(final(spec, method, h), ref) for h in steps]
    comp = [final_state_error(final(spec, method, h, compensated=True), ref) for h in steps]
    assert max(comp) <= 1e-11, (plain, comp)
    # the plain loop's round-off scatters between 3e-11 and 4e-10 at these steps (measured;
    # it depends on the exact rounding sequence, hence the largest of two steps)
    assert max(plain) >= 3 * max(comp), (plain, comp)


def _plain_loop(system, y0, t_end, integ: Splitting, n: int) -> np.ndarray:
    """The drift–kick table stepped from Python with the system's own plain kernels."""
    k, data, work = system.kernels, system.data, system.work()
    y = np.array(y0, dtype=float)
    h = t_end / n
    a, b = integ.a, integ.b
    for _ in range(n):
        for s in range(len(b)):
            k.drift(y, a[s] * h, data)
            k.kick(y, b[s] * h, data, work)
        k.drift(y, a[len(b)] * h, data)
    return y


@pytest.mark.parametrize("method", ["splitting8", "splitting4_bm"])
def test_default_is_off_and_bit_identical_to_the_plain_table(method):
    spec = encounter(periods=1)
    integ = make_integrator(method, {})
    assert integ.compensated is False and "compensated" not in integ.name
    y0, t_end, n = np.asarray(spec.y0, dtype=float), float(spec.t_end), 200
    # save_every=1: no first-same-as-last merge, so the step is exactly the table
    sol = solve(spec.system, y0, t_end, method=integ, step=t_end / n)
    assert sol.y[-1].tobytes() == _plain_loop(spec.system, y0, t_end, integ, n).tobytes()
    explicit = solve(spec.system, y0, t_end, method=make_integrator(method, {"compensated": False}),
                     step=t_end / n)
    assert np.array_equal(explicit.y, sol.y)


def test_compensated_resume_is_bit_identical(tmp_path):
    spec = encounter(periods=2)
    y0, t_end, h = np.asarray(spec.y0, dtype=float), float(spec.t_end), 0.01
    opts = {"compensated": True}
    calls = {"n": 0}

    def stop() -> bool:
        calls["n"] += 1
        return calls["n"] == 3

    ck = Checkpoint(tmp_path / "ck", 97)
    part = solve(spec.system, y0, t_end, "splitting6_bm", step=h, options=opts, checkpoint=ck,
                 stop=stop, save_every=5)
    assert part.extra["interrupted"]
    full = solve(spec.system, y0, t_end, "splitting6_bm", step=h, options=opts, checkpoint=ck,
                 resume=True, save_every=5)
    ref = solve(spec.system, y0, t_end, "splitting6_bm", step=h, options=opts, save_every=5)
    assert "resumed_from" in full.extra
    assert full.y[-1].tobytes() == ref.y[-1].tobytes()
    assert np.array_equal(full.t, ref.t) and np.array_equal(full.y, ref.y)
    # the compensation is part of the state: a plain run cannot take over the checkpoint,
    # nor a compensated run a plain one's
    with pytest.raises(CheckpointError, match="differs"):
        solve(spec.system, y0, t_end, "splitting6_bm", step=h, checkpoint=ck, resume=True,
              save_every=5)
    plain_ck = Checkpoint(tmp_path / "plain", 97)
    solve(spec.system, y0, t_end, "splitting6_bm", step=h, checkpoint=plain_ck, save_every=5)
    with pytest.raises(CheckpointError, match="differs"):
        solve(spec.system, y0, t_end, "splitting6_bm", step=h, options=opts,
              checkpoint=plain_ck, resume=True, save_every=5)


@pytest.mark.parametrize("opts", [{}, {"adaptive": True}], ids=["fixed", "adaptive"])
@pytest.mark.parametrize("method", ["splitting8", "splitting4_bm"])
def test_compensated_keeps_invariants_at_round_off(method, opts):
    spec = encounter()
    system, y0 = spec.system, np.asarray(spec.y0, dtype=float)
    sol = solve(system, y0, float(spec.t_end), method=make_integrator(
        method, {"compensated": True, **opts}), step=0.05, save_every=50)
    c0, j0 = system.casimirs(y0), system.angular_momentum(y0)
    dc = np.max(np.abs(system.casimirs(sol.y) - c0))
    dj = np.max(np.linalg.norm(system.angular_momentum(sol.y) - j0, axis=-1)) / np.linalg.norm(j0)
    assert dc < 1e-13 and dj < 1e-13, (dc, dj)
    # and it is the same trajectory as the plain loop, up to the plain loop's round-off
    plain = solve(system, y0, float(spec.t_end), method=make_integrator(method, opts),
                  step=0.05, save_every=50)
    if not opts:  # fixed step: the same save times
        assert np.array_equal(plain.t, sol.t)
    assert final_state_error(sol.y[-1], plain.y[-1]) < 1e-8


def test_compensated_rows_events_and_first_same_as_last_agree():
    from poissonkit.numerics import Collision

    spec = encounter(periods=2)
    system, y0, t_end = spec.system, np.asarray(spec.y0, dtype=float), float(spec.t_end)
    opts = {"compensated": True}
    quiet = solve(system, y0, t_end, "splitting4_bm", step=0.01, options=opts, save_every=10**9)
    rows = solve(system, y0, t_end, "splitting4_bm", step=0.01, options=opts, save_every=7)
    # an event that never fires: only the merged kicks differ (FSAL is off while watching)
    watched = solve(system, y0, t_end, "splitting4_bm", step=0.01, options=opts,
                    events=[Collision(1e-3)])
    assert not watched.events
    for other in (rows.y[-1], watched.y[-1]):
        assert final_state_error(quiet.y[-1], other) < 1e-12
    assert rows.t[0] == 0.0 and np.all(np.diff(rows.t) > 0) and len(rows.t) > 2


def test_compensated_needs_compensated_kernels(dipole_pair):
    from numerics_helpers import orbit_state  # type: ignore[import-not-found]

    class NoCompensatedKernels:
        """A splittable system whose kernels have no compensated drift/kick (as a plugin's
        system written before the option existed)."""

        def __init__(self, inner):
            self.inner = inner
            self.kernels = inner.kernels._replace(drift_compensated=None, kick_compensated=None)
            self.data = inner.data

        def work(self):
            return self.inner.work()

    system = NoCompensatedKernels(dipole_pair)
    y0 = orbit_state()
    plain = solve(system, y0, 1.0, "splitting4", step=0.01)  # the plain loop runs
    assert np.all(np.isfinite(plain.y))
    # refused with a typed error naming the option, not silently run uncompensated
    with pytest.raises(InputError, match="compensated"):
        solve(system, y0, 1.0, "splitting4", step=0.01, options={"compensated": True})
    with pytest.raises(InputError, match="compensated"):
        Splitting(order=4, compensated="yes")


def test_compensated_stream_interrupt_and_terminal_event(tmp_path):
    from poissonkit.numerics import Collision
    from poissonkit.numerics.checkpoint import read_trajectory

    spec = encounter(periods=2)
    system, y0, t_end = spec.system, np.asarray(spec.y0, dtype=float), float(spec.t_end)
    opts = {"compensated": True}
    ref = solve(system, y0, t_end, "splitting8", step=0.01, options=opts, save_every=3)
    # streamed rows and the streamed run's final state are the compensated states y − c
    streamed = solve(system, y0, t_end, "splitting8", step=0.01, options=opts, save_every=3,
                     stream=tmp_path / "parts")
    assert streamed.y[-1].tobytes() == ref.y[-1].tobytes()
    t, y = read_trajectory(tmp_path / "parts")
    assert np.array_equal(t, ref.t) and np.array_equal(y, ref.y)
    # an interrupted run ends on the state where it stopped, not on the uncompensated sum
    calls = {"n": 0}

    def stop() -> bool:
        calls["n"] += 1
        return calls["n"] == 2

    part = solve(system, y0, t_end, "splitting8", step=0.01, options=opts, stop=stop,
                 save_every=10**9)
    full = solve(system, y0, t_end, "splitting8", step=0.01, options=opts)
    assert part.extra["interrupted"]
    k = int(np.searchsorted(full.t, part.t[-1]))
    assert full.t[k] == part.t[-1] and part.y[-1].tobytes() == full.y[k].tobytes()
    # a terminal contact at the pericentre (0.43) is located as in the plain loop
    ev = [Collision(0.5)]
    hit_c = solve(system, y0, t_end, "splitting8", step=0.01, options=opts, events=ev)
    hit_p = solve(system, y0, t_end, "splitting8", step=0.01, events=ev)
    assert len(hit_c.events) == len(hit_p.events) == 1
    assert abs(hit_c.events[0].time - hit_p.events[0].time) < 1e-9
    assert final_state_error(hit_c.y[-1], hit_p.y[-1]) < 1e-9


@pytest.mark.slow  # 12-15 s on a cold kernel cache; the default run keeps a smaller sibling
def test_compensated_nbody_passes_the_round_off_floor():
    # the close encounter as a general N-body system (two tops, lab frame), against heyoka
    seed = _seed()
    spec = encounter()
    nb = seed.nbody_system()
    y0 = seed.nbody_state(np.asarray(spec.y0, dtype=float))
    ref = heyoka_final(spec)
    errs = []
    for comp in (False, True):
        sol = solve(nb, y0, float(spec.t_end), method=make_integrator(
            "splitting8", {"compensated": comp}), step=0.005, save_every=10**9)
        y = sol.y[-1]
        r, p = seed.relative_orbit(y)
        y18 = np.concatenate([r, p, y[12:24]])
        errs.append(final_state_error(y18, ref))
    assert errs[1] <= 1e-11, errs
    # invariants of the N-body form: total momenta at round-off
    sol = solve(nb, y0, float(spec.t_end), "splitting4_bm", step=0.05,
                options={"compensated": True}, save_every=50)
    j = nb.angular_momentum(sol.y)
    assert np.max(np.abs(nb.casimirs(sol.y) - nb.casimirs(y0))) < 1e-13
    assert np.max(np.linalg.norm(j - j[0], axis=-1)) <= 1e-13 * np.linalg.norm(j[0])


@pytest.mark.slow  # 12-15 s on a cold kernel cache; the default run keeps a smaller sibling
def test_compensated_nbody_cluster_parallel_loop_equals_serial():
    # a cell-listed cluster on the parallel pair loop: the compensated kick uses the same
    # (bit-for-bit reproducible) forces, so serial and parallel runs agree bit for bit
    import sympy as sp

    from poissonkit.numerics import AllPairs, Body, NBodySystem

    r, c1, c2, c3 = sp.symbols("r c1 c2 c3", real=True)
    dipole = (c3 - 3 * c1 * c2) / r**3
    rng = np.random.default_rng(3)
    g = np.arange(4, dtype=float)
    pos = np.array(np.meshgrid(g, g, g, indexing="ij")).reshape(3, -1).T
    pos = pos + rng.uniform(-0.2, 0.2, size=pos.shape)
    n = len(pos)
    p, nu, m = (s * rng.normal(size=(n, 3)) for s in (0.1, 1.0, 0.1))
    finals = []
    for parallel in (False, True):
        system = NBodySystem([Body(f"b{k}", 1.0, 1.0) for k in range(n)], [AllPairs(dipole)],
                             cutoff=2.0, parallel=parallel, parallel_min_bodies=0)
        y0 = system.pack(pos, p, nu, m, normalize=True)
        sol = solve(system, y0, 0.2, "splitting4_bm", step=0.01, options={"compensated": True})
        finals.append(sol.y[-1])
        c = system.casimirs(sol.y)
        assert np.max(np.abs(c - c[0])) < 1e-13
    assert finals[0].tobytes() == finals[1].tobytes()
