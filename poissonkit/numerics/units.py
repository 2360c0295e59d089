"""Nondimensionalisation of SI scenes.

Seed 000's magnets weigh about 1e-4 kg and have ``alpha = 1/I_perp`` of about 3.9e7 kg⁻¹m⁻²;
integrating in SI mixes numbers of very different size. A :class:`Scales` fixes a length, a mass
and a time unit; every derived unit follows from them:

==================  ===================
quantity            unit
==================  ===================
position            ``L``
momentum            ``M L / T``
angular momentum    ``M L^2 / T``
energy              ``M L^2 / T^2``
alpha = 1/I         ``1 / (M L^2)``
force               ``M L / T^2``
torque              ``M L^2 / T^2``
==================  ===================

``nd = si / unit`` and ``si = nd * unit``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from poissonkit.errors import InputError
from poissonkit.validation import positive_number

_EXPONENTS = {  # (length, mass, time)
    "length": (1, 0, 0), "mass": (0, 1, 0), "time": (0, 0, 1),
    "momentum": (1, 1, -1), "angular_momentum": (2, 1, -1), "energy": (2, 1, -2),
    "alpha": (-2, -1, 0), "inertia": (2, 1, 0), "force": (1, 1, -2), "torque": (2, 1, -2),
    "velocity": (1, 0, -1), "frequency": (0, 0, -1), "dimensionless": (0, 0, 0),
}


@dataclass(frozen=True)
class Scales:
    """Units of length [m], mass [kg] and time [s] used inside the numerics.

    Parameters
    ----------
    length, mass, time
        Positive, finite SI values of the internal units.

    Examples
    --------
    >>> s = Scales(length=0.01, mass=1e-4, time=0.1)
    >>> s.unit("energy")
    1e-06
    """

    length: float = 1.0
    mass: float = 1.0
    time: float = 1.0

    def __post_init__(self) -> None:
        for name, v in (("length", self.length), ("mass", self.mass), ("time", self.time)):
            object.__setattr__(self, name, positive_number(v, f"Scales.{name}"))

    @classmethod
    def from_energy(cls, length: float, mass: float, energy: float) -> Scales:
        """Scales whose energy unit is ``energy`` (time ``= L sqrt(M / E)``)."""
        if not energy > 0:
            raise InputError(f"energy scale must be > 0, got {energy!r}")
        return cls(length, mass, length * math.sqrt(mass / energy))

    def unit(self, kind: str) -> float:
        """SI value of the internal unit of ``kind`` (see the module table)."""
        try:
            a, b, c = _EXPONENTS[kind]
        except KeyError:
            from poissonkit.errors import UnknownNameError

            raise UnknownNameError("quantity kind", kind, _EXPONENTS) from None
        return self.length ** a * self.mass ** b * self.time ** c

    @property
    def energy(self) -> float:
        """Energy unit [J]."""
        return self.unit("energy")

    def to_internal(self, value, kind: str):
        """SI value(s) → internal (nondimensional) value(s)."""
        return np.asarray(value, dtype=float) / self.unit(kind) if np.ndim(value) else \
            float(value) / self.unit(kind)

    def to_si(self, value, kind: str):
        """Internal value(s) → SI value(s)."""
        return np.asarray(value, dtype=float) * self.unit(kind) if np.ndim(value) else \
            float(value) * self.unit(kind)
