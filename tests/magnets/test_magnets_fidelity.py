"""The model-fidelity estimates bound the true force error against the exact cylinder model
(MAGNETS.md §4 gives the asymptotic laws; the truth here is the exact model, itself validated
against magpylib in test_magnets_cylinder.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from poissonkit.errors import InputError, UnknownNameError
from poissonkit.pairs import OverlapError, pair_interaction
from poissonkit_magnets.fidelity import cheapest_model, estimated_error

CHEAP = ("dipole", "dumbbell", "dumbbell_octupole")


def _orientations(n_random, seed=1):
    z, x = np.array([0, 0, 1.0]), np.array([1.0, 0, 0])
    out = [(z, z, z), (z, z, -z), (x, z, z), (x, z, -z), (z, z, x), (x, x, z)]
    rng = np.random.default_rng(seed)
    for _ in range(n_random):
        v = rng.normal(size=(3, 3))
        out.append(tuple(v / np.linalg.norm(v, axis=1)[:, None]))
    return out


def _ratios(aspects, seps, n_random):
    """max over the grid of true force error / estimate, per model, and the worst torque ratio."""
    worst = {m: 0.0 for m in CHEAP}
    worst_torque = 0.0
    h = 0.02
    for ah in aspects:
        a = ah * h
        s = 2 * math.hypot(h / 2, a)
        for k in seps:
            r = k * s
            for e, n1, n2 in _orientations(n_random):
                try:
                    exact = pair_interaction("cylinder", r * e, n1, n2, magnetization=1e6,
                                             radius=a, length=h)
                except OverlapError:
                    continue
                mu = 1e6 * math.pi * a * a * h
                tscale = 1e-7 * mu * mu / r ** 3
                for m in CHEAP:
                    est = estimated_error(m, r, a, h)
                    if not math.isfinite(est):
                        continue
                    out = pair_interaction(m, r * e, n1, n2, magnetization=1e6, radius=a,
                                           length=h)
                    err = np.linalg.norm(out.force - exact.force) / np.linalg.norm(exact.force)
                    worst[m] = max(worst[m], err / est)
                    terr = max(np.linalg.norm(out.torque1 - exact.torque1),
                               np.linalg.norm(out.torque2 - exact.torque2)) / tscale
                    worst_torque = max(worst_torque, terr / est)
    return worst, worst_torque


def test_estimates_bound_the_true_force_error():
    worst, _ = _ratios(aspects=(1 / 16, 0.5, 2.0), seps=(1.06, 1.2, 1.5, 2.5, 6, 20),
                       n_random=2)
    for model, ratio in worst.items():
        assert ratio <= 1.0, (model, ratio)
        # ... and are not vacuous: the far-field law is tight to the safety factor 2
        assert ratio >= 0.3, (model, ratio)


@pytest.mark.slow
def test_estimates_bound_force_and_torque_errors_on_a_fine_grid():
    worst, worst_torque = _ratios(aspects=(1 / 16, 1 / 8, 0.25, 0.5, 1.0, 2.0),
                                  seps=(1.06, 1.1, 1.2, 1.4, 1.7, 2, 3, 5, 10, 30), n_random=6)
    assert max(worst.values()) <= 1.0
    # torque error over the dipole torque scale obeys the same estimate
    assert worst_torque <= 1.0


def test_cheapest_model_goes_from_exact_to_dipole_with_distance():
    a, h = 1.25e-3, 0.02
    picks = [cheapest_model(1e-2, r, a, h) for r in (0.021, 0.04, 0.1, 0.5)]
    assert picks == ["cylinder", "dumbbell_octupole", "dumbbell_octupole", "dipole"]
    # a looser tolerance never asks for a costlier model
    order = ("dipole", "dumbbell_octupole", "dumbbell", "cylinder")
    for r in (0.025, 0.05, 0.2, 1.0):
        costs = [order.index(cheapest_model(t, r, a, h)) for t in (1e-1, 1e-2, 1e-3, 1e-4)]
        assert costs == sorted(costs)


@pytest.mark.parametrize("tol", [1e-2, 1e-3])
def test_auto_meets_its_tolerance(tol):
    a, h, m = 1.25e-3, 0.02, 1.58359e6
    rng = np.random.default_rng(5)
    for r in (0.03, 0.06, 0.15, 0.4):
        e, n1, n2 = (v / np.linalg.norm(v) for v in rng.normal(size=(3, 3)))
        auto = pair_interaction("auto", r * e, n1, n2, magnetization=m, radius=a, length=h,
                                tol=tol)
        exact = pair_interaction("cylinder", r * e, n1, n2, magnetization=m, radius=a, length=h)
        err = np.linalg.norm(auto.force - exact.force) / np.linalg.norm(exact.force)
        assert err <= tol
        assert auto.estimated_error <= tol


def test_flat_magnets_never_get_the_octupole_dumbbell():
    assert estimated_error("dumbbell_octupole", 1.0, 0.02, 0.01) == math.inf
    assert cheapest_model(1e-3, 0.3, 0.02, 0.01) in ("dipole", "dumbbell", "cylinder")


def test_fidelity_rejects_bad_input():
    with pytest.raises(UnknownNameError, match="available"):
        estimated_error("quadrupole", 0.1, 1e-3, 1e-2)
    with pytest.raises(InputError):
        estimated_error("dipole", -0.1, 1e-3, 1e-2)
    with pytest.raises(InputError):
        estimated_error("dipole", 0.1, 0.0, 1e-2)
    with pytest.raises(InputError):
        cheapest_model(0.0, 0.1, 1e-3, 1e-2)
