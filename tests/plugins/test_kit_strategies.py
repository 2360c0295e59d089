"""The kit's hypothesis strategies draw what they promise (checked against the definitions,
not against poissonkit's own use of them): unit axes, distances in range, separated bodies,
brackets that satisfy the Jacobi identity (the symbolic Jacobiator vanishes)."""

from __future__ import annotations

import numpy as np
import sympy as sp
from hypothesis import given, settings

from poissonkit.testing import strategies as pks


@given(pks.pair_configurations(distances=(0.01, 0.1)))
def test_pair_configurations_have_unit_axes_and_distances_in_range(cfg):
    # |r| is drawn in range, then carried by a unit vector: equal up to rounding
    assert 0.01 * (1 - 1e-12) <= float(np.linalg.norm(cfg.r)) <= 0.1 * (1 + 1e-12)
    for axis in (cfg.nu1, cfg.nu2):
        assert abs(float(np.linalg.norm(axis)) - 1.0) < 1e-12


@given(pks.bodies({"charge": (1e-9, 1e-8)}))
def test_bodies_carry_the_drawn_attributes(body):
    assert body.is_top and 1e-9 <= body.attribute("charge") <= 1e-8


@given(pks.configurations(4, min_distance=1.0, box=10.0))
def test_configurations_keep_their_bodies_apart(pos):
    d = np.linalg.norm(pos[:, None] - pos[None, :], axis=-1) + np.eye(4) * 10
    assert pos.shape == (4, 3) and d.min() >= 1.0 and np.abs(pos).max() <= 5.0


@settings(max_examples=8, deadline=None)
@given(pks.brackets())
def test_brackets_satisfy_the_jacobi_identity(P):
    x = P.coords
    n = len(x)
    bracket = P.bracket
    for i in range(n):
        for j in range(i + 1, n):
            for k in range(j + 1, n):
                cyclic = (bracket(x[i], bracket(x[j], x[k])) + bracket(x[j], bracket(x[k], x[i]))
                          + bracket(x[k], bracket(x[i], x[j])))
                assert sp.expand(cyclic) == 0
    assert any(sp.expand(bracket(x[i], x[j])) != 0 for i in range(n) for j in range(n))
