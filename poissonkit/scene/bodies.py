"""Body models carried by graph nodes, and the per-pair parameters derived from them.

Node attributes (all SI)
------------------------
``name`` (str, default ``str(node)``)
    Name of the body in reports.
``mass`` (float > 0, kg)
    Required.
``alpha`` (float > 0, 1/(kg m²)) or ``inertia`` (float > 0, kg m²)
    ``alpha = 1/I_perp`` of a symmetric top. Omit both (or give ``alpha=None``) for a point
    mass, which carries no axis and no angular momentum.
``r``, ``p`` (3-vectors; m, kg m/s)
    Initial position (required) and momentum (default 0).
``nu``, ``m`` (3-vectors; unit, kg m²/s)
    Initial symmetry axis (required for a top, normalised if not unit) and angular momentum
    (default 0). Ignored for point masses.
``fixed`` (bool, default False)
    A fixed body keeps its position and axis: it contributes fields, not degrees of freedom.
Magnet parameters (optional)
    ``moment`` (A m²), ``magnetization`` (A/m), ``radius`` (m), ``length`` (full height, m),
    ``half_length`` (m, default ``length/2``). ``moment`` and ``magnetization`` are derived from
    each other through the cylinder volume ``pi radius² length`` when only one is given;
    ``moment = 0`` (or ``magnetization = 0``) marks a body that is not a magnet.

Pair parameters of a potential are filled from these attributes: a potential parameter named
``<base>1`` / ``<base>2`` (e.g. ``moment1``, ``half_length2``, ``mass1``) takes the node
attribute ``<base>`` of the first / second body of the pair.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from poissonkit.errors import InputError

#: Node attributes a body understands; anything else is passed through untouched.
BODY_KEYS = ("name", "mass", "alpha", "inertia", "r", "p", "nu", "m", "fixed", "moment",
             "magnetization", "radius", "length", "half_length")
MAGNET_KEYS = ("moment", "magnetization", "radius", "length", "half_length")


def _vector(value: Any, what: str) -> np.ndarray:
    try:
        v = np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise InputError(f"{what} must be a 3-vector of numbers, got {value!r}") from None
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise InputError(f"{what} must be a finite 3-vector, got {value!r}")
    return v


def _positive(value: Any, what: str) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{what} must be a number, got {value!r}") from None
    if not (math.isfinite(x) and x > 0):
        raise InputError(f"{what} must be finite and > 0, got {value!r}")
    return x


@dataclass(frozen=True)
class BodyModel:
    """A validated body: mass, inertia (or point mass), magnet parameters and initial state.

    Build it with :meth:`from_attrs` from a node-attribute mapping (see the module docstring).
    """

    name: str
    mass: float
    alpha: float | None
    r: tuple[float, float, float]
    p: tuple[float, float, float] = (0.0, 0.0, 0.0)
    nu: tuple[float, float, float] | None = None
    m: tuple[float, float, float] | None = None
    fixed: bool = False
    magnet: Mapping[str, float] = field(default_factory=dict)

    @property
    def is_top(self) -> bool:
        """True if the body carries an axis and angular momentum."""
        return self.alpha is not None

    @property
    def bounding_radius(self) -> float:
        """Radius of the smallest sphere about the centre containing the body (0 if unknown)."""
        a = self.magnet.get("radius", 0.0)
        h = self.magnet.get("half_length", 0.0)
        return math.hypot(a, h)

    def attr(self, base: str) -> Any:
        """The value a pair parameter ``<base>1``/``<base>2`` takes from this body, or None."""
        if base == "mass":
            return self.mass
        if base == "alpha":
            return self.alpha
        return self.magnet.get(base)

    @classmethod
    def from_attrs(cls, attrs: Mapping[str, Any], default_name: str = "") -> BodyModel:
        """Validate node attributes; errors name the body and the attribute."""
        name = str(attrs.get("name", default_name))
        where = f"body {name!r}"
        if "mass" not in attrs:
            raise InputError(f"{where}: missing 'mass' (kg)")
        mass = _positive(attrs["mass"], f"{where}: mass")
        alpha = attrs.get("alpha")
        if alpha is not None:
            alpha = _positive(alpha, f"{where}: alpha")
        elif attrs.get("inertia") is not None:
            alpha = 1.0 / _positive(attrs["inertia"], f"{where}: inertia")
        if "r" not in attrs:
            raise InputError(f"{where}: missing initial position 'r' (m)")
        r = _vector(attrs["r"], f"{where}: r")
        p = _vector(attrs.get("p", (0.0, 0.0, 0.0)), f"{where}: p")
        nu = m = None
        if alpha is not None:
            if attrs.get("nu") is None:
                raise InputError(f"{where}: a top (alpha given) needs its axis 'nu'")
            nu_v = _vector(attrs["nu"], f"{where}: nu")
            norm = float(np.linalg.norm(nu_v))
            if norm == 0.0:
                raise InputError(f"{where}: axis 'nu' must not be zero")
            nu = tuple(nu_v / norm)
            m = tuple(_vector(attrs.get("m", (0.0, 0.0, 0.0)), f"{where}: m"))
        # moment = 0 or magnetization = 0 says "not a magnet" (e.g. overriding scene defaults)
        demagnetised = any(attrs.get(k) is not None and not isinstance(attrs[k], bool)
                           and attrs[k] == 0 for k in ("moment", "magnetization"))
        magnet = {k: _positive(attrs[k], f"{where}: {k}") for k in MAGNET_KEYS
                  if attrs.get(k) is not None
                  and not (demagnetised and k in ("moment", "magnetization"))}
        magnet = _complete_magnet(magnet)
        fixed = attrs.get("fixed", False)
        if not isinstance(fixed, (bool, np.bool_)):
            raise InputError(f"{where}: fixed must be true or false, got {fixed!r}")
        return cls(name=name, mass=mass, alpha=alpha, r=tuple(r), p=tuple(p), nu=nu, m=m,
                   fixed=bool(fixed), magnet=magnet)


def _complete_magnet(mag: dict[str, float]) -> dict[str, float]:
    """Derive half_length from length (and back) and moment from magnetization (and back)."""
    if "length" in mag and "half_length" not in mag:
        mag["half_length"] = mag["length"] / 2
    if "half_length" in mag and "length" not in mag:
        mag["length"] = 2 * mag["half_length"]
    if "radius" in mag and "length" in mag:
        volume = math.pi * mag["radius"] ** 2 * mag["length"]
        if "magnetization" in mag and "moment" not in mag:
            mag["moment"] = mag["magnetization"] * volume
        elif "moment" in mag and "magnetization" not in mag:
            mag["magnetization"] = mag["moment"] / volume
    return mag


def pair_params(entry: Any, first: BodyModel, second: BodyModel,
                given: Mapping[str, Any] | None = None, *, where: str = "") -> dict[str, Any]:
    """Parameters of potential ``entry`` for the pair (first, second).

    Explicit values in ``given`` win; a parameter ``<base>1``/``<base>2`` not given is taken from
    the first/second body's attribute ``<base>``; the rest fall back to the entry's defaults
    (``entry.resolve_params`` validates everything and raises naming the parameter).
    """
    values: dict[str, Any] = dict(given or {})
    for param in entry.params:
        if param.name in values or param.name[-1:] not in ("1", "2"):
            continue
        body = first if param.name.endswith("1") else second
        value = body.attr(param.name[:-1])
        if value is not None:
            values[param.name] = value
    try:
        return entry.resolve_params(values)
    except InputError as exc:
        raise InputError(f"{where}{exc}") from None
