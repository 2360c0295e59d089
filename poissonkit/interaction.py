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
from typing import Any

import numpy as np

from poissonkit.errors import InputError, UnknownNameError

#: Shorthands for two identical bodies, expanded to ``<name>1`` and ``<name>2``.
SHORTHANDS: tuple[str, ...] = ("moment", "magnetization", "radius", "length", "half_length",
                               "current", "flux", "wire_radius")


class OverlapError(InputError):
    """The two bodies overlap (or touch), so the pair energy is not defined by the model."""


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
        For the magnet models: estimated worst-case relative force error of ``model`` against
        the exact cylinders (``None`` when the cylinder sizes are unknown).
    """

    model: str
    energy: float
    force: np.ndarray
    torque1: np.ndarray
    torque2: np.ndarray
    estimated_error: float | None = None


def _vector(name: str, value: Any) -> np.ndarray:
    try:
        v = np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a 3-vector of numbers, got {value!r}") from None
    if v.shape != (3,):
        raise InputError(f"{name} must be a 3-vector, got shape {np.shape(value)}")
    if not np.all(np.isfinite(v)):
        raise InputError(f"{name} must be finite, got {value!r}")
    return v


def _axis(name: str, value: Any) -> np.ndarray:
    v = _vector(name, value)
    n = float(np.linalg.norm(v))
    if n == 0.0:
        raise InputError(f"{name} is the zero vector; give a unit axis")
    if abs(n - 1.0) > 1e-9:
        raise InputError(f"{name} must be a unit vector (|{name}| = {n:.12g}); normalise it")
    return v / n


def _project_cylinder(p: np.ndarray, centre: np.ndarray, nu: np.ndarray, a: float,
                      l: float) -> np.ndarray:
    d = p - centre
    z = float(d @ nu)
    rv = d - z * nu
    rho = float(np.linalg.norm(rv))
    if rho > a:
        rv *= a / rho
    return centre + min(max(z, -l), l) * nu + rv


def cylinder_gap(r: np.ndarray, nu1: np.ndarray, nu2: np.ndarray, a1: float, h1: float,
                 a2: float, h2: float) -> float:
    """Smallest distance between two solid cylinders (0 if they touch or overlap).

    Alternating projections between the two convex bodies (Cheney–Goldstein), which converge
    to a closest pair for disjoint bodies and into the intersection otherwise.
    """
    c1 = np.zeros(3)
    c2 = np.asarray(r, dtype=float)
    scale = max(a1, a2, h1, h2)
    x = c1.copy()
    y = _project_cylinder(c2, c1, nu1, a1, 0.5 * h1)
    last = math.inf
    for _ in range(5000):
        y = _project_cylinder(x, c2, nu2, a2, 0.5 * h2)
        x = _project_cylinder(y, c1, nu1, a1, 0.5 * h1)
        dist = float(np.linalg.norm(x - y))
        if dist < 1e-12 * scale or last - dist < 1e-15 * scale:
            break
        last = dist
    return dist


def _expand(params: Mapping[str, Any]) -> dict[str, Any]:
    out = dict(params)
    for key in SHORTHANDS:
        if key in out:
            value = out.pop(key)
            for i in ("1", "2"):
                if key + i in out:
                    raise InputError(f"give either {key!r} or {key + i!r}, not both")
                out[key + i] = value
    return out


def _complete(needed: Sequence[str], given: dict[str, Any]) -> dict[str, Any]:
    """Derive missing per-body quantities the model needs from the ones given."""
    out = dict(given)
    for i in ("1", "2"):
        m, mu, a, h = (out.get("magnetization" + i), out.get("moment" + i),
                       out.get("radius" + i), out.get("length" + i))
        if a is not None and h is not None:
            try:
                volume = math.pi * float(a) ** 2 * float(h)
            except (TypeError, ValueError, OverflowError):
                raise InputError(f"radius{i} and length{i} must be finite numbers") from None
            try:
                if volume > 0:
                    if "moment" + i in needed and mu is None and m is not None:
                        out["moment" + i] = float(m) * volume
                    if "magnetization" + i in needed and m is None and mu is not None:
                        out["magnetization" + i] = float(mu) / volume
                if "half_length" + i in needed and out.get("half_length" + i) is None:
                    out["half_length" + i] = 0.5 * float(h)
            except (TypeError, ValueError, OverflowError):
                raise InputError(f"moment{i} / magnetization{i} must be finite numbers") from None
        elif "half_length" + i in needed and out.get("half_length" + i) is None and h is not None:
            try:
                out["half_length" + i] = 0.5 * float(h)
            except (TypeError, ValueError, OverflowError):
                raise InputError(f"length{i} must be a finite number, got {h!r}") from None
    # drop what the model does not take (sizes given only for the overlap check, moments given
    # together with magnetisations)
    return {k: v for k, v in out.items() if k in needed}


def _sizes(given: Mapping[str, Any]) -> tuple[float, float, float, float] | None:
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
                     nu2: Sequence[float], **params: Any) -> PairInteraction:
    """Energy, force on body 2 and torques on both bodies of one pair, in SI units.

    Parameters
    ----------
    model
        A registered pair potential (``"dipole"``, ``"dumbbell"``, ``"dumbbell_octupole"``,
        ``"cylinder"``, ``"dipole_cylinder_field"``, ``"loops"``, ... — see
        ``poissonkit.plugin.names("potential")``), or ``"auto"``: the cheapest of dipole /
        dumbbell / octupole-corrected dumbbell / exact cylinder whose estimated force error is
        within ``tol`` (:func:`poissonkit_magnets.fidelity.cheapest_model`).
    r
        ``r2 - r1`` (m), body 1's centre to body 2's centre.
    nu1, nu2
        Unit axes (magnetisation directions) of the bodies.
    **params
        The potential's parameters (docs/architecture.md), plus the shorthands ``moment``,
        ``magnetization``, ``radius``, ``length`` (and ``half_length``, ``current``, ``flux``,
        ``wire_radius``) for two identical bodies. Moments and magnetisations are converted
        through the cylinder volume ``pi a^2 h`` where the model needs the other one; a
        dumbbell given ``length`` gets ``half_length = length/2``. With ``"auto"`` give ``tol``.
        When radii and lengths are known, overlapping cylinders are rejected.

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

    Examples
    --------
    >>> from poissonkit.interaction import pair_interaction
    >>> out = pair_interaction("dipole", (0, 0, 0.1), (0, 0, 1), (0, 0, 1),
    ...                        moment=0.155)
    >>> round(float(out.force[2]), 6)  # coaxial, head to tail: attraction
    -0.000144
    """
    from poissonkit.plugin import potential

    if not isinstance(model, str):
        raise InputError(f"model must be a potential name (str), got {model!r}")
    rvec = _vector("r", r)
    n1 = _axis("nu1", nu1)
    n2 = _axis("nu2", nu2)
    dist = float(np.linalg.norm(rvec))
    if dist == 0.0:
        raise InputError("r = 0: the two bodies are at the same place")
    given = _expand(params)
    tol = given.pop("tol", None)
    sizes = _sizes(given)
    if sizes is not None and cylinder_gap(rvec, n1, n2, *sizes) <= 0.0:
        raise OverlapError(f"the cylinders overlap or touch (r = {dist:.6g} m, radii "
                           f"{sizes[0]:.6g}, {sizes[2]:.6g} m, lengths {sizes[1]:.6g}, "
                           f"{sizes[3]:.6g} m)")
    estimate: float | None = None
    if model == "auto":
        from poissonkit_magnets.fidelity import cheapest_model

        if tol is None:
            raise InputError("model='auto' needs tol (relative force tolerance)")
        if sizes is None:
            raise InputError("model='auto' needs radius and length (or radius1/2, length1/2)")
        try:
            model = cheapest_model(tol, dist, sizes[0], sizes[1], sizes[2], sizes[3])
        except OverflowError:  # sizes absurd against r (1e308 m magnets)
            raise InputError(f"radius/length out of range against r = {dist:.3g} m") from None
    elif tol is not None:
        raise InputError("tol is only used with model='auto'")
    entry = potential(model)
    needed = [p.name for p in entry.params]
    known = set(needed) | {"magnetization1", "magnetization2", "moment1", "moment2",
                           "radius1", "radius2", "length1", "length2"}
    unknown = sorted(set(given) - known)
    if unknown:
        raise UnknownNameError(f"parameter of {model!r}", unknown[0], needed)
    resolved = entry.resolve_params(_complete(needed, given))
    if sizes is not None and model in ("dipole", "dumbbell", "dumbbell_octupole", "cylinder"):
        from poissonkit_magnets.fidelity import estimated_error

        try:
            estimate = estimated_error(model, dist, sizes[0], sizes[1], sizes[2], sizes[3])
        except OverflowError:  # sizes absurd against r: no estimate, the result stands
            estimate = None
    if "half_length1" in resolved and "half_length2" in resolved:
        l1, l2 = float(resolved["half_length1"]), float(resolved["half_length2"])
        gaps = [np.linalg.norm(rvec + s2 * l2 * n2 - s1 * l1 * n1)
                for s1 in (1, -1) for s2 in (1, -1)]
        if min(gaps) <= 1e-9 * (dist + l1 + l2):
            raise OverlapError(f"{model}: two poles coincide (r = {dist:.6g} m)")
    e = rvec / dist
    c1, c2, c3 = float(e @ n1), float(e @ n2), float(n1 @ n2)
    try:
        u, ur, u1, u2, u3 = _partials(model, entry, resolved, dist, c1, c2, c3)
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
    return PairInteraction(model=model, energy=float(u), force=force, torque1=torque1,
                           torque2=torque2, estimated_error=estimate)


def _partials(model: str, entry: Any, resolved: Mapping[str, Any], r: float, c1: float,
              c2: float, c3: float) -> tuple[float, float, float, float, float]:
    from poissonkit_magnets.models import BY_NAME, evaluate

    if model in BY_NAME:
        return evaluate(model, resolved, r, c1, c2, c3)
    # any other registered potential: through the numerics' compiled kernel
    from poissonkit.numerics.potentials import compile_potential

    kern = compile_potential(entry, resolved)
    return tuple(float(v) for v in kern(r, c1, c2, c3))  # type: ignore[return-value]
