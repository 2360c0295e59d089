"""An external field: an isotropic harmonic trap ``U = ½ M ω² |r − c|²`` on every body with a
mass (an optical or magneto-optical trap in its harmonic approximation).

A field plugin gives the energy and its partial derivatives, compiled with numba; the host
derives the force ``−∂U/∂r`` (and torques, for a field that depends on the axis).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numba
import numpy as np

from poissonkit.numerics.fields import CompiledField, FieldRequest
from poissonkit.plugin import ExternalField, Param


@numba.njit(cache=True)
def trap_energy(x, y, z, n0, n1, n2, c, P):
    """``(U, ∂U/∂r, ∂U/∂ν)`` of a mass ``c`` in the trap ``P = [ω², c_x, c_y, c_z]``."""
    k = c * P[0]
    dx = x - P[1]
    dy = y - P[2]
    dz = z - P[3]
    return 0.5 * k * (dx * dx + dy * dy + dz * dz), k * dx, k * dy, k * dz, 0.0, 0.0, 0.0


def build_trap(params: Mapping[str, Any], request: FieldRequest, source: object = None
               ) -> CompiledField:
    """The compiled trap for the resolved parameters."""
    data = np.array([params["omega"] ** 2, *params["centre"]], dtype=float)
    return CompiledField("harmonic_trap", trap_energy, data, reads="mass",
                         info={"omega_per_s": params["omega"], "centre_m": list(params["centre"])})


HARMONIC_TRAP = ExternalField(
    name="harmonic_trap",
    doc="Isotropic harmonic trap U = M omega^2 |r - centre|^2 / 2 on every body with a mass.",
    params=(Param("omega", "float", "angular frequency of the trap [1/s]", unit="1/s",
                  positive=True),
            Param("centre", "vector", "centre of the trap [m]", (0.0, 0.0, 0.0), unit="m")),
    reads="mass", orientation=False, build=build_trap)
