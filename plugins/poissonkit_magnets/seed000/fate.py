"""How a perturbed seed 000 orbit ends: stays bound, escapes, or the magnets touch."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from poissonkit.errors import IntegrationError
from poissonkit_magnets.seed000.orbit import circular_orbit
from poissonkit_magnets.seed000.runs import default_run
from poissonkit_magnets.seed000.table import parameter_table


@dataclass(frozen=True)
class OrbitFate:
    """How a perturbed seed orbit ends.

    Attributes
    ----------
    kind
        ``"bounded"`` (distance stayed within the escape radius and above contact for the whole
        run), ``"collision"`` or ``"escape"``.
    r_min, r_max
        Smallest and largest centre distance seen, in units of ``R_orb``.
    t_end
        Time reached, in orbital periods (the event time if one fired).
    max_energy_error
        Largest relative energy error of the run (trust the verdict only when it is small).
    """

    kind: str
    r_min: float
    r_max: float
    t_end: float
    max_energy_error: float


def axis_distance(y: np.ndarray, half_length: float) -> np.ndarray:
    """Smallest distance between the two magnets' axis segments, per state (rows).

    Segment 1 is ``[-l ν', +l ν']`` about the origin, segment 2 ``r + [-l ν'', +l ν'']``
    (relative coordinates of the 18-variable form, internal units). Two cylinders of radius
    ``a`` overlap when this distance is below ``2a`` (capsule bound: exact for side-by-side
    contact, slightly early at the rims). Vectorised closest-points of two segments.
    """
    y = np.atleast_2d(np.asarray(y, dtype=float))
    l = float(half_length)
    d1 = 2 * l * y[:, 6:9]
    d2 = 2 * l * y[:, 12:15]
    p1 = -l * y[:, 6:9]
    p2 = y[:, 0:3] - l * y[:, 12:15]
    w = p1 - p2
    a = np.einsum("ij,ij->i", d1, d1)
    e = np.einsum("ij,ij->i", d2, d2)
    b = np.einsum("ij,ij->i", d1, d2)
    c = np.einsum("ij,ij->i", d1, w)
    f = np.einsum("ij,ij->i", d2, w)
    den = a * e - b * b
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(den > 1e-14 * a * e, np.clip((b * f - c * e) / den, 0.0, 1.0), 0.0)
        t = (b * s + f) / e
        t_c = np.clip(t, 0.0, 1.0)
        s = np.where(t != t_c, np.clip((b * t_c - c) / a, 0.0, 1.0), s)
    diff = (p1 + s[:, None] * d1) - (p2 + t_c[:, None] * d2)
    return np.linalg.norm(diff, axis=1)


def orbit_fate(*, spin_ratio: float, tilt: float, periods: float = 20.0,
               radius_factor: float = 1.0, momentum_factor: float = 1.0,
               escape_distance: float = 3.0, method: str = "splitting8",
               step: float = 2 * math.pi / 400) -> OrbitFate:
    """Integrate a perturbed seed orbit and classify it (the seed's stability statement).

    Contact: the magnets' axis segments come closer than ``2a = 2.5 mm`` (see
    :func:`axis_distance`; the dumbbell model's poles would otherwise pass through each other).
    Escape: the centre distance exceeds ``escape_distance * R_orb``. The run is classified on its
    saved states up to the first event; the energy error is that of this part.
    """
    from poissonkit.numerics.events import Escape
    from poissonkit.numerics.solver import solve

    t = parameter_table()
    orbit = circular_orbit(table=t)
    spec = default_run(periods=periods, method=method, step=step, spin_ratio=spin_ratio,
                       tilt=tilt, radius_factor=radius_factor, momentum_factor=momentum_factor)
    contact = float(2 * t.a / orbit.radius)
    l_nd = float(t.l / orbit.radius)
    try:
        # the two-body escape test measures a body's distance from the centre of mass (r/2)
        sol = solve(spec.system, spec.y0, spec.t_end, method=method, step=step,
                    events=(Escape(escape_distance / 2),))
        y, tt = np.asarray(sol.y), np.asarray(sol.t)
        kind = sol.events[0].kind if sol.events else "bounded"
    except IntegrationError as exc:  # blow-up after an unresolved contact
        y, tt, kind = np.asarray(getattr(exc, "y", np.empty((0, 18)))), np.empty(0), "collision"
        if y.size == 0:
            raise
    ok = np.all(np.isfinite(y), axis=1)
    hit = np.nonzero(~ok | (axis_distance(np.where(ok[:, None], y, 0.0), l_nd) < contact))[0]
    if hit.size:
        kind = "collision"
        y, tt = y[: max(hit[0], 1)], tt[: max(hit[0], 1)]
    r = np.linalg.norm(y[:, :3], axis=1)
    H = np.asarray(spec.system.energy(y), dtype=float)
    ee = float(np.max(np.abs(H - H[0])) / abs(H[0]))
    return OrbitFate(kind=kind, r_min=float(r.min()), r_max=float(r.max()),
                     t_end=float(tt[-1]) / (2 * math.pi), max_energy_error=ee)
