"""The magnets' run-time-parameter kernels give the same bits as the constant kernels.

``param_kernel(params)(r, c1, c2, c3, P)`` with ``P = param_values(params)`` must equal
``kernel(params)(r, c1, c2, c3)`` exactly (the same operations on the same values, combined
constants rounded in the same order), and be one function for every value of the floats.
"""

from __future__ import annotations

import pytest

from poissonkit.plugin import entries

CASES = {
    "dipole": {"moment1": 0.12, "moment2": -0.07},
    "dumbbell": {"moment1": 0.15, "moment2": 0.11, "half_length1": 0.01, "half_length2": 0.007},
    "dumbbell_octupole": {"moment1": 0.15, "moment2": 0.11, "radius1": 1.25e-3,
                          "length1": 0.02, "radius2": 1e-3, "length2": 0.015},
    "dipole_loop": {"current1": 2.0, "radius1": 0.01, "moment2": 0.05, "n_nodes": 64},
}
POINTS = [(0.05, 0.3, -0.6, 0.2), (0.031, -0.9, 0.1, -0.4), (0.2, 0.0, 1.0, 1.0)]


@pytest.mark.parametrize("name", sorted(CASES))
def test_parameter_kernel_equals_constant_kernel_bitwise(name):
    pots = entries("potential")
    if name not in pots:
        pytest.skip("the magnets plugin is not installed")
    entry = pots[name]
    params = entry.resolve_params(CASES[name])
    const = entry.kernel(params)
    f = entry.param_kernel(params)
    P = tuple(entry.param_values(params))
    for pt in POINTS:
        assert f(*pt, P) == const(*pt)
    other = entry.resolve_params({**CASES[name], "mu0": 1.1e-6})
    assert entry.param_kernel(other) is f  # one function whatever the float values
    assert tuple(entry.param_values(other)) != P
