"""``pair_interaction``: what does a pair of magnets (or any registered pair potential) feel?

Geometry and signs follow :mod:`poissonkit.conventions`: ``r = r2 - r1``, ``e = r/|r|``,
``c1 = (e, nu1)``, ``c2 = (e, nu2)``, ``c3 = (nu1, nu2)``; from the partials of
``U(r, c1, c2, c3)``

    F  = -[U_r e + U_c1 (nu1 - c1 e)/r + U_c2 (nu2 - c2 e)/r]      (force on body 2)
    T2 = U_c2 e x nu2 + U_c3 nu1 x nu2,   T1 = U_c1 e x nu1 + U_c3 nu2 x nu1

(torques about each body's centre; the force on body 1 is ``-F``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from poissonkit.errors import InputError, OverlapError, UnknownNameError
from poissonkit.plugin.contributions import ModelFamily, PairPotential
from poissonkit.validation import vector3


class NoModelFamilyError(InputError):
    """``model="auto"`` but no registered model family applies to the pair."""


@dataclass(frozen=True)
class PairInteraction:
    """Energy, force and torques of a pair (SI).

    Attributes
    ----------
    model
        The potential actually evaluated (for ``"auto"``: the one the planner chose).
    energy
        Interaction energy U (J).
    force
        Force on body 2 (N); body 1 feels ``-force``.
    torque1, torque2
        Torques on bodies 1 and 2 about their own centres (N m).
    estimated_error
        For a model of a registered model family (e.g. the magnet models): its family's
        estimated worst-case relative force error (``None`` when the family does not apply
        or the body attributes it reads, e.g. the cylinder sizes, are unknown).
    """

    model: str
    energy: float
    force: np.ndarray
    torque1: np.ndarray
    torque2: np.ndarray
    estimated_error: float | None = None


#: Largest vector component accepted (SI): squares beyond this overflow a double.
MAX_COMPONENT = 1e150


def _vector(name: str, value: object) -> np.ndarray:
    v = vector3(value, name)
    if np.max(np.abs(v)) > MAX_COMPONENT:  # its square would overflow in every norm below
        raise InputError(f"{name} has a component of magnitude {np.max(np.abs(v)):.3g}, more "
                         f"than {MAX_COMPONENT:.0e}")
    return v


def _axis(name: str, value: object) -> np.ndarray:
    v = _vector(name, value)
    n = float(np.linalg.norm(v))
    if n == 0.0:
        raise InputError(f"{name} is the zero vector; give a unit axis")
    if abs(n - 1.0) > 1e-9:
        raise InputError(f"{name} must be a unit vector (|{name}| = {n:.12g}); normalise it")
    return v / n


def cylinder_gap(r: np.ndarray, nu1: np.ndarray, nu2: np.ndarray, a1: float, h1: float,
                 a2: float, h2: float) -> float:
    """Smallest distance between two solid cylinders (0 if they touch or overlap).

    Body 1 (radius ``a1``, full height ``h1``, axis ``nu1``) at the origin, body 2 at ``r``.
    The one gap solver of poissonkit, :func:`poissonkit.scene.geometry.distance` (alternating
    projections checked by a separating plane, to ``1e-10`` of the larger body or distance).
    """
    from poissonkit.scene.geometry import distance, shape_of

    return distance(shape_of(np.zeros(3), nu1, a1, 0.5 * h1),
                    shape_of(np.asarray(r, dtype=float), nu2, a2, 0.5 * h2))


def _bases(entries: Sequence[PairPotential]) -> set[str]:
    """Per-body quantities (names without the 1/2 suffix) these potentials accept."""
    out: set[str] = set()
    for entry in entries:
        out.update(p.name[:-1] for p in entry.params if p.name[-1:] in ("1", "2"))
        out.update(entry.body_quantities)
    return out


def _expand(params: Mapping[str, object], bases: set[str]) -> dict[str, object]:
    """Expand the shorthand ``x`` of two identical bodies into ``x1`` and ``x2``."""
    out = dict(params)
    for key in sorted(bases & set(params)):
        value = out.pop(key)
        for i in ("1", "2"):
            if key + i in out:
                raise InputError(f"give either {key!r} or {key + i!r}, not both")
            out[key + i] = value
    return out


def _body(given: Mapping[str, object], i: str) -> dict[str, object]:
    """The attributes of body ``i`` (``"1"`` or ``"2"``) among the suffixed parameters."""
    return {k[:-1]: v for k, v in given.items() if k.endswith(i) and len(k) > 1}


def _sizes(given: Mapping[str, object]) -> tuple[float, float, float, float] | None:
    """``(radius1, length1, radius2, length2)`` when all are given: the bodies are solid
    cylinders (the core's body-shape convention, :mod:`poissonkit.scene.geometry`)."""
    keys = ("radius1", "length1", "radius2", "length2")
    if not all(k in given for k in keys):
        return None
    vals = []
    for k in keys:
        try:
            v = float(given[k])
        except (TypeError, ValueError, OverflowError):  # 10**400 overflows
            raise InputError(f"{k} must be a finite number, got {given[k]!r}") from None
        if not (v > 0 and math.isfinite(v)):
            raise InputError(f"{k} must be positive and finite, got {given[k]!r}")
        vals.append(v)
    return vals[0], vals[1], vals[2], vals[3]


def pair_interaction(model: str, r: Sequence[float], nu1: Sequence[float],
                     nu2: Sequence[float], **params: object) -> PairInteraction:
    """Energy, force on body 2 and torques on both bodies of one pair, in SI units.

    Parameters
    ----------
    model
        A registered pair potential (``"dipole"``, ``"dumbbell"``, ``"dumbbell_octupole"``,
        ``"cylinder"``, ``"dipole_cylinder_field"``, ``"loops"``, ``"gravity"``, ... — see
        ``poissonkit.plugin.names("potential")``), or ``"auto"``: the cheapest model of the
        registered model family that applies to the pair (``poissonkit.plugin.model_families()``;
        the magnets plugin's: dipole / dumbbells / exact cylinder) whose estimated force error
        is within ``tol``.
    r
        ``r2 - r1`` (m), body 1's centre to body 2's centre.
    nu1, nu2
        Unit axes (magnetisation directions) of the bodies.
    **params
        The potential's parameters (docs/architecture.md). A per-body name without its suffix
        (``moment``, ``radius``, ``mass``, ...) gives both bodies the same value. A potential
        may accept further per-body quantities and derive its parameters from them (the
        magnet potentials: ``moment`` and ``magnetization`` are converted through the cylinder
        volume ``pi a^2 h``, a dumbbell given ``length`` gets ``half_length = length/2``). With
        ``"auto"`` give ``tol``. When radii and lengths are known, overlapping cylinders are
        rejected.

    Returns
    -------
    PairInteraction

    Raises
    ------
    InputError
        Malformed vectors, non-unit or zero axes, ``r = 0``, bad or missing parameters.
    OverlapError
        The cylinders overlap or touch.
    UnknownNameError
        Unknown model or parameter name (the message lists the available ones).
    NoModelFamilyError
        ``"auto"`` but no registered model family applies to the pair.

    Examples
    --------
    >>> from poissonkit.pairs import pair_interaction
    >>> out = pair_interaction("dipole", (0, 0, 0.1), (0, 0, 1), (0, 0, 1),
    ...                        moment=0.155)
    >>> round(float(out.force[2]), 6)  # coaxial, head to tail: attraction
    -0.000144
    """
    from poissonkit.plugin import model_families, potential

    if not isinstance(model, str):
        raise InputError(f"model must be a potential name (str), got {model!r}")
    rvec = _vector("r", r)
    n1 = _axis("nu1", nu1)
    n2 = _axis("nu2", nu2)
    dist = float(np.linalg.norm(rvec))
    if dist == 0.0:
        raise InputError("r = 0: the two bodies are at the same place")
    families = model_families()
    if model == "auto":
        candidates = [potential(m) for f in families for m in f.models]
        own = list(families)
    else:
        candidates = [potential(model)]
        own = [f for f in families if model in f.models]
    # what the families read to choose or estimate: accepted, passed on only if taken
    reads = {q for f in own for q in f.reads}
    given = _expand(params, _bases(candidates) | reads)
    tol = given.pop("tol", None)
    sizes = _sizes(given)
    if sizes is not None and cylinder_gap(rvec, n1, n2, *sizes) <= 0.0:
        raise OverlapError(f"the cylinders overlap or touch (r = {dist:.6g} m, radii "
                           f"{sizes[0]:.6g}, {sizes[2]:.6g} m, lengths {sizes[1]:.6g}, "
                           f"{sizes[3]:.6g} m)")
    body1, body2 = _body(given, "1"), _body(given, "2")
    read = {q + i for q in reads for i in ("1", "2")}
    if model == "auto":
        if tol is None:
            raise InputError("model='auto' needs tol (relative force tolerance)")
        family = _family_for(families, body1, body2)
        model = _cheapest(family, tol, dist, body1, body2)
        read = {q + i for q in family.reads for i in ("1", "2")}
    elif tol is not None:
        raise InputError("tol is only used with model='auto'")
    entry = potential(model)
    resolved = _resolved_params(entry, model, given, read)
    estimate = _estimate(families, model, dist, body1, body2)
    _check_poles(resolved, model, rvec, n1, n2, dist)
    u, force, torque1, torque2 = _loads(entry, resolved, model, rvec, n1, n2, dist)
    return PairInteraction(model=model, energy=float(u), force=force, torque1=torque1,
                           torque2=torque2, estimated_error=estimate)


def _resolved_params(entry: PairPotential, model: str, given: Mapping[str, object],
                     read: set[str]) -> dict[str, object]:
    """The potential's resolved parameters from ``given`` (per-body quantities completed by the
    potential; those only a model family reads are dropped).

    Raises
    ------
    UnknownNameError
        A parameter that neither the potential nor its family knows.
    """
    needed = [p.name for p in entry.params]
    known = set(needed) | read | {q + i for q in entry.body_quantities for i in ("1", "2")}
    unknown = sorted(set(given) - known)
    if unknown:
        raise UnknownNameError(f"parameter of {model!r}", unknown[0], needed)
    completed = given if entry.complete_params is None else entry.complete_params(given)
    completed = {k: v for k, v in completed.items() if k in needed or k not in read}
    return entry.resolve_params(completed)


def _check_poles(resolved: Mapping[str, object], model: str, rvec: np.ndarray, n1: np.ndarray,
                 n2: np.ndarray, dist: float) -> None:
    """Refuse dumbbells (``half_length1/2``) with two coinciding poles (:class:`OverlapError`)."""
    if "half_length1" in resolved and "half_length2" in resolved:
        l1, l2 = float(resolved["half_length1"]), float(resolved["half_length2"])
        gaps = [np.linalg.norm(rvec + s2 * l2 * n2 - s1 * l1 * n1)
                for s1 in (1, -1) for s2 in (1, -1)]
        if min(gaps) <= 1e-9 * (dist + l1 + l2):
            raise OverlapError(f"{model}: two poles coincide (r = {dist:.6g} m)")


def _loads(entry: PairPotential, resolved: Mapping[str, object], model: str, rvec: np.ndarray,
           n1: np.ndarray, n2: np.ndarray, dist: float
           ) -> tuple[float, np.ndarray, np.ndarray, np.ndarray]:
    """``(energy, force on body 2, torque on body 1, torque on body 2)`` from the potential's
    partial derivatives in ``r`` and the three cosines (read-only arrays).

    Raises
    ------
    InputError
        The potential is singular or not finite at this configuration.
    """
    e = rvec / dist
    c1, c2, c3 = float(e @ n1), float(e @ n2), float(n1 @ n2)
    try:
        u, ur, u1, u2, u3 = _partials(entry, resolved, dist, c1, c2, c3)
    except (ZeroDivisionError, np.linalg.LinAlgError) as exc:
        # compiled kernels raise these when two poles or charges coincide
        raise InputError(f"{model}: the potential is singular at this configuration "
                         f"(r = {dist:.6g} m): {exc}") from None
    vals = np.array([u, ur, u1, u2, u3])
    if not np.all(np.isfinite(vals)):
        raise InputError(f"{model}: the potential is not finite at this configuration "
                         f"(r = {dist:.6g} m, c = {c1:.6g}, {c2:.6g}, {c3:.6g}); bodies too close?")
    force = -(ur * e + u1 * (n1 - c1 * e) / dist + u2 * (n2 - c2 * e) / dist)
    torque2 = u2 * np.cross(e, n2) + u3 * np.cross(n1, n2)
    torque1 = u1 * np.cross(e, n1) + u3 * np.cross(n2, n1)
    for arr in (force, torque1, torque2):
        arr.setflags(write=False)
    return u, force, torque1, torque2


def _family_for(families: Sequence[ModelFamily], body1: Mapping[str, object],
                body2: Mapping[str, object]) -> ModelFamily:
    """The first registered family that applies to the pair and has what it reads."""
    if not families:
        raise NoModelFamilyError("model='auto': no model family is registered (are the plugins "
                                 "that provide them blocked? see `poissonkit plugins`); name a "
                                 "potential instead")
    for family in families:
        if family.applies(body1, body2):
            missing = [q for q in family.reads if q not in body1 or q not in body2]
            if missing:
                raise InputError(f"model='auto' ({family.name} family) needs "
                                 f"{' and '.join(missing)} of both bodies (or "
                                 f"{', '.join(q + '1/2' for q in missing)})")
            return family
    raise NoModelFamilyError(f"model='auto': no registered model family applies to this pair "
                             f"(families: {', '.join(f.name for f in families)}); name a "
                             f"potential instead")


def _cheapest(family: ModelFamily, tol: float, r: float, body1: Mapping[str, object],
              body2: Mapping[str, object]) -> str:
    """The cheapest model of ``family`` within ``tol``; among equal costs the most accurate;
    the most expensive model if none is within ``tol``."""
    try:
        tol = float(tol)
    except (TypeError, ValueError):
        raise InputError(f"tol must be a number, got {tol!r}") from None
    if not (tol > 0 and math.isfinite(tol)):
        raise InputError(f"tol must be positive and finite, got {tol!r}")
    tiers: dict[float, list[str]] = {}
    for m in family.models:
        tiers.setdefault(family.cost(m), []).append(m)
    try:
        for cost in sorted(tiers):
            errors = {m: float(family.estimate(m, r, body1, body2)) for m in tiers[cost]}
            best = min(tiers[cost], key=errors.__getitem__)
            if errors[best] <= tol:
                return best
    except OverflowError:  # sizes absurd against r (1e308 m magnets)
        raise InputError(f"{family.name}: body sizes out of range against r = {r:.3g} m") from None
    return max(family.models, key=family.cost)


def _estimate(families: Sequence[ModelFamily], model: str, r: float, body1: Mapping[str, object],
              body2: Mapping[str, object]) -> float | None:
    """The error estimate of ``model`` by its family, when the family applies and has what
    it reads; else ``None``."""
    for family in families:
        if model in family.models and family.applies(body1, body2) and all(
                q in body1 and q in body2 for q in family.reads):
            try:
                return float(family.estimate(model, r, body1, body2))
            except OverflowError:  # sizes absurd against r: no estimate, the result stands
                return None
    return None


def _partials(entry: PairPotential, resolved: Mapping[str, object], r: float, c1: float,
              c2: float, c3: float) -> tuple[float, float, float, float, float]:
    """``(U, U_r, U_c1, U_c2, U_c3)``: the entry's own evaluation if it has one, else its
    compiled kernel."""
    if entry.evaluate is not None:
        return entry.evaluate(resolved)(r, c1, c2, c3)
    from poissonkit.numerics.potentials import compile_potential

    kern = compile_potential(entry, resolved)
    return tuple(float(v) for v in kern(r, c1, c2, c3))  # type: ignore[return-value]
