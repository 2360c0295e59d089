"""Collision, escape and closest-approach records name the bodies at fault and the distance in
metres (``EventRecord.detail``), and so do their typed errors.

The truth is the scene's construction: two bodies sent head on into each other while a third
stays far, one body launched away from two others; the located distance is checked against
the positions of the last state (numpy, not the compiled kernels)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from poissonkit.errors import CollisionError, EscapeError
from poissonkit.numerics import AllPairs, Body, NBodySystem, TwoBodySystem, solve
from poissonkit.numerics.events import Collision, Escape
from poissonkit.numerics.units import Scales

G = {"G": 1e-9}  # weak: the bodies fly nearly straight, the construction decides who meets


def _three(names, scales=None):
    return NBodySystem([Body(n, 1.0) for n in names], [AllPairs("gravity", G)], scales=scales)


def head_on(order=("far", "a", "b"), scales=None):
    """``a`` and ``b`` 1 apart closing at speed 2 along y (they meet 0.1 apart at t = 0.45);
    ``far`` 50 away at rest."""
    system = _three(order, scales)
    where = {"far": ([50.0, 0, 0], [0, 0, 0]), "a": ([0, 0, 0], [0, 1, 0]),
             "b": ([0, 1.0, 0], [0, -1, 0])}
    pos = [where[n][0] for n in order]
    mom = [where[n][1] for n in order]
    return system, system.pack(pos, mom)


def positions(y, n):
    return np.asarray(y)[: 6 * n].reshape(n, 6)[:, :3]


@pytest.mark.parametrize("order", [("far", "a", "b"), ("a", "far", "b")])
@pytest.mark.parametrize("method, kw", [("splitting4", {"step": 0.01}),
                                        ("dop853", {"tol": 1e-10})])
def test_collision_names_the_pair_that_meets(order, method, kw):
    system, y0 = head_on(order)
    sol = solve(system, y0, 5.0, method, events=[Collision(0.1)], **kw)
    (ev,) = sol.events
    assert ev.kind == "collision" and ev.time == pytest.approx(0.45, abs=1e-6)
    assert ev.detail["bodies"] == ["a", "b"]  # never the (0, 1) pair by default
    pos = positions(sol.y[-1], 3)
    ia, ib = order.index("a"), order.index("b")
    assert ev.detail["distance_m"] == pytest.approx(np.linalg.norm(pos[ia] - pos[ib]), rel=1e-12)
    assert ev.detail["distance_m"] == pytest.approx(0.1, abs=1e-8)
    json.dumps(ev.detail)  # summary.json and the checkpoint write it as is
    with pytest.raises(CollisionError, match=r"bodies 'a' and 'b' came within 0\.1"):
        solve(system, y0, 5.0, method, events=[Collision(0.1, error=True)], **kw)


def test_collision_distance_in_metres_through_the_scales():
    scales = Scales(length=0.01, mass=1.0, time=1.0)
    system, y0 = head_on(scales=scales)  # numbers as given: internal units
    sol = solve(system, y0, 5.0, "splitting4", step=0.01, events=[Collision(0.1)])
    (ev,) = sol.events
    assert ev.detail["bodies"] == ["a", "b"]
    assert ev.detail["distance_m"] == pytest.approx(0.1 * 0.01, rel=1e-8)
    with pytest.raises(CollisionError, match=r"came within 0\.1 \(0\.001 m\)"):
        solve(system, y0, 5.0, "splitting4", step=0.01, events=[Collision(0.1, error=True)])


def test_two_body_form_names_both_bodies():
    from numerics_helpers import DIPOLE  # type: ignore[import-not-found]

    pair = TwoBodySystem(None, None, 3.0, 5.0, DIPOLE, reduced_mass=2.0)
    y0 = pair.pack([1.5, 0, 0], [0, 0, 0], [1, 0, 0], [0, 0, 0], [1, 0, 0], [0, 0, 0])
    sol = solve(pair, y0, 50.0, "splitting4", step=0.01, events=[Collision(0.6)])
    (ev,) = sol.events
    assert ev.detail["bodies"] == ["body1", "body2"]
    assert ev.detail["distance_m"] == pytest.approx(np.linalg.norm(sol.y[-1][:3]), rel=1e-12)


@pytest.mark.parametrize("method, kw", [("splitting4", {"step": 0.01}),
                                        ("dop853", {"tol": 1e-10})])
def test_escape_names_the_body_launched_away(method, kw):
    system = _three(("a", "fast", "c"))
    y0 = system.pack([[0, 0, 0], [1.0, 0, 0], [0, 1.0, 0]], [[0, 0, 0], [0, 0, 3.0], [0, 0, 0]])
    sol = solve(system, y0, 10.0, method, events=[Escape(5.0)], **kw)
    (ev,) = sol.events
    assert ev.kind == "escape" and ev.detail["bodies"] == ["fast"]
    pos = positions(sol.y[-1], 3)
    r = np.linalg.norm(pos - pos.mean(axis=0), axis=1)  # equal masses: the mean is the centre
    assert int(np.argmax(r)) == 1
    assert ev.detail["distance_m"] == pytest.approx(r[1], rel=1e-12)
    with pytest.raises(EscapeError, match=r"body 'fast' reached distance 5"):
        solve(system, y0, 10.0, method, events=[Escape(5.0, error=True)], **kw)


def test_two_fixed_bodies_closer_than_the_distance_are_not_the_pair():
    """Two fixed bodies 0.05 apart never collide (the kernels skip the pair); the moving body
    ``m`` sent at ``post`` at speed 1 meets it 0.1 apart at t = 0.9."""
    system = NBodySystem([Body("wall", 1.0, fixed=True, position=(0.0, 0.05, 0.0)),
                          Body("post", 1.0, fixed=True, position=(0.0, 0.0, 0.0)),
                          Body("m", 1.0)], [AllPairs("gravity", G)])
    y0 = system.pack([[1.0, 0, 0]], [[-1.0, 0, 0]])
    sol = solve(system, y0, 5.0, "splitting4", step=0.01, events=[Collision(0.1)])
    (ev,) = sol.events
    assert ev.time == pytest.approx(0.9, abs=1e-6)
    assert ev.detail["bodies"] == ["post", "m"]
    m = np.asarray(sol.y[-1])[:3]
    assert ev.detail["distance_m"] == pytest.approx(np.linalg.norm(m), rel=1e-12)


@pytest.mark.parametrize("order", [("far", "a", "b"), ("b", "far", "a")])
def test_closest_approach_names_the_pair_that_passes(order):
    """``a`` and ``b`` pass each other 0.2 apart at t = 0.5; ``far`` stays 50 away."""
    from poissonkit.numerics.events import ClosestApproach

    system = _three(order)
    where = {"far": ([50.0, 0, 0], [0, 0, 0]), "a": ([0, 0, 0], [0, 1, 0]),
             "b": ([0.2, 1.0, 0], [0, -1, 0])}
    y0 = system.pack([where[n][0] for n in order], [where[n][1] for n in order])
    sol = solve(system, y0, 1.0, "splitting4", step=0.01, events=[ClosestApproach(0.5)])
    (ev,) = sol.events
    assert ev.kind == "closest_approach" and ev.time == pytest.approx(0.5, abs=1e-6)
    assert ev.detail["bodies"] in (["a", "b"], ["b", "a"])
    assert ev.detail["distance_m"] == pytest.approx(0.2, abs=1e-8)
