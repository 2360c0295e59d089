"""What LAMMPS can run of a built scene, and the per-body numbers it needs (SI).

LAMMPS integrates spheres (``atom_style sphere``): one moment of inertia per body, the
dipole rotating with the angular velocity. poissonkit's tops have kinetic energy
``α |m|²/2`` (``α = 1/I₁``), the same dynamics for every pair potential that depends on the
axis alone, so a top maps onto a sphere of inertia ``I = 1/α``. Point masses map onto spheres
moved by ``fix nve`` (no rotation).

The registered pair potentials mapped (:data:`PAIR_STYLES`; exact formulas and conversions in
``docs/lammps.md``):

* ``dipole`` (magnetic point dipoles, ``μ0/4π · m₁m₂ (c3 − 3c1c2)/r³``) and ``point_dipole``
  (the example plugin's electric point dipoles, ``k p₁p₂ (c3 − 3c1c2)/r³``, ``p = q d``) —
  LAMMPS's dipole–dipole term of ``lj/cut/dipole/cut``, the prefactor reached through
  ``dielectric`` (``qqr2e/ε = μ0/4π`` or ``k``);
* ``lennard_jones`` (the example plugin's ``4ε[(σ/r)¹² − (σ/r)⁶]``) — ``lj/cut`` for point
  masses, the LJ term of ``lj/cut/dipole/cut`` beside a dipole potential;
* ``gravity`` (``−G m₁m₂/r``) — ``coul/cut`` (``lj/cut/coul/cut`` beside Lennard-Jones) with
  charges ``q = m`` and ``dielectric = −qqr2e/G``, so LAMMPS's Coulomb constant becomes ``−G``.

The external fields ``gravity`` and ``uniform`` (a uniform magnetic field) are mapped too. A
potential is recognised by its registered name *and* its formula: the registry's energy is
evaluated at sample points against the LAMMPS formula (:func:`_check_formula`), so a plugin
potential that reuses a name with another energy is refused.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial

import numpy as np

from poissonkit.conventions import MU0
from poissonkit.errors import InputError, UnknownNameError
from poissonkit.numerics.nbody import NBodySystem
from poissonkit.numerics.nbody.bodies import AllPairs, Interaction
from poissonkit.plugin.contributions import PairPotential

#: Pair potentials with a LAMMPS pair style here (registry name -> LAMMPS style).
PAIR_STYLES = {"dipole": "lj/cut/dipole/cut", "point_dipole": "lj/cut/dipole/cut",
               "lennard_jones": "lj/cut (lj/cut/dipole/cut beside a dipole potential)",
               "gravity": "coul/cut (lj/cut/coul/cut beside lennard_jones)"}
#: Potentials whose strength is carried per body as a LAMMPS point dipole [A m² or C m].
DIPOLES = ("dipole", "point_dipole")
#: Why poissonkit potentials without a LAMMPS counterpart are refused.
NO_STYLE = {
    "dumbbell": "LAMMPS has no pair style of two magnetic poles per body",
    "dumbbell_octupole": "LAMMPS has no pair style with the octupole of finite magnets",
    "cylinder": "LAMMPS has no pair style of finite cylindrical magnets",
    "finite_dipole": "LAMMPS has no pair style of two charges at a fixed distance inside one "
                     "sphere (its point dipoles are the far field only: use point_dipole)",
}


@dataclass(frozen=True)
class LammpsBodies:
    """Per-body numbers of a scene LAMMPS can run (SI, body order of the system).

    Attributes
    ----------
    mass
        ``(n,)`` kg.
    inertia, moment
        ``(n,)``: kg m² (``1/α``) and the point dipole (A m² magnetic, C m electric) of tops;
        ``None`` for point masses.
    cutoff
        The system's hard cutoff [m], or ``None`` for the full pair sum.
    gravity, field
        The uniform gravity [m/s²] and magnetic field [T] acting on every body, or ``None``.
    charge
        ``(n,)`` LAMMPS charges: the masses [kg] of a ``gravity`` pair potential, else ``None``.
    lj
        ``(epsilon [J], sigma [m])`` of a ``lennard_jones`` pair potential, or ``None``.
    prefactor
        LAMMPS's Coulomb constant ``qqr2e/ε`` of the run: ``μ0/4π``, ``k`` or ``−G``.
    """

    mass: np.ndarray
    inertia: np.ndarray | None
    moment: np.ndarray | None
    cutoff: float | None
    gravity: tuple[float, float, float] | None = None
    field: tuple[float, float, float] | None = None
    charge: np.ndarray | None = None
    lj: tuple[float, float] | None = None
    prefactor: float = MU0 / (4.0 * math.pi)

    @property
    def dipolar(self) -> bool:
        """Tops carrying point dipoles (``atom_style hybrid sphere dipole``), not point masses."""
        return self.moment is not None


class NotExpressible(InputError):
    """A scene LAMMPS cannot run (the message says why)."""


def _number(value: object, what: str) -> float:
    """A pair parameter as a float (``NotExpressible`` if it is not a number)."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return float(value)
    raise NotExpressible(f"pair parameter {what} = {value!r} is not a number")


def _entry(term: AllPairs | Interaction) -> PairPotential:
    """The registered potential of a term (read through the public registry)."""
    from poissonkit.plugin import registry

    pot = term.potential
    if isinstance(pot, PairPotential):
        return pot
    if isinstance(pot, str):
        try:
            return registry.potential(pot)
        except UnknownNameError as exc:  # a plugin that has gone since the system was built
            raise NotExpressible(str(exc)) from None
    raise NotExpressible("a pair potential given as an expression or a compiled kernel has no "
                         "LAMMPS pair style (give a registered potential by name)")


def _value(system: NBodySystem, term: AllPairs | Interaction, pot: PairPotential, name: str,
           k: int) -> float:
    """Parameter ``name`` of ``term`` for body ``k``: given in the term, else the body attribute
    the potential takes it from (``body_params``)."""
    if name in term.params:
        return _number(term.params[name], name)
    for param, attr, _ in pot.body_params:
        if param == name:
            return float(system.bodies[k].attribute(attr))
    if name[-1:] in "12" and name[:-1] in dict(system.bodies[k].attributes):
        return float(system.bodies[k].attribute(name[:-1]))  # ``moment1`` from ``moment``
    default = {p.name: p.default for p in pot.params}.get(name)
    if default is None:
        raise NotExpressible(f"pair potential {pot.name!r}: no value for {name!r}")
    return _number(default, name)


#: Per-body strength of a pair of bodies ``(k, 1 or 2)`` for the per-body potentials.
_PER_BODY: dict[str, Callable[[Callable[[str], float], str], float]] = {
    "dipole": lambda v, w: v(f"moment{w}"),
    "point_dipole": lambda v, w: v(f"charge{w}") * v(f"dipole_length{w}"),
    "gravity": lambda v, w: v(f"mass{w}"),
}


def _prefactor(name: str, value: Callable[[str], float]) -> float:
    """LAMMPS's Coulomb constant for a per-body potential (``μ0/4π``, ``k``, ``−G``)."""
    if name == "dipole":
        return value("mu0") / (4.0 * math.pi)
    if name == "point_dipole":
        return value("k")
    return -value("G")


@dataclass
class _Collected:
    """What the pair terms give, potential by potential."""

    strength: dict[str, np.ndarray]
    prefactor: dict[str, float]
    lj: tuple[float, float] | None
    groups: dict[str, list[list[int]]]  # the bodies of each term (a listed pair: two)
    every: set[str]  # potentials with a term joining every body


def _members(system: NBodySystem, term: AllPairs | Interaction) -> list[int]:
    """The bodies a term joins: all its members, or the pair ``(i, j)``."""
    index = {b.name: k for k, b in enumerate(system.bodies)}
    if isinstance(term, AllPairs):
        if term.members is None:
            return list(range(len(system.bodies)))
        return [m if isinstance(m, int) else index[m] for m in term.members]
    return [x if isinstance(x, int) else index[x] for x in (term.i, term.j)]


def _collect(system: NBodySystem) -> _Collected:
    """Per-body strengths, prefactors, the LJ parameters and the pairs each potential joins."""
    n = len(system.bodies)
    got = _Collected({}, {}, None, {}, set())
    for term in system.interactions:
        pot = _entry(term)
        if pot.name not in PAIR_STYLES:
            why = NO_STYLE.get(pot.name, "none is mapped to it here")
            raise NotExpressible(f"pair potential {pot.name!r} has no LAMMPS pair style ({why}; "
                                 f"mapped: {', '.join(PAIR_STYLES)})")
        members = _members(system, term)
        if pot.name not in got.groups:  # the energy's form, once per potential
            _check_formula(system, term, pot, members)
        got.groups.setdefault(pot.name, []).append(members)
        if isinstance(term, AllPairs) and len(set(members)) == n:
            got.every.add(pot.name)
        scalar = partial(_value, system, term, pot, k=members[0])
        if pot.name == "lennard_jones":
            lj = (scalar("epsilon"), scalar("sigma"))
            if got.lj not in (None, lj):
                raise NotExpressible(f"Lennard-Jones pairs with (epsilon, sigma) = {got.lj} and "
                                     f"{lj}: one atom type holds one pair")
            got.lj = lj
            continue
        pref = _prefactor(pot.name, scalar)
        if got.prefactor.setdefault(pot.name, pref) != pref:
            raise NotExpressible(f"{pot.name!r} pairs with different constants {pref} and "
                                 f"{got.prefactor[pot.name]}")
        strength = got.strength.setdefault(pot.name, np.full(n, np.nan))
        sides = [(members[0], 1), (members[1], 2)] if isinstance(term, Interaction) else \
            [(k, w) for k in members for w in (1, 2)]
        for k, w in sides:
            v = _PER_BODY[pot.name](partial(_value, system, term, pot, k=k), str(w))
            if not math.isnan(strength[k]) and strength[k] != v:
                raise NotExpressible(f"body {system.bodies[k].name!r} has {pot.name} strengths "
                                     f"{strength[k]} and {v} in different pairs: LAMMPS holds "
                                     "one per atom")
            strength[k] = v
    return got


def _check_complete(system: NBodySystem, got: _Collected) -> None:
    """Every potential joins every pair of bodies once (LAMMPS applies a style once to every
    pair); the pairs are listed only for a potential without a term over every body."""
    n = len(system.bodies)
    for name, groups in got.groups.items():
        counted = sum(len(g) * (len(g) - 1) // 2 for g in groups)
        if counted > n * (n - 1) // 2 or (name in got.every and len(groups) > 1):
            raise NotExpressible(f"some pairs of bodies interact twice through {name!r}: "
                                 "LAMMPS applies the pair style once to each pair of atoms")
        if name in got.every:
            continue
        pairs = {(min(a, b), max(a, b)) for g in groups for x, a in enumerate(g)
                 for b in g[x + 1:] if a != b}
        if len(pairs) != counted:
            raise NotExpressible(f"some pairs of bodies interact twice through {name!r}: "
                                 "LAMMPS applies the pair style once to each pair of atoms")
        if len(pairs) != n * (n - 1) // 2:
            raise NotExpressible(f"some pairs of bodies do not interact through {name!r}: "
                                 "LAMMPS applies the pair style to every pair of atoms")


def _check_bodies(system: NBodySystem) -> None:
    if system.smooth_cutoff is not None:
        raise NotExpressible("a smoothed cutoff (LAMMPS's pair styles here cut hard)")
    for b in system.bodies:
        if b.fixed:
            raise NotExpressible(f"body {b.name!r} is fixed (not mapped to LAMMPS yet)")
    if not system.interactions:
        raise NotExpressible("no pair interaction")
    tops = [b.alpha is not None for b in system.bodies]
    if any(tops) and not all(tops):
        raise NotExpressible("point masses beside tops (LAMMPS's atoms here are either all "
                             "dipolar spheres or all point masses)")


def lammps_bodies(system: NBodySystem) -> LammpsBodies:
    """The per-body numbers of ``system`` for LAMMPS.

    Raises
    ------
    NotExpressible
        With the reason, for anything LAMMPS cannot run as poissonkit would.
    """
    if not isinstance(system, NBodySystem):
        raise NotExpressible(f"{type(system).__name__} is not an N-body system of bodies")
    _check_bodies(system)
    got = _collect(system)
    _check_complete(system, got)
    dipoles = [d for d in DIPOLES if d in got.strength]
    if len(dipoles) > 1:
        raise NotExpressible("magnetic and electric point dipoles together: LAMMPS holds one "
                             "dipole and one dipole constant per run")
    if dipoles and "gravity" in got.strength:
        raise NotExpressible("gravity pairs beside point dipoles: LAMMPS would carry the masses "
                             "as charges in the dipole style, adding charge-dipole forces")
    tops = system.bodies[0].alpha is not None
    mass = np.array([float(b.mass) for b in system.bodies])
    cutoff = None if system.cutoff is None else float(system.cutoff)  # SI, as given
    if tops:
        if not dipoles:
            raise NotExpressible("tops without a dipole potential: LAMMPS carries a sphere's "
                                 "axis only as its dipole")
        moment = got.strength[dipoles[0]]
        for k in np.flatnonzero(~(moment != 0)):  # zero or NaN
            raise NotExpressible(f"body {system.bodies[k].name!r} has no dipole moment: "
                                 "LAMMPS carries a sphere's axis only as its dipole")
        inertia = np.array([1.0 / float(b.alpha or 0.0) for b in system.bodies])
        gravity, field = _uniform_fields(system, moment, dipoles[0])
        return LammpsBodies(mass, inertia, moment, cutoff, gravity, field, lj=got.lj,
                            prefactor=got.prefactor[dipoles[0]])
    gravity, _ = _uniform_fields(system, None, None)
    charge = got.strength.get("gravity")
    return LammpsBodies(mass, None, None, cutoff, gravity, None, charge=charge, lj=got.lj,
                        prefactor=got.prefactor.get("gravity", 1.0))


def _uniform_fields(system: NBodySystem, moment: np.ndarray | None, dipole: str | None
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
        if moment is None or dipole != "dipole":
            raise NotExpressible("a uniform magnetic field needs magnetic point dipoles "
                                 "(the 'dipole' pair potential): LAMMPS's fix efield turns "
                                 "the dipole of its pair style")
        for k, b in enumerate(system.bodies):
            own = dict(b.attributes).get("moment", moment[k])
            if own != moment[k]:
                raise NotExpressible(f"body {b.name!r}: moment {own} A m² in the field but "
                                     f"{moment[k]} in its pairs")
    return found.get("gravity"), found.get("uniform")


# --- the formula check: the registered energy against the LAMMPS formula ---------------------

#: Sample invariants ``(r [m], c1, c2, c3)`` at which the registered energy is compared.
_SAMPLES = ((0.013, 0.31, -0.52, 0.27), (0.029, -0.83, 0.11, -0.64))


def _lammps_energy(name: str, value: Callable[[str], float], r: float, c1: float, c2: float,
                   c3: float) -> float:
    """The energy LAMMPS computes for the mapped potential ``name`` (docs/lammps.md)."""
    if name == "lennard_jones":
        x = (value("sigma") / r) ** 6
        return 4.0 * value("epsilon") * (x * x - x)
    one = _PER_BODY[name](value, "1")
    two = _PER_BODY[name](value, "2")
    if name == "gravity":
        return _prefactor(name, value) * one * two / r
    return _prefactor(name, value) * one * two * (c3 - 3.0 * c1 * c2) / r ** 3


def _check_formula(system: NBodySystem, term: AllPairs | Interaction, pot: PairPotential,
                   members: list[int]) -> None:
    """:class:`NotExpressible` unless the registered energy of ``pot`` is the LAMMPS formula
    (to 1e-12, at :data:`_SAMPLES`, with the parameters of the pair of ``members[0]`` and
    ``members[1]`` of ``term``)."""
    import sympy as sp

    if pot.expr is None:
        raise NotExpressible(f"pair potential {pot.name!r} has no closed-form energy to check "
                             "against LAMMPS's formula")
    i, j = members[0], members[1] if len(members) > 1 else members[0]
    params: dict[str, float] = {}
    for p in pot.params:
        try:
            params[p.name] = _value(system, term, pot, p.name, j if p.name.endswith("2") else i)
        except (InputError, TypeError):  # a parameter the formula may not use
            continue

    def value(name: str) -> float:
        if name not in params:
            raise NotExpressible(f"pair potential {pot.name!r}: no value for {name!r}")
        return params[name]

    expr = pot.expr(params)
    syms = {s.name: s for s in expr.free_symbols if isinstance(s, sp.Symbol)}
    f = sp.lambdify([syms.get(k, sp.Symbol(k)) for k in ("r", "c1", "c2", "c3")], expr, "math")
    for r, c1, c2, c3 in _SAMPLES:
        ours, theirs = float(f(r, c1, c2, c3)), _lammps_energy(pot.name, value, r, c1, c2, c3)
        if not abs(ours - theirs) <= 1e-12 * max(abs(theirs), 1e-300):
            raise NotExpressible(f"pair potential {pot.name!r} is registered with another "
                                 f"energy than LAMMPS's {PAIR_STYLES[pot.name]} ({ours!r} "
                                 f"against {theirs!r} J at r = {r} m)")

