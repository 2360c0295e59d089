"""A third-party pair potential as a plugin author would write it: screened Coulomb (Yukawa)
between charged point masses, the charges read from a body attribute ``charge``.

U(r) = k q1 q2 exp(-r / lam) / r. Registered by the tests' fixtures as an extra plugin.
"""

from __future__ import annotations

import sympy as sp

from poissonkit.plugin.contributions import PairPotential, Param
from poissonkit.plugin.hookspecs import hookimpl

K = 8.9875517923e9  # Coulomb constant [N m^2 / C^2]
LAM = 0.05  # screening length [m]


def yukawa_expr(params):
    r = sp.Symbol("r", real=True)
    return (params["k"] * params["charge1"] * params["charge2"]
            * sp.exp(-r / params["lam"]) / r)


YUKAWA = PairPotential(
    name="test_yukawa",
    doc="Screened Coulomb energy of two point charges, U = k q1 q2 exp(-r/lam) / r.",
    params=(
        Param("charge1", "float", "charge of the first body [C]", unit="C"),
        Param("charge2", "float", "charge of the second body [C]", unit="C"),
        Param("k", "float", "Coulomb constant [N m^2/C^2]", default=K, unit="N m^2/C^2",
              positive=True),
        Param("lam", "float", "screening length [m]", default=LAM, unit="m", positive=True),
    ),
    expr=yukawa_expr,
    orientation="none",
    body_params=(("charge1", "charge", 1), ("charge2", "charge", 2)),
)


@hookimpl
def poissonkit_potentials():
    return [YUKAWA]
