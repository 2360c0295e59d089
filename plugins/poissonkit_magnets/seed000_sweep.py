"""The seed 000 orbit as a sweep scene: its named parameters and one run's fate.

Registered as the ``sweep`` factory of the ``seed000`` scene entry (:mod:`.plugin`), so
``poissonkit sweep seed000 --param spin_ratio=0:30:16`` works while the core's sweep layer
(:mod:`poissonkit.sweeps`) knows nothing of this scene.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from poissonkit.errors import InputError, UnknownNameError
from poissonkit.sweeps.targets import RunRecord, cut_solution as _cut, record_units as _units

#: Named parameters of the seed scene: units and meaning (``initial.<name>`` is an alias).
SEED_PARAMETERS: Mapping[str, tuple[str, str]] = {
    "spin_ratio": ("1", "alpha |m| / omega_orb of each magnet"),
    "tilt": ("rad", "tilt of both axes towards the line of centres"),
    "radius_factor": ("1", "initial distance / R_orb"),
    "momentum_factor": ("1", "initial momentum / P_orb"),
    "orbit_radius": ("1", "radius of the circular orbit / magnet length h (seed: 0.5)"),
}
SEED_DEFAULTS: Mapping[str, float] = {"spin_ratio": 20.0, "tilt": 0.0, "radius_factor": 1.0,
                                      "momentum_factor": 1.0, "orbit_radius": 0.5}


@dataclass(frozen=True)
class SeedScene:
    """The seed 000 orbit (two cylinder magnets, dumbbell model, 18-variable two-body form).

    Parameters
    ----------
    periods
        Duration of each run in orbital periods.
    method, step
        Integrator and fixed step (internal time; the orbital period is ``2 pi``).
    escape
        Escape distance in orbit radii.
    fixed
        Values of named parameters that are not swept (defaults: :data:`SEED_DEFAULTS`).
    """

    periods: float = 20.0
    method: str = "splitting8"
    step: float = 2 * math.pi / 400
    escape: float = 3.0
    fixed: Mapping[str, float] = field(default_factory=dict)

    name = "seed000"

    def __post_init__(self) -> None:
        for k, v in (("periods", self.periods), ("step", self.step), ("escape", self.escape)):
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise InputError(f"seed000 sweep: {k} must be a positive number, got {v!r}")
        if self.escape <= 1:
            raise InputError(f"seed000 sweep: escape must exceed 1 orbit radius, got {self.escape}")
        for k in self.fixed:
            self.check(k)

    @property
    def key(self) -> str:
        """Identifies what :meth:`prepare` builds (the worker cache key)."""
        return "seed000"

    def settings(self) -> dict[str, Any]:
        """Attributes recorded in the dataset."""
        return {"scene": "seed000", "method": self.method, "step": self.step,
                "step_units": "internal time (orbital period = 2 pi)",
                "duration_periods": self.periods, "escape_orbit_radii": self.escape}

    def check(self, path: str) -> str:
        """The named parameter ``path`` refers to (``initial.`` stripped); units via
        :meth:`units`. Raises :class:`UnknownNameError` listing the parameters."""
        name = path[len("initial."):] if path.startswith("initial.") else path
        if name not in SEED_PARAMETERS:
            raise UnknownNameError("seed000 sweep parameter", path, SEED_PARAMETERS)
        return name

    def units(self, path: str) -> str:
        """Units of a parameter's values."""
        return SEED_PARAMETERS[self.check(path)][0]

    def prepare(self) -> dict[str, Any]:
        """Parameter table, orbit, system (kernels compiled by a short warm-up run)."""
        from poissonkit_magnets import seed000

        from poissonkit.numerics.solver import solve

        t = seed000.parameter_table()
        o = seed000.circular_orbit(table=t)
        system = seed000.seed_system(t, o)
        y0 = seed000.initial_state(orbit=o, table=t)
        solve(system, y0, 4 * self.step, method=self.method, step=self.step)  # compile now
        return {"table": t, "orbit": o, "system": system, "scales": seed000.scales(o, t),
                "contact": float(2 * t.a / o.radius), "half_length": float(t.l / o.radius)}

    def run(self, prep: Mapping[str, Any], values: Mapping[str, float]) -> RunRecord:
        """Integrate one point (``values`` by parameter path) and classify its fate."""
        from poissonkit_magnets import seed000

        from poissonkit.numerics.events import Escape
        from poissonkit.numerics.solver import solve

        kw = dict(SEED_DEFAULTS)
        kw.update({self.check(k): float(v) for k, v in self.fixed.items()})
        kw.update({self.check(k): float(v) for k, v in values.items()})
        system = prep["system"]
        y0, ratio = _seed_state(prep, kw)
        # durations, steps and the escape radius follow the orbit's own period and radius;
        # the state is in the units of the seed orbit (R_orb = 10 mm), where the kernels live
        t_end = 2 * math.pi * self.periods * ratio["time"]
        step = self.step * ratio["time"]
        # the two-body escape test measures a body's distance from the centre of mass (r/2)
        sol = solve(system, y0, t_end, method=self.method, step=step,
                    events=(Escape(self.escape * ratio["length"] / 2),))
        fate = sol.events[0].kind if sol.events else "bounded"
        fate_t = sol.events[0].time if sol.events else math.nan
        y = np.asarray(sol.y)
        ok = np.all(np.isfinite(y), axis=1)
        touch = seed000.axis_distance(np.where(ok[:, None], y, 0.0), prep["half_length"])
        hit = np.nonzero(~ok | (touch < prep["contact"]))[0]
        if hit.size:
            fate = "collision"
            k = int(hit[0])
            fate_t = float(sol.t[k])
            sol = _cut(sol, max(k + 1 if ok[k] else k, 1))  # keep the first contact state
        tu, eu, ju = _units(prep["scales"])
        dist = np.linalg.norm(np.asarray(sol.y)[:, :3], axis=1) * prep["scales"].length
        return RunRecord(sol, fate, fate_t * tu if math.isfinite(fate_t) else math.nan, dist,
                         tu, eu, ju, (system, y0, float(sol.t[-1]), self.method, step))


def _seed_state(prep: dict[str, Any], kw: Mapping[str, float]
                ) -> tuple[np.ndarray, dict[str, float]]:
    """Initial state of a seed point in the units of the seed orbit, and the ratios of the
    point's orbit units (length, time) to those units.

    ``orbit_radius`` other than the seed's picks the circular orbit of that radius
    (:func:`poissonkit_magnets.seed000.circular_orbit`, cached per worker); its state, built in
    its own units by :func:`~poissonkit_magnets.seed000.initial_state`, is converted to the seed
    orbit's units so that one compiled system serves every radius.
    """
    from poissonkit_magnets import seed000

    t = prep["table"]
    radius = float(kw["orbit_radius"])
    if not (math.isfinite(radius) and radius > 0):
        raise InputError(f"seed000: orbit_radius must be > 0, got {radius!r}")
    state_kw = {k: kw[k] for k in ("spin_ratio", "tilt", "radius_factor", "momentum_factor")}
    orbits = prep.setdefault("orbits", {})
    if radius not in orbits:
        orbits[radius] = seed000.circular_orbit(radius * float(t.h), table=t)
    o = orbits[radius]
    y = seed000.initial_state(orbit=o, table=t, **state_kw)
    s0, s1 = prep["scales"], seed000.scales(o, t)
    ratio = {"length": s1.length / s0.length, "time": s1.time / s0.time}
    conv = np.ones(18)
    conv[0:3] = ratio["length"]
    conv[3:6] = s1.unit("momentum") / s0.unit("momentum")
    for block in (9, 15):  # spins m', m'' (the axes nu are unit vectors in any units)
        conv[block:block + 3] = s1.unit("angular_momentum") / s0.unit("angular_momentum")
    return y * conv, ratio
