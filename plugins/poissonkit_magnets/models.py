"""The magnet models as data: parameters, compiled cores and (where closed) sympy expressions.

Each :class:`Model` knows how to turn validated parameters into the argument tuple of its
compiled core ``core(r, c1, c2, c3, *args) -> (U, U_r, U_c1, U_c2, U_c3)``. The plugin wraps
these as :class:`poissonkit.plugin.PairPotential` entries; :func:`evaluate` calls a core
directly (no per-parameter compilation), which is what ``poissonkit.pair_interaction`` uses.
"""

from __future__ import annotations

import math
import threading
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np

from poissonkit.conventions import MU0
from poissonkit.errors import InputError
from poissonkit.numerics.jit import compile_generated, jit
from poissonkit.plugin.contributions import Param
from poissonkit_magnets import analytic, cylinder, fields, loops


@dataclass(frozen=True)
class Model:
    """One magnet pair model.

    Attributes
    ----------
    name, doc, params
        As in the registry entry.
    core
        Compiled scalar core ``core(r, c1, c2, c3, *args)``.
    args
        ``args(params) -> tuple`` of the core's extra arguments (SI floats and ints).
    expr
        ``expr(params) -> sympy.Expr`` or ``None`` when U has no closed form.
    folded
        Optional core ``folded(r, c1, c2, c3, *fold(params))`` taking the per-pair constants
        already combined (e.g. ``mu0 m1 m2``): the run-time-parameter kernel
        (:func:`param_kernel`) then does no more work per call than one with constants
        compiled in, and gives the same bits.
    fold
        ``fold(params) -> tuple`` of floats for ``folded``.
    """

    name: str
    doc: str
    params: tuple[Param, ...]
    core: Callable[..., tuple[float, float, float, float, float]]
    args: Callable[[Mapping[str, Any]], tuple]
    expr: Callable[[Mapping[str, Any]], Any] | None = None
    folded: Callable[..., tuple[float, float, float, float, float]] | None = None
    fold: Callable[[Mapping[str, Any]], tuple] | None = None


def _p(name: str, doc: str, unit: str, positive: bool = False, default: Any = None,
       type_: str = "float") -> Param:
    return Param(name=name, type=type_, doc=doc, default=default, unit=unit, positive=positive)


MU0_PARAM = _p("mu0", "vacuum permeability [H/m]", "H/m", positive=True, default=MU0)


def _moments() -> tuple[Param, Param]:
    return (_p("moment1", "magnetic moment of body 1 [A m^2]", "A m^2"),
            _p("moment2", "magnetic moment of body 2 [A m^2]", "A m^2"))


def _sizes(i: int) -> tuple[Param, Param]:
    return (_p(f"radius{i}", f"radius of cylinder {i} [m]", "m", positive=True),
            _p(f"length{i}", f"full height of cylinder {i} [m]", "m", positive=True))


def _octupole_args(p: Mapping[str, Any]) -> tuple:
    try:
        le1 = analytic.effective_half_length(p["radius1"], p["length1"])
        le2 = analytic.effective_half_length(p["radius2"], p["length2"])
    except ValueError as exc:
        raise InputError(f"dumbbell_octupole: {exc}") from None
    return (p["moment1"], p["moment2"], le1, le2, p["mu0"])


def _self_inductances(p: Mapping[str, Any]) -> tuple[float, float]:
    try:
        return (loops.self_inductance(p["radius1"], p["wire_radius1"], p["mu0"]),
                loops.self_inductance(p["radius2"], p["wire_radius2"], p["mu0"]))
    except ValueError as exc:
        raise InputError(f"superconducting_rings: {exc}") from None


def _dumbbell_fold(m1: float, m2: float, l1: float, l2: float, mu0: float) -> tuple:
    return (analytic.dumbbell_strength(m1, m2, l1, l2, mu0), l1, l2)


MODELS: tuple[Model, ...] = (
    Model(
        "dipole",
        "Two point dipoles: U = mu0 m1 m2 (c3 - 3 c1 c2)/(4 pi r^3). Far-field model of any "
        "magnet; force error vs a cylinder ~ C (l^2 - 3a^2/4)/r^2 (docs/magnets.md).",
        (*_moments(), MU0_PARAM),
        analytic.dipole_core,
        lambda p: (p["moment1"], p["moment2"], p["mu0"]),
        lambda p: analytic.dipole_expr(p["moment1"], p["moment2"], p["mu0"]),
        analytic.dipole_core_k,
        lambda p: (analytic.dipole_strength(p["moment1"], p["moment2"], p["mu0"]),),
    ),
    Model(
        "dumbbell",
        "Two magnetic dumbbells, seed 000 eq. (16): charges +-mu/(2l) at +-l nu (l = half-length). "
        "For a cylinder use l = h/2; force error ~ (3/4) C a^2/r^2.",
        (*_moments(),
         _p("half_length1", "pole distance from the centre of body 1 [m]", "m", positive=True),
         _p("half_length2", "pole distance from the centre of body 2 [m]", "m", positive=True),
         MU0_PARAM),
        analytic.dumbbell_core,
        lambda p: (p["moment1"], p["moment2"], p["half_length1"], p["half_length2"], p["mu0"]),
        lambda p: analytic.dumbbell_expr(p["moment1"], p["moment2"], p["half_length1"],
                                         p["half_length2"], p["mu0"]),
        analytic.dumbbell_core_k,
        lambda p: _dumbbell_fold(p["moment1"], p["moment2"], p["half_length1"],
                                 p["half_length2"], p["mu0"]),
    ),
    Model(
        "dumbbell_octupole",
        "Octupole-corrected dumbbell of a cylinder: poles at +-l_eff, l_eff = sqrt(l^2 - 3a^2/4) "
        "(l = length/2), matching the cylinder's dipole and octupole moments. Needs "
        "length > sqrt(3) radius. Force error ~ (9..14) a^2 l^2/r^4.",
        (*_moments(), *_sizes(1), *_sizes(2), MU0_PARAM),
        analytic.dumbbell_core,
        _octupole_args,
        lambda p: analytic.dumbbell_expr(*_octupole_args(p)),
        analytic.dumbbell_core_k,
        lambda p: _dumbbell_fold(*_octupole_args(p)),
    ),
    Model(
        "cylinder",
        "Exact uniformly, axially magnetised cylinders (charged end disks; 3-D quadrature with "
        "analytic gradients). Accurate to ~1e-10 while end-disk gaps exceed ~half a radius.",
        (_p("magnetization1", "magnetisation of cylinder 1 along its axis [A/m]", "A/m"),
         _p("magnetization2", "magnetisation of cylinder 2 along its axis [A/m]", "A/m"),
         *_sizes(1), *_sizes(2), MU0_PARAM,
         _p("n_radial", "Gauss-Legendre nodes radially and per ring integral", "",
            positive=True, default=cylinder.N_RADIAL, type_="int"),
         _p("n_angular", "trapezoid nodes in angle on the disks of body 1", "",
            positive=True, default=cylinder.N_ANGULAR, type_="int")),
        cylinder.cylinder_core,
        lambda p: (p["magnetization1"], p["magnetization2"], p["radius1"], p["radius2"],
                   0.5 * p["length1"], 0.5 * p["length2"], p["mu0"], p["n_radial"],
                   p["n_angular"]),
    ),
    Model(
        "dipole_cylinder_field",
        "Seed 000 eq. (17): point dipole (body 2) in the field of a uniformly magnetised "
        "cylinder (body 1), U = mu0 mu2 nu2.grad psi1; psi1 by ring decomposition near, "
        "axial multipoles (n <= 41) beyond 3 sqrt(l^2+a^2).",
        (_p("magnetization1", "magnetisation of cylinder 1 [A/m]", "A/m"), *_sizes(1),
         _p("moment2", "magnetic moment of the dipole [A m^2]", "A m^2"), MU0_PARAM,
         _p("n_ring", "Gauss-Legendre nodes of the ring integrals", "", positive=True,
            default=fields.N_RING, type_="int")),
        fields.dipole_cylinder_core,
        lambda p: (p["magnetization1"], p["radius1"], 0.5 * p["length1"], p["moment2"],
                   p["mu0"], p["n_ring"]),
    ),
    Model(
        "dumbbell_cylinder_field",
        "Seed 000 eq. (18) (with the factor eps): dumbbell (body 2; poles +-mu/(2l) at +-l nu2) "
        "in the field of a uniformly magnetised cylinder (body 1), U = mu0 kappa sum eps psi1.",
        (_p("magnetization1", "magnetisation of cylinder 1 [A/m]", "A/m"), *_sizes(1),
         _p("moment2", "magnetic moment of the dumbbell [A m^2]", "A m^2"),
         _p("half_length2", "pole distance from the centre of the dumbbell [m]", "m",
            positive=True),
         MU0_PARAM,
         _p("n_ring", "Gauss-Legendre nodes of the ring integrals", "", positive=True,
            default=fields.N_RING, type_="int")),
        fields.dumbbell_cylinder_core,
        lambda p: (p["magnetization1"], p["radius1"], 0.5 * p["length1"], p["moment2"],
                   p["half_length2"], p["mu0"], p["n_ring"]),
    ),
    Model(
        "dipole_loop",
        "Point dipole (body 2) in the field of a circular current loop (body 1; current "
        "right-handed about nu1): U = -m.B_loop, Biot-Savart with the trapezoid rule.",
        (_p("current1", "loop current [A]", "A"),
         _p("radius1", "loop radius [m]", "m", positive=True),
         _p("moment2", "magnetic moment of the dipole [A m^2]", "A m^2"), MU0_PARAM,
         _p("n_nodes", "trapezoid nodes along the loop", "", positive=True,
            default=loops.N_LOOP, type_="int")),
        loops.loop_dipole_core,
        lambda p: (p["current1"], p["radius1"], p["moment2"], p["mu0"], p["n_nodes"]),
    ),
    Model(
        "loops",
        "Two thin circular loops at constant currents: U = -I1 I2 M, M by the Neumann double "
        "line integral (coaxial case checked against Maxwell's formula).",
        (_p("current1", "current of loop 1 [A]", "A"), _p("current2", "current of loop 2 [A]", "A"),
         _p("radius1", "radius of loop 1 [m]", "m", positive=True),
         _p("radius2", "radius of loop 2 [m]", "m", positive=True), MU0_PARAM,
         _p("n_nodes", "trapezoid nodes along each loop", "", positive=True,
            default=loops.N_LOOP, type_="int")),
        loops.loops_core,
        lambda p: (p["current1"], p["current2"], p["radius1"], p["radius2"], p["mu0"],
                   p["n_nodes"]),
    ),
    Model(
        "superconducting_rings",
        "Two thin superconducting rings keeping their fluxes: U = Phi^T L^-1 Phi/2 - (value at "
        "infinity), L = [[L1, M], [M, L2]], L_i = mu0 a_i (ln(8 a_i/b_i) - 2); currents follow "
        "the configuration (I = L^-1 Phi).",
        (_p("flux1", "trapped flux of ring 1 [Wb]", "Wb"), _p("flux2", "trapped flux of ring 2 [Wb]", "Wb"),
         _p("radius1", "radius of ring 1 [m]", "m", positive=True),
         _p("radius2", "radius of ring 2 [m]", "m", positive=True),
         _p("wire_radius1", "wire radius of ring 1 [m]", "m", positive=True),
         _p("wire_radius2", "wire radius of ring 2 [m]", "m", positive=True), MU0_PARAM,
         _p("n_nodes", "trapezoid nodes along each ring", "", positive=True,
            default=loops.N_LOOP, type_="int")),
        loops.superconducting_core,
        lambda p: (p["flux1"], p["flux2"], p["radius1"], p["radius2"],
                   *_self_inductances(p), p["mu0"], p["n_nodes"]),
    ),
)

BY_NAME: dict[str, Model] = {m.name: m for m in MODELS}

_kernels: dict[tuple, Callable[..., Any]] = {}
_lock = threading.Lock()


def _bind(core: Callable[..., Any], args: tuple) -> Callable[..., Any]:
    # The arguments are scalars, so numba freezes them as constants and reuses the cached
    # compiled core (arrays would be frozen read-only and force a recompilation of the core).
    @jit(error_model="python")
    def kernel(r, c1, c2, c3):
        return core(r, c1, c2, c3, *args)

    return kernel


def kernel(name: str, params: Mapping[str, Any]) -> Callable[..., Any]:
    """Compiled ``f(r, c1, c2, c3) -> (U, U_r, U_c1, U_c2, U_c3)`` for resolved params."""
    model = BY_NAME[name]
    args = tuple(float(a) if isinstance(a, float) else a for a in model.args(params))
    key = (name, args)
    with _lock:
        hit = _kernels.get(key)
    if hit is None:
        hit = _bind(model.core, args)
        with _lock:
            _kernels[key] = hit
    return hit


def _layout(args: tuple) -> tuple[object, ...]:
    """Which core arguments are run-time floats (``None``) and which integers stay constants
    (node counts shape the quadrature loops)."""
    return tuple(a if isinstance(a, (int, np.integer)) and not isinstance(a, bool) else None
                 for a in args)


def param_kernel(name: str, params: Mapping[str, Any]) -> Callable[..., Any]:
    """Compiled ``f(r, c1, c2, c3, P) -> (U, U_r, U_c1, U_c2, U_c3)`` reading the float
    arguments of the core from ``P`` (:func:`param_values`); one function per model and
    integer settings, whatever the float values."""
    model = BY_NAME[name]
    core = model.core if model.folded is None else model.folded
    layout = _layout(model.args(params) if model.fold is None else model.fold(params))
    key = ("P", name, layout)
    with _lock:
        hit = _kernels.get(key)
    if hit is None:
        parts, k = [], 0
        for a in layout:
            if a is None:
                parts.append(f"P[{k}]")
                k += 1
            else:
                parts.append(repr(int(a)))
        source = (f"def kernel_{name}(r, c1, c2, c3, P):\n"
                  f"    return core(r, c1, c2, c3, {', '.join(parts)})")
        hit = compile_generated(source, f"kernel_{name}", {"core": core},
                                error_model="python")
        with _lock:
            _kernels[key] = hit
    return hit


def param_values(name: str, params: Mapping[str, Any]) -> tuple[float, ...]:
    """The float arguments of model ``name``'s core (its folded core where it has one) for
    resolved ``params``: the tuple ``P`` of :func:`param_kernel`, derived quantities included
    (e.g. effective half-lengths)."""
    model = BY_NAME[name]
    args = model.args(params) if model.fold is None else model.fold(params)
    return tuple(float(a) for a, slot in zip(args, _layout(args)) if slot is None)


def evaluate(name: str, params: Mapping[str, Any], r: float, c1: float, c2: float, c3: float
             ) -> tuple[float, float, float, float, float]:
    """``(U, U_r, U_c1, U_c2, U_c3)`` of model ``name`` (resolved params), without binding."""
    model = BY_NAME[name]
    out = model.core(float(r), float(c1), float(c2), float(c3), *model.args(params))
    return tuple(float(v) for v in out)  # type: ignore[return-value]


def evaluator(name: str, params: Mapping[str, Any]
              ) -> Callable[[float, float, float, float], tuple[float, float, float, float, float]]:
    """``f(r, c1, c2, c3)`` evaluating model ``name`` directly (:func:`evaluate`), for the
    registry entry's ``evaluate`` (``pair_interaction``)."""
    return partial(evaluate, name, params)


def moment_of_cylinder(magnetization: float, radius: float, length: float) -> float:
    """``mu = M pi a^2 h`` (A m^2)."""
    return magnetization * math.pi * radius ** 2 * length
