"""The Levitron as a sweep scene: ``poissonkit sweep levitron --param spin_rpm=...``.

Each point builds the top over its base (systems cached per worker by mass, moment and base
polarisation), finds the hovering relative equilibrium at the point's spin, starts from it
displaced by ``offset`` and tilted by ``axis_tilt``, integrates for ``duration`` seconds and
classifies the fate (:func:`poissonkit_magnets.levitron.classify`): ``bounded`` (levitation),
``collision`` (the top flipped or fell onto the base) or ``escape`` (it left the trap). A top
too heavy for the base falls at once (``collision`` at t = 0). The run stops where the top
touches the base (a located contact event). The finer fate — flip told from fall by the axis —
is the outcome ``levitron_fate`` (:data:`LEVITRON_FATE`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from poissonkit.errors import InputError, UnknownNameError
from poissonkit.plugin.contributions import OutcomeEntry
from poissonkit.sweeps.targets import RunRecord, cut_solution, record_units

#: Swept parameters: units and meaning.
LEVITRON_PARAMETERS: Mapping[str, tuple[str, str]] = {
    "spin_rpm": ("rpm", "spin of the top about its axis"),
    "mass": ("kg", "mass of the top"),
    "moment": ("A m^2", "magnetic moment of the top"),
    "polarization": ("T", "polarisation of the base ring"),
    "I1": ("kg m^2", "moment of inertia of the top about a transverse axis"),
    "I3": ("kg m^2", "moment of inertia of the top about its symmetry axis"),
    "inner_radius": ("m", "inner radius of the base ring"),
    "outer_radius": ("m", "outer radius of the base ring"),
    "thickness": ("m", "thickness of the base ring"),
    "g": ("m/s^2", "gravitational acceleration"),
    "offset": ("m", "initial horizontal displacement from the hovering point"),
    "axis_tilt": ("rad", "initial tilt of the axis"),
}
LEVITRON_DEFAULTS: Mapping[str, float] = {"spin_rpm": 1200.0, "mass": 0.022, "moment": 0.60,
                                          "polarization": 0.265, "offset": 5e-4,
                                          "axis_tilt": 0.005, "I1": 1.15e-6, "I3": 2.10e-6,
                                          "inner_radius": 0.008, "outer_radius": 0.040,
                                          "thickness": 0.010, "g": 9.81}
#: Parameters of :class:`~poissonkit_magnets.levitron.LevitronParameters` (the others set the
#: start and the spin).
_PHYSICAL = ("mass", "moment", "polarization", "I1", "I3", "inner_radius", "outer_radius",
             "thickness", "g")

#: How the finer failure modes map onto the sweep's fates.
FATE_OF: Mapping[str, str] = {"bounded": "bounded", "flip": "collision", "fall": "collision",
                              "escape": "escape"}


@dataclass(frozen=True)
class LevitronScene:
    """The Levitron sweep scene.

    Parameters
    ----------
    periods
        Duration of each run [s] (the Levitron has no orbital period; ``--periods`` sets it).
    method, step
        Integrator and fixed step [s].
    escape
        Distance from the hovering point [m] beyond which the top has escaped.
    fixed
        Values of parameters that are not swept (defaults :data:`LEVITRON_DEFAULTS`).
    """

    periods: float = 3.0
    method: str = "splitting4"
    step: float = 2e-4
    escape: float = 0.03
    fixed: Mapping[str, float] = field(default_factory=dict)

    name = "levitron"

    def __post_init__(self) -> None:
        for k in ("periods", "step", "escape"):
            v = getattr(self, k)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise InputError(f"levitron sweep: {k} must be a positive number, got {v!r}")
        for k in self.fixed:
            self.check(k)

    @property
    def key(self) -> str:
        """Identifies what :meth:`prepare` builds."""
        return "levitron"

    def settings(self) -> dict[str, Any]:
        """Attributes recorded in the dataset."""
        return {"scene": "levitron", "method": self.method, "step_s": self.step,
                "duration_s": self.periods, "escape_m": self.escape,
                "fates": "collision = flip or fall onto the base (levitron_fate tells them "
                         "apart)"}

    def check(self, path: str) -> str:
        """The parameter ``path`` names (``initial.`` stripped)."""
        name = path[len("initial."):] if path.startswith("initial.") else path
        if name not in LEVITRON_PARAMETERS:
            raise UnknownNameError("levitron sweep parameter", path, LEVITRON_PARAMETERS)
        return name

    def units(self, path: str) -> str:
        """Units of a parameter's values."""
        return LEVITRON_PARAMETERS[self.check(path)][0]

    def prepare(self) -> dict[str, Any]:
        """A per-worker cache of systems (kernels compile on the first one)."""
        return {"systems": {}}

    def values(self, values: Mapping[str, float]) -> dict[str, float]:
        """Every parameter of a point: defaults, then ``fixed``, then ``values``."""
        kw = dict(LEVITRON_DEFAULTS)
        kw.update({self.check(k): float(v) for k, v in self.fixed.items()})
        kw.update({self.check(k): float(v) for k, v in values.items()})
        return kw

    def run(self, prep: Mapping[str, Any], values: Mapping[str, float]) -> RunRecord:
        """Integrate one point and classify its fate."""
        from poissonkit.numerics.solver import solve
        from poissonkit_magnets import levitron as lev

        kw = self.values(values)
        p = lev.LevitronParameters().with_values(**{k: kw[k] for k in _PHYSICAL})
        systems = prep["systems"]
        key = p
        if key not in systems:
            systems[key] = lev.levitron_system(p)
        system = systems[key]
        T = system.scales.time
        try:
            eq = lev.hovering_state(system, p, kw["spin_rpm"])
        except InputError:  # no height where the base holds this top: it falls
            y0 = system.pack([[0.0, 0.0, 0.003]], [[0.0, 0.0, 0.0]], [[0.0, 0.0, -1.0]],
                             [[0.0, 0.0, 0.0]], si=True)
            sol = solve(system, y0, self.step / T, method=self.method, step=self.step / T)
            tu, eu, ju = record_units(system.scales)
            return RunRecord(sol, "collision", 0.0, np.full(len(sol.t), 0.003), tu, eu, ju,
                             (system, y0, float(sol.t[-1]), self.method, self.step / T))
        y0 = lev.perturbed(system, eq, kw["offset"], kw["axis_tilt"])
        z0 = float(system.unpack(eq, si=True)["r"][0, 2])
        sol = solve(system, y0, self.periods / T, method=self.method, step=self.step / T,
                    save_every=10, events=(lev.base_contact(p, system),))
        ys = np.asarray(sol.y)
        touched = any(e.kind == "contact" for e in sol.events)
        mode, k = lev.classify(system, ys, z0, self.escape, touched)
        fate_t = math.nan
        if k >= 0:
            fate_t = float(sol.t[k]) * T
            sol = cut_solution(sol, max(k + 1, 1))
        height = system.unpack(np.asarray(sol.y), si=True)["r"][:, 0, 2]
        tu, eu, ju = record_units(system.scales)
        return RunRecord(sol, FATE_OF[mode], fate_t, height, tu, eu, ju,
                         (system, y0, float(sol.t[-1]), self.method, self.step / T))


def _fine_fate(rec: RunRecord) -> int:
    """0 bounded, 1 flip, 2 fall, 3 escape: a collision is a flip if the axis turned up
    (``ν_z > 0``) at any saved state up to it, else a fall."""
    if rec.fate != "collision":
        return {"bounded": 0, "escape": 3}.get(rec.fate, -1)
    system = rec.solution.system
    ys = np.asarray(rec.solution.y)
    nu = system.unpack(ys, si=True)["nu"][:, 0, :]  # type: ignore[union-attr]
    return 1 if np.any(nu[:, 2] > 0.0) else 2


def levitron_fate_outcome() -> OutcomeEntry:
    """The sweep outcome ``levitron_fate``: the Levitron's fate told finely."""
    return OutcomeEntry(name="levitron_fate", dtype="i1", unit="1", fill=-1,
                        doc="Levitron fate: 0 bounded, 1 flip (axis turned up), 2 fall onto "
                            "the base (axis down), 3 escape (-1 not computed)",
                        compute=_fine_fate)
