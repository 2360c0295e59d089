"""The input model of an N-body system: bodies and the pairs that interact, validated on entry."""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Union

from poissonkit import contracts
from poissonkit.errors import InputError
from poissonkit.traits import SystemTraits
from poissonkit.validation import finite_number, positive_number, vector3

#: The contracts every system of moving bodies fulfils (two bodies and N bodies alike);
#: a system class extends them with what it adds (:meth:`SystemTraits.extended`).
BODY_SYSTEM_TRAITS = SystemTraits(
    contracts.NumericsSystem, contracts.HasCompiledKernels, contracts.HasLayout,
    contracts.HasStateCheck, contracts.HasOverlapCheck, contracts.HasCasimirs,
    contracts.HasCasimirScales, contracts.HasMomenta, contracts.HasEnergy,
    contracts.HasBodyMomenta, contracts.HasPoissonStructure, contracts.HasUnpack,
    contracts.HasScales, contracts.HasKineticSplit)

if TYPE_CHECKING:
    import sympy as sp
    from numba.core.dispatcher import Dispatcher

    from poissonkit.plugin.contributions import PairPotential

#: What a pair potential may be given as: a registry entry, its registry name, a sympy
#: expression in ``r, c1, c2, c3`` or a compiled kernel ``f(r, c1, c2, c3) -> (U, U_r, U_c1,
#: U_c2, U_c3)`` (see :func:`poissonkit.numerics.nbody.pairkernels.resolve_kernel`).
PotentialLike = Union["PairPotential", str, "sp.Basic", "Dispatcher"]

#: Per-body quantities as given: a mapping or pairs ``name -> number``.
AttributesLike = Union[Mapping[str, float], Iterable[tuple[str, float]]]


class NonUnitAxisError(InputError):
    """A top's axis ``ν`` is not a unit vector (pass ``normalize=True`` to normalise it)."""


def _vector3(value: object, what: str) -> tuple[float, float, float]:
    """``value`` as a finite 3-tuple of floats, else :class:`InputError` naming ``what``."""
    a = vector3(value, what)
    return (float(a[0]), float(a[1]), float(a[2]))


@dataclass(frozen=True)
class Body:
    """A rigid body: symmetric top (``alpha`` given) or point mass (``alpha=None``).

    Parameters
    ----------
    name
        Unique name; coordinates are called ``name.r_x`` etc.
    mass
        Mass [kg] (or the unit of the system's ``units``, e.g. M☉ for
        ``NBodySystem(..., units=("AU", "yr", "Msun"))``; the internal unit with scales), > 0.
        Every other number of a body is in the system's units likewise.
    alpha
        ``1 / I_perp`` [1/(kg m²)], > 0, or ``None`` for a point mass.
    fixed
        Fixed bodies carry no degrees of freedom; they act through their pairs.
    position, axis
        Position [m] and unit axis of a fixed body (required when ``fixed``).
    attributes
        Further per-body quantities (SI) that pair potentials may take from the body, e.g.
        ``{"charge": 1e-9}`` or ``{"moment": 0.15}`` (see ``PairPotential.body_params``);
        stored as sorted ``(name, value)`` pairs. ``mass`` and ``alpha`` are always available.
    """

    name: str
    mass: float
    alpha: float | None = None
    fixed: bool = False
    position: tuple[float, float, float] | None = None
    axis: tuple[float, float, float] | None = None
    attributes: AttributesLike = ()

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise InputError(f"body name must be a non-empty string, got {self.name!r}")
        checked = [("mass", self.mass)]
        if self.alpha is not None:
            checked.append(("alpha", self.alpha))
        for attr, v in checked:
            object.__setattr__(self, attr, positive_number(v, f"body {self.name!r}: {attr}"))
        if self.fixed and self.position is None:
            raise InputError(f"fixed body {self.name!r} needs a position")
        if self.fixed and self.alpha is not None and self.axis is None:
            raise InputError(f"fixed top {self.name!r} needs an axis")
        if self.position is not None:
            object.__setattr__(self, "position",
                               _vector3(self.position, f"body {self.name!r}: position"))
        if self.axis is not None:
            axis = _vector3(self.axis, f"body {self.name!r}: axis")
            if not any(axis):
                raise NonUnitAxisError(f"body {self.name!r}: axis must be non-zero, got {axis}")
            object.__setattr__(self, "axis", axis)
        attrs = self.attributes
        items = attrs.items() if isinstance(attrs, Mapping) else attrs
        try:
            named = [(str(k), v) for k, v in items]
        except (TypeError, ValueError):
            raise InputError(f"body {self.name!r}: attributes must be a mapping name -> number, "
                             f"got {attrs!r}") from None
        clean = []
        for k, v in sorted(named):
            v = finite_number(v, f"body {self.name!r}: attribute {k!r}")
            if k in ("mass", "alpha"):
                raise InputError(f"body {self.name!r}: {k!r} is a field of the body, not an "
                                 "attribute")
            clean.append((k, v))
        object.__setattr__(self, "attributes", tuple(clean))

    def attribute(self, name: str) -> float:
        """Value of a per-body quantity (``mass``, ``alpha`` or one of :attr:`attributes`).

        Raises
        ------
        InputError
            If the body does not have it (the message names the body and the quantity).
        """
        if name == "mass":
            return float(self.mass)
        if name == "alpha" and self.alpha is not None:
            return float(self.alpha)
        for k, v in self.attributes:  # sorted (name, value) pairs after __post_init__
            if k == name:
                return v
        raise InputError(f"body {self.name!r} has no {name!r}, which a pair potential takes from "
                         f"each body; give it (Body(..., attributes={{{name!r}: ...}}) or the "
                         "potential's parameter explicitly")

    @property
    def is_top(self) -> bool:
        """Whether the body carries an orientation (ν, m)."""
        return self.alpha is not None


@dataclass(frozen=True)
class Interaction:
    """One interacting pair ``(i, j)`` (indices or names of bodies) with its potential.

    ``potential`` is a :class:`~poissonkit.plugin.PairPotential`, a registry name, a sympy
    expression in ``r, c1, c2, c3`` or a compiled kernel ``f(r, c1, c2, c3) -> (U, U_r, U_c1,
    U_c2, U_c3)``; ``params`` are the potential's parameters (SI).
    """

    i: int | str
    j: int | str
    potential: PotentialLike
    params: Mapping[str, object] = field(default_factory=dict)


@dataclass(frozen=True)
class AllPairs:
    """Every pair of ``members`` (default: all bodies) interacting through one potential.

    Never builds the O(N²) pair list; with a system cutoff it uses a compiled cell list.
    """

    potential: PotentialLike
    params: Mapping[str, object] = field(default_factory=dict)
    members: Sequence[int | str] | None = None
