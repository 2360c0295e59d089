"""What LAMMPS can run of a built scene, and the per-body numbers it needs (SI).

LAMMPS integrates spheres (``atom_style sphere``): one moment of inertia per body, the
dipole rotating with the angular velocity. poissonkit's tops have kinetic energy
``α |m|²/2`` (``α = 1/I₁``), the same dynamics for every pair potential that depends on the
axis alone, so a top maps onto a sphere of inertia ``I = 1/α``. The pair potentials mapped
so far: the point ``dipole`` (``pair_style lj/cut/dipole/cut`` with ``epsilon = 0``), with the
prefactor ``μ0/4π`` reached through LAMMPS's ``dielectric`` setting; and the external fields
``gravity`` and ``uniform`` (a uniform magnetic field).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from poissonkit.conventions import MU0
from poissonkit.errors import InputError
from poissonkit.numerics.nbody import NBodySystem
from poissonkit.numerics.nbody.bodies import AllPairs, Interaction

#: Pair potentials with a LAMMPS pair style here (registry name -> LAMMPS style).
PAIR_STYLES = {"dipole": "lj/cut/dipole/cut"}


@dataclass(frozen=True)
class LammpsBodies:
    """Per-body numbers of a scene LAMMPS can run (SI, body order of the system).

    Attributes
    ----------
    mass, inertia, moment
        ``(n,)``: kg, kg m² (``1/α``), A m².
    cutoff
        The system's hard cutoff [m], or ``None`` for the full pair sum.
    gravity, field
        The uniform gravity [m/s²] and magnetic field [T] acting on every body, or ``None``.
    """

    mass: np.ndarray
    inertia: np.ndarray
    moment: np.ndarray
    cutoff: float | None
    gravity: tuple[float, float, float] | None = None
    field: tuple[float, float, float] | None = None


class NotExpressible(InputError):
    """A scene LAMMPS cannot run (the message says why)."""


def _potential_name(term: AllPairs | Interaction) -> str | None:
    from poissonkit.plugin.contributions import PairPotential

    pot = term.potential
    if isinstance(pot, str):
        return pot
    return pot.name if isinstance(pot, PairPotential) else None


def _number(value: object, what: str) -> float:
    """A pair parameter as a float (``NotExpressible`` if it is not a number)."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return float(value)
    raise NotExpressible(f"pair parameter {what} = {value!r} is not a number")


def _moments(system: NBodySystem) -> np.ndarray:
    """Each body's dipole moment [A m²] from the pair terms (``NotExpressible`` otherwise)."""
    n = len(system.bodies)
    index = {b.name: k for k, b in enumerate(system.bodies)}
    moment = np.full(n, np.nan)
    covered: set[tuple[int, int]] = set()
    every = False
    groups: list[list[int]] = []  # members of all-pairs terms over some of the bodies

    def put(k: int, value: object) -> None:
        v = _number(value, "moment") if value is not None else \
            system.bodies[k].attribute("moment")
        if not math.isnan(moment[k]) and moment[k] != v:
            raise NotExpressible(f"body {system.bodies[k].name!r} has dipole moments {moment[k]}"
                                 f" and {v} A m² in different pairs: LAMMPS holds one per atom")
        moment[k] = v

    for term in system.interactions:
        name = _potential_name(term)
        if name not in PAIR_STYLES:
            raise NotExpressible(f"pair potential {name!r} has no LAMMPS pair style mapped "
                                 f"here (mapped: {', '.join(PAIR_STYLES)})")
        mu0 = _number(term.params.get("mu0", MU0), "mu0")
        if mu0 != MU0:
            raise NotExpressible(f"dipole pairs with mu0 = {mu0} (only μ0 = 4π·1e-7 T m/A)")
        if isinstance(term, AllPairs):
            members = range(n) if term.members is None else [
                m if isinstance(m, int) else index[m] for m in term.members]
            members = list(members)
            if len(members) == n:
                every = True
            for k in members:
                put(k, term.params.get("moment1"))
                if term.params.get("moment2", term.params.get("moment1")) != \
                        term.params.get("moment1"):
                    raise NotExpressible("an all-pairs dipole term with moment1 != moment2")
            groups.append(members)
        else:
            i, j = (x if isinstance(x, int) else index[x] for x in (term.i, term.j))
            put(i, term.params.get("moment1"))
            put(j, term.params.get("moment2"))
            covered.add((min(i, j), max(i, j)))
    if not every:  # the pairs are listed only when no term joins every body
        covered |= {(a, b) for g in groups for a in g for b in g if a < b}
    if not every and len(covered) != n * (n - 1) // 2:
        raise NotExpressible("some pairs of bodies do not interact: LAMMPS applies the pair "
                             "style to every pair of atoms")
    return moment


def lammps_bodies(system: NBodySystem) -> LammpsBodies:
    """The per-body numbers of ``system`` for LAMMPS.

    Raises
    ------
    NotExpressible
        With the reason, for anything LAMMPS cannot run as poissonkit would.
    """
    if not isinstance(system, NBodySystem):
        raise NotExpressible(f"{type(system).__name__} is not an N-body system of bodies")
    if system.smooth_cutoff is not None:
        raise NotExpressible("a smoothed cutoff (LAMMPS's dipole styles cut hard)")
    for b in system.bodies:
        if b.fixed:
            raise NotExpressible(f"body {b.name!r} is fixed (not mapped to LAMMPS yet)")
        if b.alpha is None:
            raise NotExpressible(f"body {b.name!r} is a point mass: a dipole needs an axis")
    if not system.interactions:
        raise NotExpressible("no pair interaction")
    moment = _moments(system)
    for k in np.flatnonzero(~(moment != 0)):  # zero or NaN
        raise NotExpressible(f"body {system.bodies[k].name!r} has no dipole moment: LAMMPS "
                             "carries a sphere's axis only as its dipole")
    mass = np.array([float(b.mass) for b in system.bodies])
    inertia = np.array([1.0 / b.alpha for b in system.bodies if b.alpha is not None])
    cutoff = None if system.cutoff is None else float(system.cutoff)  # SI, as given
    gravity, field = _uniform_fields(system, moment)
    return LammpsBodies(mass, inertia, moment, cutoff, gravity, field)


def _uniform_fields(system: NBodySystem, moment: np.ndarray
                    ) -> tuple[tuple[float, float, float] | None, ...]:
    """The uniform gravity and magnetic field of ``system`` (``fix gravity``, ``fix efield``:
    the torque ``μ × B`` on each dipole), ``None`` where absent."""
    found: dict[str, tuple[float, float, float]] = {}
    for f in system.external_fields:
        if f.name not in ("gravity", "uniform") or f.name in found:
            raise NotExpressible(f"external field {f.name!r} is not mapped to a LAMMPS fix "
                                 "(mapped: one uniform gravity, one uniform magnetic field)")
        v = np.asarray(f.data, dtype=float)
        found[f.name] = (float(v[0]), float(v[1]), float(v[2]))
    if "uniform" in found:  # the field's moments must be the pairs' (one μ per LAMMPS atom)
        for k, b in enumerate(system.bodies):
            own = dict(b.attributes).get("moment", moment[k])
            if own != moment[k]:
                raise NotExpressible(f"body {b.name!r}: moment {own} A m² in the field but "
                                     f"{moment[k]} in its pairs")
    return found.get("gravity"), found.get("uniform")

