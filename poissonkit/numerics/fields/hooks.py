"""Built-in plugin registering poissonkit's own external fields (``poissonkit_fields`` hook):
uniform gravity and a uniform magnetic field."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numba
import numpy as np

from poissonkit.errors import InputError
from poissonkit.numerics.fields.base import CompiledField, FieldRequest
from poissonkit.numerics.fields.magnetic import UNIFORM_MAGNET
from poissonkit.plugin.contributions import ExternalField, Param
from poissonkit.plugin.hookspecs import hookimpl


@numba.njit(cache=True, error_model="numpy")
def gravity_energy(x, y, z, n0, n1, n2, c, P):
    """``U = −c g·r`` of a mass ``c`` in the uniform gravity ``g = P[0:3]``."""
    return (-c * (P[0] * x + P[1] * y + P[2] * z), -c * P[0], -c * P[1], -c * P[2],
            0.0, 0.0, 0.0)


def _vector3(params: Mapping[str, Any], key: str, name: str) -> np.ndarray:
    v = np.asarray(params[key], dtype=float)
    if v.shape != (3,):
        raise InputError(f"{name}: {key} must have 3 components, got {list(params[key])!r}")
    return np.ascontiguousarray(v)


def _gravity(params: Mapping[str, Any], request: FieldRequest, source: object = None
             ) -> CompiledField:
    g = _vector3(params, "g", "gravity")
    return CompiledField("gravity", gravity_energy, g, reads="mass", orientation=False,
                         info={"g": tuple(float(x) for x in g)})


def _uniform(params: Mapping[str, Any], request: FieldRequest, source: object = None
             ) -> CompiledField:
    b = _vector3(params, "B", "uniform")
    return CompiledField("uniform", UNIFORM_MAGNET, b, reads="moment", orientation=True,
                         info={"B": tuple(float(x) for x in b)})


GRAVITY = ExternalField(
    name="gravity",
    doc="Uniform gravity: U = -M g.r on every body with a mass.",
    params=(Param("g", "vector", "gravitational acceleration [m/s^2]", (0.0, 0.0, -9.80665),
                  unit="m/s^2"),),
    reads="mass", orientation=False, build=_gravity)

UNIFORM = ExternalField(
    name="uniform",
    doc="Uniform magnetic field: U = -mu nu.B on every body with a moment (torque only).",
    params=(Param("B", "vector", "magnetic flux density [T]", unit="T"),),
    reads="moment", orientation=True, build=_uniform)


@hookimpl
def poissonkit_fields() -> list[ExternalField]:
    """Uniform gravity and the uniform magnetic field."""
    return [GRAVITY, UNIFORM]
