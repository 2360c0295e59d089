"""Deliberately broken pair potentials, each with one defect the kit must name (and one with
all of them): a Coulomb-like ``U = k q1 q2 / r`` between charges read from the bodies."""

from __future__ import annotations

import numba
import sympy as sp

from poissonkit.plugin import PairPotential, Param

R = sp.Symbol("r", real=True)
PARAMS = (Param("q1", "float", "charge of body 1 [C]", unit="C"),
          Param("q2", "float", "charge of body 2 [C]", unit="C"),
          Param("k", "float", "coupling [N m^2/C^2]", default=2.0, unit="N m^2/C^2",
                positive=True))
SIZES = (Param("size1", "float", "size of body 1 [m]", unit="m"),
         Param("size2", "float", "size of body 2 [m]", unit="m"))
READS = (("q1", "charge", 1), ("q2", "charge", 2))
UNREAD = (("size1", "size", 1), ("size2", "size", 2))


def good_expr(p):
    return p["k"] * p["q1"] * p["q2"] / R


def asymmetric_expr(p):
    return p["k"] * p["q1"] * p["q2"] ** 2 / R


def branching_expr(p):
    # the value of k decides the code: with a symbol for k this raises, so every k compiles
    return (p["k"] if p["k"] > 1.5 else 2 * p["k"]) * p["q1"] * p["q2"] / R


def all_broken_expr(p):
    return (p["k"] if p["k"] > 1.5 else 2 * p["k"]) * p["q1"] * p["q2"] ** 2 / R


def off_kernel(params):
    """The energy right, its r-derivative 1 % too large."""
    c = float(params["k"]) * float(params["q1"]) * float(params["q2"])

    @numba.njit
    def f(r, c1, c2, c3):
        u = c / r
        return u, -1.01 * u / r, 0.0, 0.0, 0.0
    return f


def all_broken_kernel(params):
    c = float(params["k"]) * float(params["q1"]) * float(params["q2"]) ** 2

    @numba.njit
    def f(r, c1, c2, c3):
        u = c / r
        return u, -1.01 * u / r, 0.0, 0.0, 0.0
    return f


def _entry(name, doc, expr, kernel=None, params=PARAMS, body_params=READS):
    return PairPotential(name=name, doc=doc, params=params, expr=expr, kernel=kernel,
                         orientation="none", body_params=body_params)


GOOD = _entry("kit_good", "a correct Coulomb-like potential", good_expr)
FORCE_OFF = _entry("kit_force_off", "force 1 % off the gradient", good_expr, off_kernel)
ASYMMETRIC = _entry("kit_asymmetric", "U = k q1 q2^2 / r: not symmetric", asymmetric_expr)
UNREAD_ATTRIBUTE = _entry("kit_unread", "body_params names a size no kernel reads", good_expr,
                          params=PARAMS + SIZES, body_params=READS + UNREAD)
RECOMPILES = _entry("kit_recompiles", "k shapes the compiled code", branching_expr)
ALL_BROKEN = _entry("kit_all_broken", "every defect at once", all_broken_expr,
                    all_broken_kernel, params=PARAMS + SIZES, body_params=READS + UNREAD)
