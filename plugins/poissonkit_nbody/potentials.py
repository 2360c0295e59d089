"""Central pair potentials of point masses contributed by the N-body plugin."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from poissonkit.conventions import NEWTON_G
from poissonkit.plugin.contributions import PairPotential, Param

if TYPE_CHECKING:
    import sympy as sp


def _gravity_expr(params: dict[str, Any]) -> sp.Expr:
    import sympy as sp  # only when the expression is asked for, not at plugin load

    r = sp.Symbol("r", real=True)
    return -params["G"] * params["mass1"] * params["mass2"] / r


def _gravity_energy_scale(bodies: Sequence[Any], length: float) -> float:
    """Energy unit of a gravitating scene: ``G M^2 / L`` with ``M`` the mean body mass."""
    mass = float(np.mean([b.mass for b in bodies]))
    return NEWTON_G * mass * mass / length


GRAVITY = PairPotential(
    name="gravity",
    doc="Newtonian gravity of two point masses, U = -G m1 m2 / r (orientation-free).",
    params=(
        Param("mass1", "float", "mass of the first body [kg]", unit="kg", positive=True),
        Param("mass2", "float", "mass of the second body [kg]", unit="kg", positive=True),
        Param("G", "float", "gravitational constant [m^3/(kg s^2)]", default=NEWTON_G,
              unit="m^3/(kg s^2)", positive=True),
    ),
    expr=_gravity_expr,
    orientation="none",
    # an all-pairs gravity interaction takes each pair's masses from its two bodies
    body_params=(("mass1", "mass", 1), ("mass2", "mass", 2)),
    energy_scale=_gravity_energy_scale,
)
