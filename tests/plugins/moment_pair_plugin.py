"""A third-party central potential reading the magnets' body attribute ``moment``:
``U = k m1 m2 / r³`` (a made-up coupling, for tests that mix it with the magnet models)."""

from __future__ import annotations

import sympy as sp

from poissonkit.plugin import PairPotential, Param, hookimpl

K = 1e-7  # [T m/A], mu0 / (4 pi)


def moment_expr(params):
    r = sp.Symbol("r", real=True)
    return params["k"] * params["moment1"] * params["moment2"] / r ** 3


MOMENT_CENTRAL = PairPotential(
    name="test_moment_central",
    doc="Central coupling U = k m1 m2 / r^3 of two magnetic moments (a test potential).",
    params=(Param("moment1", "float", "moment of the first body [A m^2]", unit="A m^2"),
            Param("moment2", "float", "moment of the second body [A m^2]", unit="A m^2"),
            Param("k", "float", "coupling [T m/A]", default=K, unit="T m/A", positive=True)),
    expr=moment_expr,
    orientation="none",
    body_params=(("moment1", "moment", 1), ("moment2", "moment", 2)),
)


@hookimpl
def poissonkit_potentials():
    return [MOMENT_CENTRAL]
