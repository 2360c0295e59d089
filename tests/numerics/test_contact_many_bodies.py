"""``Contact.value`` on many bodies: candidate pairs from a k-d tree give the sign and, where a
pair is close, the value of the all-pairs loop (which stays the path for few bodies)."""

from __future__ import annotations

import numpy as np
import pytest

from poissonkit.numerics import AllPairs, Body, NBodySystem
from poissonkit.numerics import events
from poissonkit.numerics.events import BodyShape, Contact


def _scene(n: int, spacing: float, seed: int):
    rng = np.random.default_rng(seed)
    side = int(np.ceil(n ** (1 / 3)))
    grid = np.stack(np.meshgrid(*[np.arange(side)] * 3, indexing="ij"), -1).reshape(-1, 3)[:n]
    pos = grid * spacing + rng.uniform(-0.2, 0.2, size=(n, 3)) * spacing
    axes = rng.normal(size=(n, 3))
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    system = NBodySystem([Body(f"b{k}", 1.0, alpha=1.0) for k in range(n)],
                         [AllPairs("gravity", {"G": 1e-9})])
    y = system.pack(pos, np.zeros((n, 3)), axes, np.zeros((n, 3)))
    # cylinders and balls of mixed sizes
    shapes = tuple(BodyShape(f"b{k}", 0.1 + 0.05 * (k % 3), 0.3 * (k % 2)) for k in range(n))
    return system, y, Contact(shapes)


@pytest.mark.parametrize("spacing,seed", [(1.0, 1), (0.75, 2), (0.62, 3), (3.0, 4)])
def test_tree_candidates_agree_with_every_pair(monkeypatch, spacing, seed):
    system, y, contact = _scene(150, spacing, seed)
    tree = contact.value(system, y)
    monkeypatch.setattr(events, "TREE_SHAPES", 10**9)
    every = contact.value(system, y)
    assert np.sign(tree) == np.sign(every)
    reach = max(np.hypot(s.radius, s.half_length) for s in contact.shapes)
    if every < reach:  # a close pair decides: the same number
        assert tree == every
    else:  # all far apart: a positive lower bound of the true gap
        assert 0 < tree <= every
