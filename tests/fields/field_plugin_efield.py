"""A third-party external field as a plugin author would write it: a uniform electric field
on every body with a ``charge`` (U = -q E.r). Registered by the tests' fixture."""

from __future__ import annotations

import numba
import numpy as np

from poissonkit.numerics.fields import CompiledField
from poissonkit.plugin import ExternalField, Param, hookimpl


@numba.njit(cache=True)
def efield_energy(x, y, z, n0, n1, n2, c, P):
    return (-c * (P[0] * x + P[1] * y + P[2] * z), -c * P[0], -c * P[1], -c * P[2],
            0.0, 0.0, 0.0)


def build(params, request, source=None):
    return CompiledField("test_efield", efield_energy, np.asarray(params["E"], dtype=float),
                         reads="charge")


EFIELD = ExternalField(
    name="test_efield", doc="Uniform electric field on charged bodies: U = -q E.r.",
    params=(Param("E", "vector", "electric field [V/m]", unit="V/m"),),
    reads="charge", build=build)


@hookimpl
def poissonkit_fields():
    return [EFIELD]
