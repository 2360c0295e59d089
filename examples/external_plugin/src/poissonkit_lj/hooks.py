"""Hook implementations of the example plugin (registered through the entry point).

It uses every extension point a built-in plugin uses, through public API only:

* pair potentials — ``lennard_jones`` (central), ``finite_dipole`` and ``point_dipole``
  (orientation-dependent, :mod:`poissonkit_lj.dipoles`), whose charges and dipole lengths are
  body attributes (``charge``, ``dipole_length``) read per body, and whose ``evaluate`` serves
  ``pair_interaction`` without compiling a kernel per parameter set;
* a model family — ``electric_dipoles``: ``point_dipole`` far, ``finite_dipole`` near, with the
  error estimate of :func:`poissonkit_lj.dipoles.point_dipole_error`, for the planner and
  ``pair_interaction("auto", ...)``;
* a scene — ``dipole_pair`` (a TOML file shipped in this package), runnable by name and
  sweepable;
* a sweep outcome — ``max_axis_tilt``, the largest angle any top's axis turned away from its
  initial direction;
* an external field — ``harmonic_trap`` (:mod:`poissonkit_lj.trap`), a one-body energy on every
  body with a mass.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from importlib import resources
from typing import Any

import numpy as np
import sympy as sp

from poissonkit.plugin import (
    ExternalField,
    ModelFamily,
    OutcomeEntry,
    PairPotential,
    Param,
    SceneEntry,
    hookimpl,
)
from poissonkit_lj.dipoles import (
    COULOMB_K,
    evaluator,
    finite_dipole_expr,
    point_dipole_error,
    point_dipole_expr,
)

#: The plugin API version this plugin was written for (``poissonkit plugins`` shows it and
#: warns when the installed poissonkit has another major version).
POISSONKIT_API = "1.0"


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

#: Parameters shared by both dipole models; per-body ones default to the body attributes.
_DIPOLE_PARAMS = (
    Param("charge1", "float", "charge of the first body's dipole [C]", unit="C", positive=True),
    Param("charge2", "float", "charge of the second body's dipole [C]", unit="C", positive=True),
    Param("dipole_length1", "float", "charge separation of the first body [m]", unit="m",
          positive=True),
    Param("dipole_length2", "float", "charge separation of the second body [m]", unit="m",
          positive=True),
    Param("k", "float", "Coulomb constant 1/(4 pi eps0) [N m^2/C^2]", default=COULOMB_K,
          unit="N m^2/C^2", positive=True),
)
_DIPOLE_BODY_PARAMS = (("charge1", "charge", 1), ("charge2", "charge", 2),
                       ("dipole_length1", "dipole_length", 1),
                       ("dipole_length2", "dipole_length", 2))

FINITE_DIPOLE = PairPotential(
    name="finite_dipole",
    doc="Exact Coulomb energy of two finite electric dipoles (charges +-q at +-d/2 along each "
        "axis).",
    params=_DIPOLE_PARAMS,
    expr=finite_dipole_expr,
    evaluate=evaluator(finite_dipole_expr),
    orientation="both",
    body_params=_DIPOLE_BODY_PARAMS,
)

POINT_DIPOLE = PairPotential(
    name="point_dipole",
    doc="Point-dipole energy k p1 p2 (c3 - 3 c1 c2)/r^3 of two electric dipoles, p = q d.",
    params=_DIPOLE_PARAMS,
    expr=point_dipole_expr,
    evaluate=evaluator(point_dipole_expr),
    orientation="both",
    body_params=_DIPOLE_BODY_PARAMS,
)


def _dipole_length(body: Mapping[str, Any]) -> float:
    return float(body.get("dipole_length", 0.0) or 0.0)


def _charge(body: Mapping[str, Any]) -> float:
    return float(body.get("charge", 0.0) or 0.0)


def _applies(body1: Mapping[str, Any], body2: Mapping[str, Any]) -> bool:
    """Both bodies carry a dipole (a charge and a dipole length)."""
    return all(_charge(b) > 0 and _dipole_length(b) > 0 for b in (body1, body2))


def _estimate(model: str, r: float, body1: Mapping[str, Any], body2: Mapping[str, Any]) -> float:
    """Relative force error: 0 for the exact model, the point-dipole estimate otherwise."""
    if model == "finite_dipole":
        return 0.0
    if model == "point_dipole":
        return point_dipole_error(r, _dipole_length(body1), _dipole_length(body2))
    raise ValueError(f"not a model of the electric_dipoles family: {model!r}")


def _energy_bound(r: float, body1: Mapping[str, Any], body2: Mapping[str, Any]) -> float:
    """|U| ≤ 2 k p1 p2 / r³ (1 + ε_point(r)): the point-dipole bound widened by its error."""
    p1 = _charge(body1) * _dipole_length(body1)
    p2 = _charge(body2) * _dipole_length(body2)
    err = point_dipole_error(r, _dipole_length(body1), _dipole_length(body2))
    return 2.0 * COULOMB_K * p1 * p2 / r ** 3 * (1.0 + err)


ELECTRIC_DIPOLES = ModelFamily(
    name="electric_dipoles",
    doc="Finite electric dipoles: point dipoles far, the exact four-charge model near "
        "(point-dipole force error <= 2 (d1^2 + d2^2)/r^2 / (1 - (rho/r)^2)).",
    models=("point_dipole", "finite_dipole"),
    costs=(1.0, 4.0),
    estimate=_estimate,
    applies=_applies,
    reads=("charge", "dipole_length"),
    energy_bound=_energy_bound,
)


def _scene_path() -> str:
    return str(resources.files("poissonkit_lj") / "scenes" / "dipole_pair.toml")


def _dipole_scene(**_: Any):
    from poissonkit.scene import load_scene

    return load_scene(_scene_path())


def _dipole_sweep(**options: Any):
    from poissonkit.sweeps.targets import TomlScene

    return TomlScene.from_file(_scene_path(), **options)


DIPOLE_SCENE = SceneEntry(
    name="dipole_pair",
    doc="Two finite electric dipoles on a circular orbit with a fixed third one far away; "
        "the planner picks point or finite dipoles per pair.",
    load=_dipole_scene,
    sweep=_dipole_sweep,
)


def _max_axis_tilt(record: Any) -> float:
    """Largest angle [rad] between a top's axis and its initial axis over the saved states."""
    sol = record.solution
    system = sol.system
    parts = system.unpack(np.asarray(sol.y), si=True)
    # N-body form: "nu" (time, top, 3); the two-body centre-of-mass form: "nu1", "nu2"
    axes = [parts["nu"]] if "nu" in parts else [parts[k][:, None] for k in ("nu1", "nu2")
                                                if k in parts]
    if not axes:
        return math.nan
    nu = np.concatenate([np.asarray(a, dtype=float) for a in axes], axis=1)
    if nu.ndim != 3 or nu.shape[1] == 0:
        return math.nan
    nu = nu / np.linalg.norm(nu, axis=-1, keepdims=True)
    cos = np.clip(np.einsum("tbk,bk->tb", nu, nu[0]), -1.0, 1.0)
    return float(np.max(np.arccos(cos)))


MAX_AXIS_TILT = OutcomeEntry(
    name="max_axis_tilt",
    doc="largest angle between a top's axis and its initial direction",
    dtype="f8",
    unit="rad",
    fill=math.nan,
    compute=_max_axis_tilt,
)


@hookimpl
def poissonkit_potentials() -> list[PairPotential]:
    """The Lennard-Jones potential and the two electric-dipole models."""
    return [LENNARD_JONES, FINITE_DIPOLE, POINT_DIPOLE]


@hookimpl
def poissonkit_model_families() -> list[ModelFamily]:
    """The electric-dipole family (point dipole far, exact four charges near)."""
    return [ELECTRIC_DIPOLES]


@hookimpl
def poissonkit_scenes() -> list[SceneEntry]:
    """The ``dipole_pair`` scene."""
    return [DIPOLE_SCENE]


@hookimpl
def poissonkit_outcomes() -> list[OutcomeEntry]:
    """The ``max_axis_tilt`` sweep outcome."""
    return [MAX_AXIS_TILT]


@hookimpl
def poissonkit_fields() -> list[ExternalField]:
    """The ``harmonic_trap`` external field."""
    from poissonkit_lj.trap import HARMONIC_TRAP

    return [HARMONIC_TRAP]
