"""Types of the things plugins contribute.

Every contribution is a named registry entry with a docstring and typed parameters. Plugins
return lists of these from the hooks in :mod:`poissonkit.plugin.hookspecs`.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

from poissonkit.errors import InputError, UnknownNameError

_PARAM_TYPES = {"float": float, "int": int, "str": str, "bool": bool, "vector": tuple}


@dataclass(frozen=True)
class Param:
    """A typed, documented parameter of a registry entry.

    Parameters
    ----------
    name
        Parameter name as passed by users (keyword).
    type
        One of ``"float"``, ``"int"``, ``"str"``, ``"bool"``, ``"vector"``.
    doc
        One-line description, with the unit in brackets for physical quantities.
    default
        Default value; ``None`` means the parameter is required.
    unit
        SI unit, or ``""`` for dimensionless.
    positive
        If true, values must be > 0.
    """

    name: str
    type: str = "float"
    doc: str = ""
    default: Any = None
    unit: str = ""
    positive: bool = False

    def coerce(self, value: Any, owner: str = "") -> Any:
        """Check and convert one user value; raise :class:`InputError` naming the parameter."""
        where = f"{owner}: " if owner else ""
        if self.type not in _PARAM_TYPES:
            raise InputError(f"{where}parameter {self.name!r} has unknown type {self.type!r}")
        try:
            if self.type == "vector":
                out = tuple(float(v) for v in value)
            elif self.type == "bool":
                if not isinstance(value, bool):
                    raise TypeError
                out = value
            else:
                out = _PARAM_TYPES[self.type](value)
        except (TypeError, ValueError):
            raise InputError(
                f"{where}parameter {self.name!r} must be {self.type}, got {value!r}"
            ) from None
        if self.type == "float" and not (out == out and abs(out) != float("inf")):
            raise InputError(f"{where}parameter {self.name!r} must be finite, got {value!r}")
        if self.positive and not out > 0:
            raise InputError(f"{where}parameter {self.name!r} must be > 0, got {value!r}")
        return out


@dataclass(frozen=True)
class Entry:
    """Base of every registry entry: a name, a doc string and typed parameters."""

    name: str
    doc: str
    params: tuple[Param, ...] = ()

    def resolve_params(self, given: Mapping[str, Any]) -> dict[str, Any]:
        """Validate user parameters against :attr:`params`, fill defaults, reject unknown ones."""
        known = {p.name: p for p in self.params}
        unknown = set(given) - set(known)
        if unknown:
            raise UnknownNameError(f"parameter of {self.name!r}", sorted(unknown)[0], known)
        out: dict[str, Any] = {}
        for p in self.params:
            if p.name in given:
                out[p.name] = p.coerce(given[p.name], self.name)
            elif p.default is not None:
                out[p.name] = p.default
            else:
                raise InputError(f"{self.name}: missing required parameter {p.name!r} ({p.doc})")
        return out


@dataclass(frozen=True)
class PairPotential(Entry):
    """An interaction energy of two axisymmetric bodies, U(r, c1, c2, c3; params).

    ``r = |r_j - r_i|``, ``c1 = (e, nu_i)``, ``c2 = (e, nu_j)``, ``c3 = (nu_i, nu_j)``
    (see :mod:`poissonkit.conventions`). Plugins contribute energies, never forces: the
    numerics derive forces and torques from the partial derivatives.

    Attributes
    ----------
    expr
        ``expr(params) -> sympy.Expr`` in the symbols ``r, c1, c2, c3`` (``sympy.Symbol`` with
        those names, real). Provide it when U has closed form; the numerics differentiate it
        once and compile.
    kernel
        ``kernel(params) -> f`` returning a compiled (numba ``njit``) scalar function
        ``f(r, c1, c2, c3) -> (U, U_r, U_c1, U_c2, U_c3)``. Required when there is no closed form
        (e.g. exact cylinders by quadrature); optional otherwise.
    orientation
        ``"both"`` if U depends on both axes, ``"first"``/``"second"`` if only on one, ``"none"``
        for a central potential (point masses).
    """

    expr: Callable[[dict[str, Any]], Any] | None = None
    kernel: Callable[[dict[str, Any]], Callable[..., Any]] | None = None
    orientation: str = "both"


@dataclass(frozen=True)
class Assembly(Entry):
    """A builder of N-body arrangements (a networkx graph whose nodes carry bodies).

    ``build(**params) -> networkx.Graph``; node attributes and edge attributes are documented
    by the N-body plugin.
    """

    build: Callable[..., Any] = field(default=lambda **_: None)


@dataclass(frozen=True)
class SystemEntry(Entry):
    """A named Poisson structure or (conformally) Hamiltonian system, for ``poissonkit verify``.

    ``build(**params)`` returns a :class:`poissonkit.structure.Bivector` or a
    :class:`poissonkit.structure.HamiltonianSystem`. ``tags`` groups entries (``"lie-poisson"``,
    ``"nonholonomic"``, ...).
    """

    build: Callable[..., Any] = field(default=lambda **_: None)
    tags: tuple[str, ...] = ()


@dataclass(frozen=True)
class IntegratorEntry(Entry):
    """A time integrator. ``factory(**params)`` returns an object following the integrator
    contract of :mod:`poissonkit.numerics`. ``order`` is the classical order (0 if adaptive
    with variable order); ``family`` is e.g. ``"splitting"``, ``"implicit"``, ``"scipy"``."""

    factory: Callable[..., Any] = field(default=lambda **_: None)
    order: int = 0
    family: str = ""


@dataclass(frozen=True)
class SceneEntry(Entry):
    """A built-in scene: ``path`` to its TOML file (or ``load()`` returning a scene object)."""

    load: Callable[[], Any] = field(default=lambda: None)
