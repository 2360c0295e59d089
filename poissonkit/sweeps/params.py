"""What a sweep varies: parameter axes (grids, explicit lists) and seeded random samples.

A parameter is named by its *path* in the scene (``bodies.right.r.0``, ``run.step``,
``interactions.params.mu0``) or, for the built-in seed 000 scene, by one of its named
parameters (``spin_ratio``, ``tilt``, ``radius_factor``, ``momentum_factor``, also written
``initial.tilt``); see ``docs/sweeps.md``. A sweep is either a full grid over one or more axes
(one dataset dimension per axis) or ``n`` random points drawn uniformly from ranges with a fixed
seed (one dimension ``sample``).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from poissonkit.errors import InputError


@dataclass(frozen=True)
class Axis:
    """One swept parameter: its scene path and the values it takes (a grid or a list)."""

    path: str
    values: tuple[float, ...]

    def __post_init__(self) -> None:
        if not isinstance(self.path, str) or not self.path.strip():
            raise InputError(f"sweep parameter path must be a non-empty string, got {self.path!r}")
        vals = tuple(_finite(v, self.path) for v in self.values)
        if not vals:
            raise InputError(f"sweep parameter {self.path}: give at least one value")
        if len(set(vals)) != len(vals):
            raise InputError(f"sweep parameter {self.path}: values repeat ({list(vals)})")
        object.__setattr__(self, "values", vals)


@dataclass(frozen=True)
class Range:
    """A range ``[low, high]`` random samples of ``path`` are drawn from (uniformly)."""

    path: str
    low: float
    high: float

    def __post_init__(self) -> None:
        lo, hi = _finite(self.low, self.path), _finite(self.high, self.path)
        if not hi > lo:
            raise InputError(f"sweep parameter {self.path}: range needs low < high, "
                             f"got {lo:g}:{hi:g}")
        object.__setattr__(self, "low", lo)
        object.__setattr__(self, "high", hi)


def _finite(value: object, path: str) -> float:
    try:
        v = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise InputError(f"sweep parameter {path}: values must be numbers, got {value!r}") from None
    if not math.isfinite(v):
        raise InputError(f"sweep parameter {path}: values must be finite, got {value!r}")
    return v


def grid(path: str, start: float, stop: float, count: int) -> Axis:
    """``count`` evenly spaced values of ``path`` from ``start`` to ``stop`` (both included)."""
    if not isinstance(count, (int, np.integer)) or count < 1:
        raise InputError(f"sweep parameter {path}: count must be a positive integer, got {count!r}")
    a, b = _finite(start, path), _finite(stop, path)
    if count > 1 and a == b:
        raise InputError(f"sweep parameter {path}: start = stop with {count} points")
    return Axis(path, tuple(float(v) for v in np.linspace(a, b, int(count))))


@dataclass(frozen=True)
class Design:
    """The points of a sweep: a full grid over ``axes`` or ``samples`` random points in
    ``ranges`` (seeded), never both.

    Attributes
    ----------
    axes
        Grid axes, in dataset-dimension order.
    ranges, samples, seed
        Random design: ``samples`` points drawn uniformly from the ``ranges`` with
        ``numpy.random.default_rng(seed)``.
    """

    axes: tuple[Axis, ...] = ()
    ranges: tuple[Range, ...] = ()
    samples: int = 0
    seed: int = 0

    def __post_init__(self) -> None:
        if bool(self.axes) == bool(self.ranges):
            raise InputError("a sweep needs grid/list parameters or random ranges (not both, "
                             "not neither)")
        if self.ranges and (not isinstance(self.samples, (int, np.integer)) or self.samples < 1):
            raise InputError(f"random sweep: number of samples must be >= 1, got {self.samples!r}")
        paths = [a.path for a in self.axes] + [r.path for r in self.ranges]
        dup = {p for p in paths if paths.count(p) > 1}
        if dup:
            raise InputError(f"sweep parameter given twice: {', '.join(sorted(dup))}")

    @property
    def paths(self) -> tuple[str, ...]:
        """The swept parameter paths."""
        return tuple(a.path for a in self.axes) or tuple(r.path for r in self.ranges)

    @property
    def dims(self) -> tuple[str, ...]:
        """Dataset dimensions: one per grid axis, or ``("sample",)``."""
        return tuple(a.path for a in self.axes) if self.axes else ("sample",)

    @property
    def shape(self) -> tuple[int, ...]:
        """Shape of every outcome array."""
        return tuple(len(a.values) for a in self.axes) if self.axes else (int(self.samples),)

    @property
    def size(self) -> int:
        """Number of runs."""
        return int(np.prod(self.shape))

    def sample_values(self) -> dict[str, np.ndarray]:
        """Random design: the drawn value of each parameter at every sample (reproducible)."""
        rng = np.random.default_rng(self.seed)
        draws = rng.random((int(self.samples), len(self.ranges)))
        return {r.path: r.low + (r.high - r.low) * draws[:, k] for k, r in enumerate(self.ranges)}

    def points(self) -> Iterator[tuple[int, dict[str, float]]]:
        """``(flat index, {path: value})`` of every point in C order."""
        if self.axes:
            for k, vals in enumerate(itertools.product(*(a.values for a in self.axes))):
                yield k, dict(zip(self.paths, vals))
        else:
            cols = self.sample_values()
            for k in range(int(self.samples)):
                yield k, {p: float(cols[p][k]) for p in self.paths}

    def describe(self) -> dict[str, object]:
        """Plain data identifying the design (stored in the dataset; compared on resume)."""
        if self.axes:
            return {"kind": "grid", "axes": {a.path: list(a.values) for a in self.axes}}
        return {"kind": "random", "samples": int(self.samples), "seed": int(self.seed),
                "ranges": {r.path: [r.low, r.high] for r in self.ranges}}


def parse_param(text: str) -> Axis | Range:
    """Parse a command-line parameter.

    ``PATH=start:stop:count`` (grid), ``PATH=v1,v2,...`` (list; one value fixes it),
    ``PATH=low:high`` (range of a random sweep).

    Raises
    ------
    InputError
        Naming the parameter, if the text has none of these forms.
    """
    path, sep, spec = text.partition("=")
    path = path.strip()
    if not sep or not path or not spec.strip():
        raise InputError(f"--param expects PATH=start:stop:count, PATH=v1,v2,... or "
                         f"PATH=low:high, got {text!r}")
    if ":" in spec:
        parts = spec.split(":")
        if len(parts) == 3:
            try:
                count = int(parts[2])
            except ValueError:
                raise InputError(f"--param {path}: count must be an integer, got {parts[2]!r}"
                                 ) from None
            return grid(path, _finite(parts[0], path), _finite(parts[1], path), count)
        if len(parts) == 2:
            return Range(path, _finite(parts[0], path), _finite(parts[1], path))
        raise InputError(f"--param {path}: expected start:stop:count or low:high, got {spec!r}")
    return Axis(path, tuple(_finite(v, path) for v in spec.split(",") if v.strip()))


def design_from(params: Sequence[Axis | Range | str] | Mapping[str, object], *,
                samples: int | None = None, seed: int = 0) -> Design:
    """Build a :class:`Design` from axes/ranges, command-line strings, or a mapping
    ``{path: values}`` (a sequence of numbers, or ``(low, high)`` with ``samples`` given).
    """
    items: list[Axis | Range] = []
    if isinstance(params, Mapping):
        for path, v in params.items():
            if isinstance(v, (Axis, Range)):
                items.append(v)
            elif samples is not None:
                try:
                    lo, hi = v  # type: ignore[misc]
                except (TypeError, ValueError):
                    raise InputError(f"random sweep: {path} needs (low, high), got {v!r}") from None
                items.append(Range(str(path), lo, hi))
            else:
                if isinstance(v, (str, bytes)) or not isinstance(v, (Sequence, np.ndarray)):
                    raise InputError(f"sweep parameter {path}: give a sequence of values, "
                                     f"got {v!r}")
                items.append(Axis(str(path), tuple(v)))
    else:
        for p in params:
            items.append(parse_param(p) if isinstance(p, str) else p)
    axes = tuple(i for i in items if isinstance(i, Axis))
    ranges = tuple(i for i in items if isinstance(i, Range))
    if ranges and samples is None:
        raise InputError(f"parameter {ranges[0].path} is a range low:high; give the number of "
                         "random samples (--random N) or a grid start:stop:count")
    if samples is not None:
        if axes:
            raise InputError(f"random sweep: {axes[0].path} must be a range low:high")
        return Design(ranges=ranges, samples=samples, seed=int(seed))
    return Design(axes=axes)
