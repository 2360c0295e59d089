"""The lean per-step path: direct-sum loop kernels (same numbers as the general kernels), the
declared traits ``solve`` asks (same answers as ``isinstance``) and the remembered state checks
(bad input still rejected with the typed error)."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from poissonkit.contracts import (
    HasBodies,
    HasCompiledKernels,
    HasGravity,
    HasOverlapCheck,
    HasStateCheck,
    Integrator,
    NumericsSystem,
)
from poissonkit.errors import DimensionError, InputError
from poissonkit.numerics import AllPairs, Body, NBodySystem, solve
from poissonkit.numerics.events import Collision
from poissonkit.numerics.integrators.base import HasLoopKernels
from poissonkit.numerics.nbody import NonUnitAxisError, OverlapError
from poissonkit.traits import SystemTraits, offers

R = sp.Symbol("r", real=True)


def five_bodies(extra=()):
    """Sun and four planets on near-circular orbits (G = 1), in the barycentre frame."""
    m = np.array([1.0, 1e-3, 3e-4, 4e-5, 5e-5])
    a = np.array([0.0, 5.2, 9.5, 19.2, 30.1])
    th = np.array([0.0, 0.3, 2.0, 4.1, 5.5])
    x = np.stack([a * np.cos(th), a * np.sin(th), 0.01 * a], axis=1)
    v = np.zeros_like(x)
    v[1:] = np.stack([-np.sin(th[1:]), np.cos(th[1:]), np.zeros(4)], axis=1) \
        / np.sqrt(a[1:])[:, None]
    x -= (m[:, None] * x).sum(0) / m.sum()
    v -= (m[:, None] * v).sum(0) / m.sum()
    system = NBodySystem([Body(f"b{k}", float(mk)) for k, mk in enumerate(m)],
                         [AllPairs("gravity", {"G": 1.0}), *extra])
    return system, system.pack(x, m[:, None] * v)


def general(system):
    """The same system without its loop kernels: the integrators take the general ones."""
    system.loop_kernels = lambda: None
    return system


def test_direct_kernels_agree_bit_for_bit_with_the_general_ones():
    # two all-pairs sets (gravity over all, a repulsion among three): the sums in set order
    system, y0 = five_bodies((AllPairs(1e-4 / R**6, members=[0, 1, 2]),))
    lean = system.loop_kernels()
    assert lean is not None
    k, data, work = lean
    g, gdata = system.kernels, system.data
    rng = np.random.default_rng(3)
    y = y0 * (1 + 0.01 * rng.standard_normal(y0.size))
    assert k.energy(y, data, work) == g.energy(y, gdata, system.work())
    out, gout = np.empty_like(y), np.empty_like(y)
    k.rhs(y, data, work, out)
    g.rhs(y, gdata, system.work(), gout)
    assert np.array_equal(out, gout)
    assert k.min_distance(y, data, work) == g.min_distance(y, gdata, system.work())
    assert k.max_radius(y, data) == g.max_radius(y, gdata)
    for name, args in (("drift", (0.37, data)), ("kick", (0.37, data, work))):
        a, b = y.copy(), y.copy()
        getattr(k, name)(a, *args)
        getattr(g, name)(b, 0.37, gdata, *((system.work(),) if name == "kick" else ()))
        assert np.array_equal(a, b), name
    for name in ("drift_compensated", "kick_compensated"):
        a, b = y.copy(), y.copy()
        ca, cb = np.full_like(y, 1e-17), np.full_like(y, 1e-17)
        if name == "drift_compensated":
            k.drift_compensated(a, ca, 0.37, data)
            g.drift_compensated(b, cb, 0.37, gdata)
        else:
            k.kick_compensated(a, ca, 0.37, data, work)
            g.kick_compensated(b, cb, 0.37, gdata, system.work())
        assert np.array_equal(a, b) and np.array_equal(ca, cb), name


@pytest.mark.parametrize("method, options, events", [
    ("splitting2", None, ()),
    ("splitting4_bm", None, ()),  # kick-first: consecutive steps share a kick
    # each option compiles its own loop (~11 s cold): the default run keeps the plain ones
    pytest.param("splitting4", {"adaptive": True}, (), marks=pytest.mark.slow),
    pytest.param("splitting2", {"compensated": True}, (), marks=pytest.mark.slow),
    # located inside a step (Jupiter and Saturn approach): the lean min_distance and step
    ("splitting2", None, (Collision(5.19),)),
])
def test_lean_and_general_paths_give_the_same_trajectory(method, options, events):
    lean, y0 = five_bodies()
    assert lean.loop_kernels() is not None
    ref = general(five_bodies()[0])
    a = solve(lean, y0, 40.0, method=method, step=0.05, options=options, save_every=7,
              events=events)
    b = solve(ref, y0, 40.0, method=method, step=0.05, options=options, save_every=7,
              events=events)
    assert np.array_equal(a.t, b.t) and np.array_equal(a.y, b.y)
    assert a.steps == b.steps and a.events == b.events
    assert len(a.events) == len(events)
    # and the orbit is the right one: energy kept to the splitting's error
    assert np.max(np.abs(a.energy_error())) < 1e-4


def test_loop_kernels_only_where_the_direct_sum_is_exact():
    grav = AllPairs("gravity", {"G": 1.0})
    two = [Body("a", 1.0), Body("b", 2.0)]
    assert NBodySystem(two, [grav]).loop_kernels() is not None
    assert NBodySystem(two, [grav], cutoff=10.0).loop_kernels() is None
    assert NBodySystem(two, [grav], fast_path=False).loop_kernels() is None
    fixed = [Body("a", 1.0), Body("b", 2.0, fixed=True, position=(1.0, 0.0, 0.0))]
    assert NBodySystem(fixed, [grav]).loop_kernels() is None
    top = [Body("a", 1.0, alpha=1.0), Body("b", 2.0, alpha=1.0)]
    assert NBodySystem(top, [AllPairs(1 / R)]).loop_kernels() is None


def test_offers_reads_the_declaration_and_answers_as_isinstance():
    # the declared traits of an N-body system say what isinstance says (every contract the
    # solver asks about); non-systems are answered by isinstance itself
    system, _ = five_bodies()
    protos = (NumericsSystem, HasOverlapCheck, HasCompiledKernels, HasStateCheck, HasBodies,
              HasGravity, HasLoopKernels, Integrator)
    for obj in (system, object(), 3.0, "splitting2"):
        for proto in protos:
            assert offers(obj, proto) is isinstance(obj, proto), (obj, proto)

    class Blocked(NBodySystem):
        """A subclass that removes a method must declare so: its traits are data."""

        check_overlap = None
        traits = SystemTraits(*(c for c in NBodySystem.traits.contracts
                                if c is not HasOverlapCheck))

    assert not offers(Blocked([Body("a", 1.0)]), HasOverlapCheck)


def test_remembered_checks_still_reject_bad_states():
    system, y0 = five_bodies()
    solve(system, y0, 0.5, method="splitting2", step=0.05)
    bad = y0.copy()
    bad[6:9] = bad[0:3]  # bodies 0 and 1 at one place
    for _ in range(2):  # a failure is not remembered: the second call raises too
        with pytest.raises(OverlapError):
            solve(system, bad, 0.5, method="splitting2", step=0.05)
    solve(system, y0, 0.5, method="splitting2", step=0.05)  # the good state again
    with pytest.raises(OverlapError):
        system.check_state(bad)
    with pytest.raises(InputError, match="NaN"):
        solve(system, np.where(np.arange(y0.size) == 4, np.nan, y0), 0.5, "splitting2",
              step=0.05)
    with pytest.raises(DimensionError):
        solve(system, y0[:-1], 0.5, "splitting2", step=0.05)


def test_remembered_axis_check_depends_on_the_tolerance():
    system = NBodySystem([Body("a", 1.0, alpha=1.0), Body("b", 1.0, alpha=1.0)],
                         [AllPairs(1 / R)])
    y = system.pack([[0, 0, 0], [1, 0, 0]], np.zeros((2, 3)), [[0, 0, 1], [0, 0, 1]],
                    np.zeros((2, 3)))
    y[14] += 1e-8  # a.nu_z: |ν|² off by 2e-8
    system.check_state(y, tol=1e-6)
    with pytest.raises(NonUnitAxisError):
        system.check_state(y)  # the default tolerance 1e-10: same state, stricter test
    system.check_overlap(y)
    with pytest.raises(NonUnitAxisError):
        system.check_state(y)
