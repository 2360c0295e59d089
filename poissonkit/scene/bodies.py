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

Attributes declared by potentials (optional)
    Any other attribute (a number or a vector of numbers) is kept in :attr:`BodyModel.extra`
    when a registered pair potential declares it as a body attribute
    (``PairPotential.body_params``, e.g. ``("charge1", "charge", 1)``); an attribute no
    registered potential declares is an error naming it and listing the declared ones
    (:func:`check_attribute`).

Pair parameters of a potential are filled from these attributes: a parameter listed in the
potential's ``body_params`` takes the named attribute of the first / second body, and a
parameter named ``<base>1`` / ``<base>2`` (e.g. ``moment1``, ``half_length2``, ``mass1``) takes
the attribute ``<base>`` of the first / second body of the pair.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from poissonkit.errors import InputError
from poissonkit.validation import positive_number, vector3

if TYPE_CHECKING:
    from poissonkit.plugin.contributions import PairPotential

#: A per-body attribute value a potential may read: a number or a vector of numbers.
AttrValue = float | tuple[float, ...]
#: A potential parameter's value (``Param`` types: float, int, str, bool, vector).
ParamValue = float | int | str | bool | tuple[float, ...]

#: Node attributes a body understands itself; others must be declared by a potential.
BODY_KEYS = ("name", "mass", "alpha", "inertia", "r", "p", "nu", "m", "fixed", "moment",
             "magnetization", "radius", "length", "half_length")
MAGNET_KEYS = ("moment", "magnetization", "radius", "length", "half_length")


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
    extra: Mapping[str, AttrValue] = field(default_factory=dict)

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

    def attr(self, name: str) -> AttrValue | None:
        """This body's attribute ``name`` (``mass``, ``alpha``, a magnet parameter or an
        :attr:`extra` attribute), or ``None`` if it has none."""
        if name == "mass":
            return self.mass
        if name == "alpha":
            return self.alpha
        if name in self.magnet:
            return self.magnet[name]
        return self.extra.get(name)

    @classmethod
    def from_attrs(cls, attrs: Mapping[str, object], default_name: str = "") -> BodyModel:
        """Validate node attributes; errors name the body and the attribute."""
        name = str(attrs.get("name", default_name))
        where = f"body {name!r}"
        if "mass" not in attrs:
            raise InputError(f"{where}: missing 'mass' (kg)")
        mass = positive_number(attrs["mass"], f"{where}: mass")
        alpha = attrs.get("alpha")
        if alpha is not None:
            alpha = positive_number(alpha, f"{where}: alpha")
        elif attrs.get("inertia") is not None:
            alpha = 1.0 / positive_number(attrs["inertia"], f"{where}: inertia")
        if "r" not in attrs:
            raise InputError(f"{where}: missing initial position 'r' (m)")
        r = vector3(attrs["r"], f"{where}: r")
        p = vector3(attrs.get("p", (0.0, 0.0, 0.0)), f"{where}: p")
        nu = m = None
        if alpha is not None:
            if attrs.get("nu") is None:
                raise InputError(f"{where}: a top (alpha given) needs its axis 'nu'")
            nu_v = vector3(attrs["nu"], f"{where}: nu")
            norm = float(np.linalg.norm(nu_v))
            if norm == 0.0:
                raise InputError(f"{where}: axis 'nu' must not be zero")
            nu = tuple(nu_v / norm)
            m = tuple(vector3(attrs.get("m", (0.0, 0.0, 0.0)), f"{where}: m"))
        # moment = 0 or magnetization = 0 says "not a magnet" (e.g. overriding scene defaults)
        demagnetised = any(attrs.get(k) is not None and not isinstance(attrs[k], bool)
                           and attrs[k] == 0 for k in ("moment", "magnetization"))
        magnet = {k: positive_number(attrs[k], f"{where}: {k}") for k in MAGNET_KEYS
                  if attrs.get(k) is not None
                  and not (demagnetised and k in ("moment", "magnetization"))}
        magnet = _complete_magnet(magnet)
        fixed = attrs.get("fixed", False)
        if not isinstance(fixed, (bool, np.bool_)):
            raise InputError(f"{where}: fixed must be true or false, got {fixed!r}")
        extra = {k: attribute_value(v, f"{where}: {k}") for k, v in attrs.items()
                 if k not in BODY_KEYS and check_attribute(k, where) and v is not None}
        return cls(name=name, mass=mass, alpha=alpha, r=tuple(r), p=tuple(p), nu=nu, m=m,
                   fixed=bool(fixed), magnet=magnet, extra=extra)


def declared_attributes() -> dict[str, list[str]]:
    """Body attributes the registered pair potentials declare (``body_params``), each with
    the names of the potentials that read it (``mass`` and ``alpha`` included when declared)."""
    from poissonkit.plugin.contributions import PairPotential
    from poissonkit.plugin.manager import entries

    out: dict[str, list[str]] = {}
    for entry in entries("potential").values():
        if isinstance(entry, PairPotential):
            for _param, attr, _which in entry.body_params:
                out.setdefault(attr, []).append(entry.name)
    return out


def check_attribute(key: str, where: str = "") -> bool:
    """True if ``key`` is a body attribute: one a body understands (:data:`BODY_KEYS`) or one
    a registered potential declares; otherwise an :class:`InputError` naming the key and listing
    the declared attributes."""
    if key in BODY_KEYS:
        return True
    if key in declared_attributes():
        return True
    prefix = f"{where}: " if where else ""
    raise InputError(f"{prefix}unknown body attribute {key!r}; {allowed_attributes()}")


def allowed_attributes() -> str:
    """What a body may carry, for error messages: its own fields and the declared attributes."""
    extra = sorted(set(declared_attributes()) - set(BODY_KEYS))
    return (f"allowed: {', '.join(BODY_KEYS)}; and attributes the registered potentials "
            f"declare (body_params): {', '.join(extra) if extra else 'none'}")


def attribute_value(value: object, where: str) -> AttrValue:
    """A declared attribute's value: a finite number, or a non-empty vector of finite numbers."""
    if isinstance(value, (bool, np.bool_)):
        raise InputError(f"{where} must be a number or a list of numbers, got {value!r}")
    if isinstance(value, (int, float, np.integer, np.floating)):
        x = float(value)
        if not math.isfinite(x):
            raise InputError(f"{where} must be finite, got {value!r}")
        return x
    try:
        v = np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise InputError(f"{where} must be a number or a list of numbers, got {value!r}") from None
    if v.size == 0 or not np.all(np.isfinite(v)):
        raise InputError(f"{where} must be a non-empty list of finite numbers, got {value!r}")
    return tuple(float(x) for x in v)


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


def pair_params(entry: PairPotential, first: BodyModel, second: BodyModel,
                given: Mapping[str, ParamValue] | None = None, *, where: str = ""
                ) -> dict[str, ParamValue]:
    """Parameters of potential ``entry`` for the pair (first, second).

    Explicit values in ``given`` win; a parameter the entry declares in ``body_params`` is
    taken from the named attribute of the first/second body; a parameter ``<base>1``/``<base>2``
    not given is taken from the first/second body's attribute ``<base>``; the rest fall back to
    the entry's defaults (``entry.resolve_params`` validates everything and raises naming the
    parameter).
    """
    values: dict[str, ParamValue] = dict(given or {})
    for name, attr, which in entry.body_params:
        if name not in values:
            body = first if which == 1 else second
            value = body.attr(attr)
            declared = next((p for p in entry.params if p.name == name), None)
            if value is None and declared is not None and (declared.default is not None
                                                           or declared.optional):
                continue  # the potential's default applies
            if value is None:
                raise InputError(f"{where}body {body.name!r} has no {attr!r}, which "
                                 f"{entry.name} reads from each body (parameter {name!r}); "
                                 f"give the body a {attr!r} or the pair a {name!r}")
            values[name] = value
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
