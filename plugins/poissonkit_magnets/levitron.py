"""The Levitron: a magnetised symmetric top hovering above a ring magnet, in gravity.

The top (mass ``M``, moments of inertia ``I₁ = I₂``, ``I₃``, magnetic moment ``μ`` along its
axis ``ν``) is one body of an :class:`~poissonkit.NBodySystem` with state ``(r, p, ν, m)``;
the base is an axially magnetised ring (polarisation ``J``, radii ``a < R``, thickness ``t``,
top face at ``z = 0``), the exact field of two coaxial cylinders (``+J`` of radius ``R``,
``−J`` of radius ``a``; :mod:`poissonkit_magnets.exact_fields`) or magpylib's
``CylinderSegment`` tabulated by the ``magpylib`` field; gravity is the built-in field. The
top's moment points down, against the base's field, so the base repels it.

Default parameters (:class:`LevitronParameters`) are close to the top of Simon, Heflinger &
Ridgway (Am. J. Phys. 65, 286 (1997)): a 22 g top hovering about 3.2 cm above its base
(docs/levitron.md compares the windows).

The hovering state is a relative equilibrium (an equilibrium of the reduced system: the spin
about the axis is the Casimir ``ν·m = I₃ω₃``) found by :func:`poissonkit.relative_equilibrium`;
its linear stability against the spin rate is :func:`stability_window`.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np

from poissonkit.errors import InputError

if TYPE_CHECKING:
    from poissonkit.numerics.equilibria import LinearStability
    from poissonkit.numerics.events import Contact, EventRecord
    from poissonkit.numerics.fields.base import FieldSpec
    from poissonkit.numerics.nbody import NBodySystem
    from poissonkit.numerics.runspec import RunSpec

#: rpm → rad/s.
RPM = 2.0 * math.pi / 60.0


@dataclass(frozen=True)
class LevitronParameters:
    """A Levitron in SI units (defaults: a 22 g ferrite top over a ferrite ring).

    Attributes
    ----------
    mass
        Mass of the top [kg].
    moment
        Magnetic moment of the top along its axis [A m²].
    I1, I3
        Moments of inertia about a transverse axis and about the symmetry axis [kg m²].
    polarization
        Polarisation ``J = μ₀M`` of the base along ``+z`` [T].
    inner_radius, outer_radius, thickness
        The base ring [m]; its top face is the plane ``z = 0``.
    g
        Gravitational acceleration [m/s²].
    top_radius
        Radius [m] of the ball that stands for the top in contact with the base (its lowest
        point when hovering upright).
    field
        ``"exact"`` (two exact cylinder fields) or ``"magpylib"`` (a tabulated magpylib
        ``CylinderSegment``, tricubic Hermite).
    """

    mass: float = 0.0220
    moment: float = 0.60
    I1: float = 1.15e-6
    I3: float = 2.10e-6
    polarization: float = 0.265
    inner_radius: float = 0.008
    outer_radius: float = 0.040
    thickness: float = 0.010
    g: float = 9.81
    top_radius: float = 0.003
    field: str = "exact"

    def __post_init__(self) -> None:
        for name in ("mass", "moment", "I1", "I3", "polarization", "inner_radius",
                     "outer_radius", "thickness", "g", "top_radius"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not (
                    math.isfinite(v) and v > 0):
                raise InputError(f"levitron: {name} must be a positive number, got {v!r}")
            object.__setattr__(self, name, float(v))
        if not self.inner_radius < self.outer_radius:
            raise InputError("levitron: inner_radius must be smaller than outer_radius")
        if self.field not in ("exact", "magpylib"):
            raise InputError(f"levitron: field must be 'exact' or 'magpylib', got {self.field!r}")

    def with_values(self, **values: float | str) -> LevitronParameters:
        """A copy with some values changed (``spin_rpm`` is not a parameter of the top)."""
        unknown = set(values) - set(asdict(self))
        if unknown:
            raise InputError(f"levitron: unknown parameters {sorted(unknown)}; known: "
                             f"{sorted(asdict(self))}")
        return replace(self, **values)


def base_fields(p: LevitronParameters, region: tuple[float, ...] | None = None
                ) -> list[FieldSpec]:
    """The base's field specs (``pk.field``), and gravity."""
    from poissonkit.numerics.fields.base import field

    centre = (0.0, 0.0, -p.thickness / 2)
    grav = field("gravity", g=(0.0, 0.0, -p.g))
    if p.field == "exact":
        return [field("cylinder", polarization=p.polarization, radius=p.outer_radius,
                      length=p.thickness, position=centre),
                field("cylinder", polarization=-p.polarization, radius=p.inner_radius,
                      length=p.thickness, position=centre),
                grav]
    box = region or (-0.008, -0.008, 0.02, 0.008, 0.008, 0.05)
    return [field("magpylib", **{"class": "CylinderSegment", "params": {
                  "polarization": [0.0, 0.0, p.polarization],
                  "dimension": [p.inner_radius, p.outer_radius, p.thickness, 0.0, 360.0]},
                  "position": list(centre), "region": list(box), "tol": 1e-4}),
            grav]


@functools.lru_cache(maxsize=16)
def levitron_system(p: LevitronParameters) -> NBodySystem:
    """The top over the base as an :class:`~poissonkit.NBodySystem` (internal units: 1 cm,
    20 g, 10 ms, the same for every top so that systems share their compiled kernels)."""
    from poissonkit.numerics.nbody import Body, NBodySystem
    from poissonkit.numerics.units import Scales

    top = Body("top", mass=p.mass, alpha=1.0 / p.I1, attributes={"moment": p.moment})
    # the base as a fixed body: no force on it or from it (fixed bodies read no field), only
    # a place for contact events; the top's state and kernels are those of the top alone
    base = Body("base", mass=1.0, fixed=True, position=(0.0, 0.0, -p.thickness / 2),
                axis=(0.0, 0.0, 1.0))
    return NBodySystem([top, base], scales=Scales(length=0.01, mass=0.02, time=0.01),
                       fields=base_fields(p))


def base_contact(p: LevitronParameters, system: NBodySystem) -> Contact:
    """The contact event of the top (a ball of ``top_radius``) with the base (a solid
    cylinder of the ring's outer radius and thickness: the ring with its lid), in the
    system's internal length unit."""
    from poissonkit.numerics.events import BodyShape, Contact

    L = system.scales.length
    return Contact((BodyShape("top", p.top_radius / L),
                    BodyShape("base", p.outer_radius / L, p.thickness / 2 / L,
                              axis=(0.0, 0.0, 1.0))))


def _axis_height_guess(system: NBodySystem, p: LevitronParameters) -> float:
    """Height [m] of the vertically stable balance on the axis (moment down): the minimum of
    the on-axis energy above the field's maximum, from a scan of the system's own energy."""
    zs = np.linspace(0.005, 0.12, 2000)
    nu = np.array([[0.0, 0.0, -1.0]])
    states = np.array([system.pack([[0.0, 0.0, z]], [[0.0, 0.0, 0.0]], nu, [[0.0, 0.0, 0.0]],
                                   si=True) for z in zs])
    e = np.asarray(system.energy(states))
    inner = np.nonzero((e[1:-1] < e[:-2]) & (e[1:-1] < e[2:]))[0]
    if inner.size == 0:
        raise InputError("levitron: no height where the base holds the top up (too heavy, or "
                         "too weak a base or moment)")
    return float(zs[inner[-1] + 1])


def hovering_state(system: NBodySystem, p: LevitronParameters, spin_rpm: float) -> np.ndarray:
    """The hovering relative equilibrium (internal units): on the axis, ``ν = −e_z``,
    ``m = I₃ω₃ ν``, at the height where the lift balances the weight."""
    from poissonkit.numerics.equilibria import relative_equilibrium

    z = _axis_height_guess(system, p)
    L = p.I3 * spin_rpm * RPM
    nu = np.array([[0.0, 0.0, -1.0]])
    guess = system.pack([[0.0, 0.0, z]], [[0.0, 0.0, 0.0]], nu, L * nu, si=True)
    eq = relative_equilibrium(system, guess)
    return eq.state


def perturbed(system: NBodySystem, y: np.ndarray, offset: float, tilt: float) -> np.ndarray:
    """``y`` displaced by ``offset`` [m] along ``x`` and tilted by ``tilt`` [rad] about ``y``
    (the spin ``ν·m`` and ``|ν| = 1`` kept)."""
    parts = system.unpack(y, si=True)
    r = parts["r"][0] + np.array([offset, 0.0, 0.0])
    c, s = math.cos(tilt), math.sin(tilt)
    rot = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
    nu = rot @ parts["nu"][0]
    m = rot @ parts["m"][0]
    return system.pack([r], parts["p"], [nu], [m], si=True)


def classify(system: NBodySystem, ys: np.ndarray, z0: float, escape: float = 0.03,
             touched: bool = False) -> tuple[str, int]:
    """Fate of a trajectory (rows of internal states) and the first failing row (-1: none).

    ``"bounded"``: it stayed hovering; ``"flip"``: the axis turned up (``ν_z > 0``: the
    moment along the base's field, the top is then attracted) — told from a fall by the axis
    alone, whatever happens next; ``"fall"``: it came down onto the base with its axis still
    pointing down (``touched``: the run stopped at the contact event with the base, its last
    row; otherwise ``z < top_radius``-like 3 mm, or a non-finite state); ``"escape"``: it left
    the trap (farther than ``escape`` [m] from the hovering point).
    """
    parts = system.unpack(ys, si=True)
    r, nu = parts["r"][:, 0, :], parts["nu"][:, 0, :]
    bad = ~np.all(np.isfinite(ys), axis=1)
    with np.errstate(invalid="ignore"):  # a non-finite state counts as a fall
        flip = nu[:, 2] > 0.0
        fall = (r[:, 2] < 0.003) | bad
        away = np.linalg.norm(r - np.array([0.0, 0.0, z0]), axis=1) > escape
    if touched:
        fall[-1] = True
    first = {k: (int(np.argmax(m)) if m.any() else len(ys)) for k, m in
             (("flip", flip), ("fall", fall), ("escape", away))}
    kind = min(first, key=lambda k: first[k])
    if first[kind] == len(ys):
        return "bounded", -1
    return kind, first[kind]


def run_outcome(system: NBodySystem, t: np.ndarray, ys: np.ndarray, z0: float,
                touched: bool, time_unit: float, escape: float = 0.03) -> dict[str, Any]:
    """The reported outcome of a Levitron run: its fate (:func:`classify`), when [s], the
    tilt of the axis from the downward vertical there [°], and one line saying so
    (``"top touched the base at t = … s, tilt …°"`` when it ended on the base)."""
    kind, k = classify(system, ys, z0, escape, touched)
    row = len(ys) - 1 if k < 0 else k
    nu = system.unpack(ys[row:row + 1], si=True)["nu"][0, 0]
    tilt = float(np.degrees(np.arccos(np.clip(-nu[2], -1.0, 1.0))))
    when = float(t[row]) * time_unit
    out: dict[str, Any] = {"fate": kind, "fate_time_s": None if k < 0 else when,
                           "tilt_deg": tilt}
    if touched:
        nu_end = system.unpack(ys[-1:], si=True)["nu"][0, 0]
        tilt_end = float(np.degrees(np.arccos(np.clip(-nu_end[2], -1.0, 1.0))))
        out["contact"] = (f"top touched the base at t = {float(t[-1]) * time_unit:.6g} s, "
                          f"tilt {tilt_end:.3g}°")
    out["message"] = {"bounded": "the top kept hovering",
                      "flip": f"the top flipped (axis past horizontal) at t = {when:.6g} s",
                      "fall": f"the top fell onto the base at t = {when:.6g} s, tilt "
                              f"{tilt:.3g}°",
                      "escape": f"the top left the trap at t = {when:.6g} s"}[kind]
    return out


def spec_outcome(spec: RunSpec, t: np.ndarray, ys: np.ndarray, events: Sequence[EventRecord]
                 ) -> dict[str, Any]:
    """:func:`run_outcome` of a finished run of the ``levitron`` scene (its
    :class:`~poissonkit.plugin.SceneEntry` ``outcome``)."""
    system = spec.system
    z0 = float(spec.metadata["hover_height_m"])
    touched = any(e.kind == "contact" for e in events)
    return run_outcome(system, np.asarray(t), np.asarray(ys), z0, touched,  # type: ignore[arg-type]
                       float(system.scales.time))  # type: ignore[union-attr]


#: Parameters of the top and the base a scene run may set (``--param NAME=VALUE``), SI.
PHYSICAL = ("mass", "moment", "I1", "I3", "polarization", "inner_radius", "outer_radius",
            "thickness", "g", "top_radius")


def scene_run(*, spin_rpm: float = 1200.0, offset: float = 5e-4, axis_tilt: float = 0.005,
              duration: float = 2.0, step: float = 2e-4, method: str = "splitting4",
              tol: float | None = None, field: str = "exact", contact: str = "stop",
              **physical: float) -> RunSpec:
    """The registered ``levitron`` scene as a :class:`~poissonkit.numerics.runspec.RunSpec`.

    Parameters
    ----------
    spin_rpm
        Spin of the top about its axis [rpm].
    offset, axis_tilt
        Initial horizontal displacement [m] and tilt [rad] from the hovering equilibrium.
    duration, step
        Duration and fixed step [s].
    method, tol
        Integrator and tolerance of adaptive methods.
    field
        ``"exact"`` or ``"magpylib"`` (see :class:`LevitronParameters`).
    contact
        ``"stop"``: the run stops when the top touches the base (:func:`base_contact`);
        ``"ignore"``: no contact event (the top may pass through the base).
    **physical
        Any of :data:`PHYSICAL` (:class:`LevitronParameters`; the others at their defaults).

    Raises
    ------
    InputError
        For an unknown parameter, a value out of range, or a top the base cannot hold up.
    """
    from poissonkit.numerics.runspec import RunSpec

    unknown = sorted(set(physical) - set(PHYSICAL))
    if unknown:
        raise InputError(f"levitron: unknown parameters {unknown}; known: {list(PHYSICAL)}")
    if contact not in ("stop", "ignore"):
        raise InputError(f"levitron: contact must be 'stop' or 'ignore', got {contact!r}")
    p = LevitronParameters().with_values(field=field, **physical)
    system = levitron_system(p)
    eq = hovering_state(system, p, spin_rpm)
    y0 = perturbed(system, eq, offset, axis_tilt)
    T = system.scales.time
    z0 = float(system.unpack(eq, si=True)["r"][0, 2])
    meta: Mapping[str, Any] = {**asdict(p), "spin_rpm": spin_rpm, "hover_height_m": z0,
                               "offset_m": offset, "axis_tilt_rad": axis_tilt,
                               "system": "NBodySystem: one top, ring base field + gravity",
                               "solids": [s.describe() for f in system.fields
                                          for s in f.solids]}
    events = () if contact == "ignore" else (base_contact(p, system),)
    return RunSpec(name="levitron", system=system, y0=y0, t_end=duration / T, method=method,
                   step=None if tol is not None else step / T, tol=tol, metadata=meta,
                   events=events)


def hover_stability(p: LevitronParameters, spin_rpm: float, base: np.ndarray | None = None
                    ) -> LinearStability:
    """:func:`poissonkit.linear_stability` of the hovering top at ``spin_rpm`` (``base``: a
    hovering state at another spin to start the equilibrium solve from)."""
    from poissonkit.numerics.equilibria import linear_stability, relative_equilibrium

    system = levitron_system(p)
    if base is None:
        return linear_stability(relative_equilibrium(system, hovering_state(system, p,
                                                                            spin_rpm)))
    y = base.copy()
    L = p.I3 * spin_rpm * RPM / system.scales.unit("angular_momentum")
    y[-3:] = y[-6:-3] * L  # m = I₃ω₃ ν: only the spin changes
    return linear_stability(relative_equilibrium(system, y))


def stability_window(p: LevitronParameters, lo: float = 200.0, hi: float = 20000.0,
                     points: int = 25, resolution: float = 1.0) -> tuple[float, float]:
    """Spin rates [rpm] bounding the linear stability of the hovering top, from
    :func:`poissonkit.linear_stability` of the scene's own system (:func:`hover_stability`,
    bisected to ``resolution`` rpm).

    Raises
    ------
    InputError
        If the base cannot hold the top up, or no spin in ``[lo, hi]`` is stable.
    """
    system = levitron_system(p)
    base = hovering_state(system, p, math.sqrt(lo * hi))

    def stable(rpm: float) -> bool:
        return hover_stability(p, rpm, base).spectrally_stable

    grid = np.geomspace(lo, hi, points)
    ok = np.array([stable(w) for w in grid])
    idx = np.nonzero(ok)[0]
    if idx.size == 0:
        raise InputError("levitron: no linearly stable spin in the range")

    def edge(a: float, b: float) -> float:
        sa = stable(a)
        while b - a > resolution:
            c = 0.5 * (a + b)
            if stable(c) == sa:
                a = c
            else:
                b = c
        return 0.5 * (a + b)

    lower = edge(grid[idx[0] - 1], grid[idx[0]]) if idx[0] > 0 else float(grid[0])
    upper = edge(grid[idx[-1]], grid[idx[-1] + 1]) if idx[-1] < points - 1 else float(grid[-1])
    return lower, upper
