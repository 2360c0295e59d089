"""Hook implementations of the example plugin (registered through the entry point)."""

from __future__ import annotations

from typing import Any

import sympy as sp

from poissonkit.plugin import PairPotential, Param, hookimpl


def _lennard_jones(params: dict[str, Any]) -> sp.Expr:
    """U(r) = 4 epsilon [(sigma/r)^12 - (sigma/r)^6] in the symbol r (real)."""
    r = sp.Symbol("r", real=True)
    x = (params["sigma"] / r) ** 6
    return 4 * params["epsilon"] * (x * x - x)


LENNARD_JONES = PairPotential(
    name="lennard_jones",
    doc="Lennard-Jones pair potential U = 4 eps [(sigma/r)^12 - (sigma/r)^6] of two point "
        "particles; minimum -eps at r = 2^(1/6) sigma.",
    params=(
        Param("epsilon", "float", "depth of the well [J]", unit="J", positive=True),
        Param("sigma", "float", "distance where U = 0 [m]", unit="m", positive=True),
    ),
    expr=_lennard_jones,
    orientation="none",
)


@hookimpl
def poissonkit_potentials() -> list[PairPotential]:
    """The Lennard-Jones potential."""
    return [LENNARD_JONES]
