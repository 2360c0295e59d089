"""The plot registry of ``poissonkit run``: which figures a run gets is decided by what it has.

A :class:`PlotEntry` names a figure, the kinds of scene it is drawn for
(:attr:`PlotEntry.kinds`, names of :mod:`poissonkit.report.scene_kind`: two bodies, N bodies,
bodies in fields, planetary), says when it applies to a run of those kinds
(:attr:`PlotEntry.applies`, a predicate on :class:`RunData`) and draws it
(:attr:`PlotEntry.draw`, returning a matplotlib ``Figure``). The core registers its entries in
:data:`PLOTS` on import; a plugin adds its own with :func:`register_plot` (no hook is needed:
importing the plugin registers them).

>>> from poissonkit.report.figures import PLOTS
>>> "drifts" in PLOTS
True
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from poissonkit.contracts import HasBodies
from poissonkit.errors import InputError
from poissonkit.report.summary import Diagnostics
from poissonkit.traits import offers

__all__ = ["PLOTS", "PlotEntry", "RunData", "figures_for", "register_plot", "write_figures"]


@dataclass(frozen=True)
class RunData:
    """What a figure may draw from: the saved states of a run and its description.

    Attributes
    ----------
    system
        The integrated system.
    t
        Saved times, internal units, shape ``(n,)``.
    y
        Saved states, internal units, shape ``(n, dim)``.
    diag
        The run's :class:`~poissonkit.report.summary.Diagnostics` at the same times.
    time_unit
        SI value of the internal time unit [s].
    name
        Scene name (figure titles).
    metadata
        The run's metadata (``"plan"``: the model plan of a planned scene).
    shapes
        ``{body name: (radius, half_length)}`` (internal length unit) of finite-size bodies.
    relative
        Relative position ``r2 − r1`` [m] of a two-body run (``None`` otherwise).
    jz
        z-component of the total angular momentum [J s] (two-body figures).
    elements
        Orbital elements against time (``{"a": (n, bodies), "e": ..., "inc": ...}``, SI and
        radians) of a planetary run whose dataset has them, else ``None`` (no element figure).
    """

    system: object
    t: np.ndarray
    y: np.ndarray
    diag: Diagnostics
    time_unit: float = 1.0
    name: str = ""
    metadata: Mapping[str, object] = field(default_factory=dict)
    shapes: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    relative: np.ndarray | None = None
    jz: np.ndarray | None = None
    elements: Mapping[str, np.ndarray] | None = None

    @property
    def kind(self) -> str:
        """The kind of scene (:func:`poissonkit.report.scene_kind.scene_kind`)."""
        from poissonkit.report.scene_kind import scene_kind

        return scene_kind(self.system, relative=self.relative is not None)

    @property
    def t_s(self) -> np.ndarray:
        """Saved times [s]."""
        return np.asarray(self.t) * self.time_unit

    @property
    def n_bodies(self) -> int:
        """Number of bodies, fixed ones included (2 for the seed's two-body form)."""
        if offers(self.system, HasBodies):
            return len(self.system.bodies)
        return 2 if self.relative is not None else 0

    @property
    def plan(self) -> Mapping[str, object] | None:
        """The model plan of a planned scene, or ``None``."""
        plan = self.metadata.get("plan")
        return plan if isinstance(plan, Mapping) else None


Draw = Callable[[RunData], object]  # returns a matplotlib Figure


@dataclass(frozen=True)
class PlotEntry:
    """One registered figure.

    Attributes
    ----------
    name
        File stem (``<name>.png``) and registry key.
    applies
        ``applies(run)`` is true when the figure makes sense for the run.
    draw
        ``draw(run)`` returns a matplotlib ``Figure``.
    kinds
        The kinds of scene it is drawn for (``None``: every kind).
    """

    name: str
    applies: Callable[[RunData], bool]
    draw: Draw
    kinds: frozenset[str] | None = None


#: Registered figures, in drawing order.
PLOTS: dict[str, PlotEntry] = {}


def register_plot(name: str, applies: Callable[[RunData], bool], draw: Draw, *,
                  replace: bool = False, kinds: Iterable[str] | None = None) -> PlotEntry:
    """Add a figure to :data:`PLOTS`.

    Parameters
    ----------
    name
        File stem and key.
    applies, draw
        See :class:`PlotEntry`.
    replace
        Allow replacing an entry of the same name.
    kinds
        Kinds of scene (:data:`poissonkit.report.scene_kind.KINDS`) the figure is drawn for;
        default every kind.

    Raises
    ------
    InputError
        If ``name`` is taken and ``replace`` is false, or a kind is unknown.
    """
    from poissonkit.report.scene_kind import KINDS

    if name in PLOTS and not replace:
        raise InputError(f"a plot named {name!r} is already registered")
    wanted = None if kinds is None else frozenset(kinds)
    if wanted is not None and not wanted <= set(KINDS):
        raise InputError(f"plot {name!r}: unknown scene kind(s) {sorted(wanted - set(KINDS))} "
                         f"(kinds: {', '.join(KINDS)})")
    entry = PlotEntry(name, applies, _in_run_units(draw), wanted)
    PLOTS[name] = entry
    return entry


def _in_run_units(draw: Draw) -> Draw:
    """``draw`` with its axes in the units of the run's scene
    (:func:`~poissonkit.report.axis_units.scene_units`)."""
    import functools

    @functools.wraps(draw)
    def drawn(run: RunData) -> object:
        from poissonkit.report.axis_units import scene_units
        from poissonkit.report.run_units import unit_system

        with scene_units(unit_system(run.metadata)):
            return draw(run)
    return drawn


def figures_for(run: RunData) -> list[PlotEntry]:
    """The registered figures that apply to ``run``, in registration order."""
    _load_builtin()
    kind = run.kind
    return [e for e in PLOTS.values()
            if (e.kinds is None or kind in e.kinds) and e.applies(run)]


def write_figures(outdir: str | Path, run: RunData) -> Sequence[Path]:
    """Draw every figure that applies to ``run`` into ``outdir/<name>.png``; return the paths."""
    from poissonkit.report.plotkit import save

    out = Path(outdir)
    return [save(e.draw(run), out / f"{e.name}.png") for e in figures_for(run)]


def _load_builtin() -> None:
    # the built-in entries register themselves on import
    import poissonkit.report.field_plots
    import poissonkit.report.nbody_plots
    import poissonkit.report.planet_plots
    import poissonkit.report.plots  # noqa: F401
