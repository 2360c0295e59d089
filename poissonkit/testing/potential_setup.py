"""What the potential checks evaluate: example parameters, the compiled kernels and their
pair-swap, all from the project's own machinery (:mod:`poissonkit.numerics.potentials`)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from poissonkit.errors import InputError
from poissonkit.plugin.contributions import PairPotential
from poissonkit.testing.geometry import Partials


@dataclass(frozen=True)
class Options:
    """Settings shared by the potential checks.

    Attributes
    ----------
    samples
        Random configurations per check.
    seed
        Seed of the configurations.
    rtol
        Relative tolerance of the finite-difference gradient (central differences, steps
        ``1e-4 |r|`` and ``1e-4`` rad: truncation about 1e-8 relative).
    exact
        Relative tolerance of comparisons that should hold to round-off (symmetry, the
        parameter kernel against the constant kernel, momentum of the kick).
    """

    samples: int = 6
    seed: int = 0
    rtol: float = 1e-5
    exact: float = 1e-9



#: Example values of required float parameters of the first and second body: different, so
#: that a swap of the bodies that forgets to swap their parameters shows.
FIRST, SECOND = 1.0, 1.25


@dataclass(frozen=True)
class Setup:
    """A potential with example parameters.

    Attributes
    ----------
    entry
        The registry entry.
    params
        Its resolved parameters (every one, bound ones included).
    swap
        ``{name: partner}`` of the per-body parameters (``moment1`` ↔ ``moment2``); empty when
        the two bodies are not alike (a mixed pair such as a cylinder and a dipole).
    distances
        Range of centre distances sampled [m].
    """

    entry: PairPotential
    params: dict[str, Any]
    swap: dict[str, str]
    distances: tuple[float, float]

    def kernel(self, params: Mapping[str, Any] | None = None) -> Partials:
        """The constant kernel (every parameter compiled in) for ``params`` (default: own)."""
        from poissonkit.numerics.potentials import compile_potential

        kern = compile_potential(self.entry, dict(self.params if params is None else params))
        return kern  # type: ignore[return-value]

    def swapped_params(self) -> dict[str, Any]:
        """The parameters with the two bodies' values exchanged."""
        return {self.swap.get(k, k): v for k, v in self.params.items()}


def _example(p_name: str, p_type: str) -> Any:
    if p_type == "float":
        return SECOND if p_name.endswith("2") else FIRST
    if p_type == "int":
        return 1
    if p_type == "bool":
        return False
    if p_type == "vector":
        return (1.0, 0.0, 0.0)
    raise InputError(f"parameter {p_name!r} ({p_type}) has no default; give it in params=")


def body_swap(entry: PairPotential) -> dict[str, str]:
    """``{x1: x2, x2: x1}`` for every per-body parameter pair, when every parameter ending in
    ``1`` or ``2`` has its partner (else ``{}``: the bodies are not alike)."""
    names = {p.name for p in entry.params}
    ended = {n for n in names if n[-1:] in ("1", "2")}
    swap = {n: n[:-1] + ("2" if n.endswith("1") else "1") for n in ended}
    if not all(v in names for v in swap.values()):
        return {}
    return swap


def setup(entry: PairPotential, params: Mapping[str, Any] | None = None,
          distances: tuple[float, float] | None = None) -> Setup:
    """Example parameters (given ones, defaults, then :data:`FIRST`/:data:`SECOND` for
    required floats) and distances: 3 to 6 times the largest length parameter (1 m without
    one), so bodies of those sizes do not touch."""
    given = dict(params or {})
    for p in entry.params:
        if p.name not in given and p.default is None and not p.optional:
            given[p.name] = _example(p.name, p.type)
    resolved = entry.resolve_params(given)
    if distances is None:
        lengths = [float(resolved[p.name]) for p in entry.params
                   if p.unit == "m" and p.type == "float" and p.name in resolved]
        scale = max(lengths, default=1.0)
        distances = (3.0 * scale, 6.0 * scale)
    return Setup(entry, resolved, body_swap(entry), distances)
