"""Planetary systems of the Wisdom–Holman tests and their truth, REBOUND's IAS15.

Import as ``from planet_systems import ...`` (each test folder is on ``sys.path``). REBOUND is
in the test extra: missing it must fail, not skip.
"""

from __future__ import annotations

import math

import numpy as np
import rebound

from poissonkit.numerics import AllPairs, Body, NBodySystem


def elements_to_state(mu: float, a: float, e: float, inc: float, f: float):
    """Position/velocity of a Keplerian orbit (pericentre on x, node on x), true anomaly f."""
    p = a * (1 - e * e)
    r = p / (1 + e * math.cos(f))
    x = np.array([r * math.cos(f), r * math.sin(f), 0.0])
    v = math.sqrt(mu / p) * np.array([-math.sin(f), e + math.cos(f), 0.0])
    rot = np.array([[1, 0, 0], [0, math.cos(inc), -math.sin(inc)],
                    [0, math.sin(inc), math.cos(inc)]])
    return rot @ x, rot @ v


def two_planets(eps: float = 1e-2, cutoff: float | None = None):
    """A star and two planets of mass ``eps`` on well-separated eccentric, inclined orbits
    (a = 1 and 1.7, G = 1), barycentric: the system, its state, masses, positions, velocities."""
    m = np.array([1.0, eps, eps])
    x1, v1 = elements_to_state(1 + eps, 1.0, 0.05, 0.0, 0.3)
    x2, v2 = elements_to_state(1 + 2 * eps, 1.7, 0.1, 0.1, 2.0)
    x = np.array([[0, 0, 0], x1, x2])
    v = np.array([[0, 0, 0], v1, v2])
    x -= (m[:, None] * x).sum(0) / m.sum()
    v -= (m[:, None] * v).sum(0) / m.sum()
    system = NBodySystem([Body(n, mk) for n, mk in zip(("star", "b", "c"), m)],
                         [AllPairs("gravity", {"G": 1.0})], cutoff=cutoff)
    return system, system.pack(x, m[:, None] * v), m, x, v


def ias15(m, x, v, t_end, G: float = 1.0):
    """Positions (n, 3) at ``t_end`` of point masses ``m`` from ``x``, ``v`` by REBOUND's IAS15
    (machine precision), gravitational constant ``G``."""
    sim = rebound.Simulation()
    sim.G = G
    for k in range(len(m)):
        sim.add(m=m[k], x=x[k, 0], y=x[k, 1], z=x[k, 2], vx=v[k, 0], vy=v[k, 1], vz=v[k, 2])
    sim.integrator = "ias15"
    sim.integrate(t_end, exact_finish_time=1)
    return np.array([[p.x, p.y, p.z] for p in sim.particles])
