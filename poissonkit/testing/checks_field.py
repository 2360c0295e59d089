"""``check_field``: an external field against :class:`~poissonkit.plugin.ExternalField`.

The compiled kernel ``f(x, y, z, ν_x, ν_y, ν_z, c, P) -> (U, U_x, U_y, U_z, U_νx, U_νy,
U_νz)`` must give partials that are the gradient of its ``U`` (central differences in the
position, and rotations of the axis for the torque ``∂U/∂ν × ν``), read the coupling ``c`` of
the declared attribute (``U`` proportional to it), declare what it reads and whether it depends
on the axis as its entry does, and carry no axis partials when it says it has no orientation.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from poissonkit.plugin.contributions import ExternalField
from poissonkit.testing.geometry import rotation, unit
from poissonkit.testing.lookup import findings_for


def _example_params(entry: ExternalField, given: Mapping[str, Any] | None) -> dict[str, Any]:
    out = dict(given or {})
    for p in entry.params:
        if p.name not in out and p.default is None and not p.optional:
            out[p.name] = {"float": 1.0, "int": 1, "vector": (0.0, 0.0, 1.0)}.get(p.type)
    return entry.resolve_params(out)


def _fd(f: Any, x: np.ndarray, nu: np.ndarray, c: float, data: np.ndarray, h: float
        ) -> tuple[np.ndarray, np.ndarray]:
    """Force ``−∂U/∂r`` and torque ``−∂U/∂θ`` (axis rotations) by central differences."""
    def u(xx: np.ndarray, nn: np.ndarray) -> float:
        return float(f(xx[0], xx[1], xx[2], nn[0], nn[1], nn[2], c, data)[0])

    force, torque = np.zeros(3), np.zeros(3)
    for k in range(3):
        d = np.eye(3)[k] * h
        force[k] = -(u(x + d, nu) - u(x - d, nu)) / (2 * h)
        a = 1e-4
        torque[k] = -(u(x, rotation(np.eye(3)[k], a) @ nu)
                      - u(x, rotation(np.eye(3)[k], -a) @ nu)) / (2 * a)
    return force, torque


def check_field(field: ExternalField | str, *, params: Mapping[str, Any] | None = None,
                source: object = None, distances: tuple[float, float] = (2.0, 4.0),
                samples: int = 6, seed: int = 0, rtol: float = 1e-5) -> None:
    """Check an external field; raise :class:`CheckFailed` listing every defect.

    Parameters
    ----------
    field
        The :class:`~poissonkit.plugin.ExternalField` or its registered name.
    params
        Example parameters (SI); required floats default to 1.0, vectors to ``(0, 0, 1)``.
    source
        The Python object the field is built from, for entries that take one (``accepts``).
    distances
        Distances from the origin of the sampled points [m].
    samples, seed
        Random points and axes, and their seed.
    rtol
        Tolerance of the gradient, relative to the largest load at the point.

    Raises
    ------
    CheckFailed
    """
    from poissonkit.numerics.fields import FieldRequest

    entry, out = findings_for(field, "field", ExternalField)
    rng = np.random.default_rng(seed)
    points = np.array([unit(rng.normal(size=3)) * rng.uniform(*distances)
                       for _ in range(samples)])
    try:
        built = entry.build(_example_params(entry, params), FieldRequest(points=points), source)
    except Exception as exc:  # noqa: BLE001 - reported
        out.add("build", f"build fails: {type(exc).__name__}: {exc} (give params= or source=)")
        out.raise_if_any()
        return
    if built.reads != entry.reads:
        out.add("reads", f"the compiled field reads {built.reads!r}, the entry declares "
                         f"{entry.reads!r}")
    if bool(built.orientation) != bool(entry.orientation):
        out.add("orientation", f"the compiled field's orientation {built.orientation} differs "
                               f"from the entry's {entry.orientation}")
    f, data = built.kernel, np.ascontiguousarray(built.data, dtype=float)
    worst, where = 0.0, ""
    for x in points:
        nu = unit(rng.normal(size=3))
        with out.guard("gradient"):
            vals = np.array(f(x[0], x[1], x[2], nu[0], nu[1], nu[2], 1.0, data), float)
            twice = float(f(x[0], x[1], x[2], nu[0], nu[1], nu[2], 2.0, data)[0])
            if abs(twice - 2 * vals[0]) > 1e-9 * abs(vals[0]) or (vals[0] == 0 and twice == 0
                                                                   and np.all(vals[1:] == 0)):
                out.add("reads", f"U is not proportional to the coupling {entry.reads!r}: "
                                 f"U(c=1) = {vals[0]:.6g}, U(c=2) = {twice:.6g} at x = {x}")
            force, torque = -vals[1:4], np.cross(vals[4:7], nu)
            fd_f, fd_t = _fd(f, x, nu, 1.0, data, 1e-4 * float(np.linalg.norm(x)))
            r = float(np.linalg.norm(x))
            scale = max(float(np.linalg.norm(force)), float(np.linalg.norm(torque)) / r,
                        abs(vals[0]) / r, 1e-300)
            err = max(float(np.linalg.norm(force - fd_f)),
                      float(np.linalg.norm(torque - fd_t)) / r) / scale
            if err > worst:
                worst, where = err, f"x = {np.round(x, 4).tolist()} m"
            if not entry.orientation and np.any(vals[4:7] != 0):
                out.add("orientation", f"declares no orientation but U_ν = {vals[4:7]} at "
                                       f"{where}")
    if worst > rtol:
        out.add("gradient", f"force or torque is not minus the gradient of U: off by "
                            f"{worst:.3g} relative at {where} (tolerance {rtol:g})")
    out.raise_if_any()
