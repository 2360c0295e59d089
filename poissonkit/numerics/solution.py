"""The result of :func:`~poissonkit.numerics.solve`, with its diagnostics."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from poissonkit._display import PrettyPrinter, html_table, latex_table, text_block
from poissonkit.contracts import (CompiledFrom, HasBodyMomenta, HasCasimirs, HasEnergy, HasLayout,
                                  HasName, HasScales)
from poissonkit.errors import InputError, MissingDependencyError
from poissonkit.numerics import diagnostics
from poissonkit.numerics.diagnostics import Drift
from poissonkit.numerics.events import EventRecord
from poissonkit.numerics.units import Scales
from poissonkit.numerics.unitsystem import units_of
from poissonkit.traits import offers

if TYPE_CHECKING:
    from poissonkit.numerics.elements import OrbitalElements

#: Invariants :meth:`Solution.plot` can draw: name -> (method, legend label).
DRIFTS: dict[str, tuple[str, str]] = {
    "energy": ("energy_error", "|ΔH|/|H|"),
    "casimirs": ("casimir_drift", "Casimir drift"),
    "momentum": ("linear_momentum_drift", "|ΔP|/max|p_i(0)|"),
    "angular_momentum": ("angular_momentum_drift", "|Δj|/(Σ|r×p|+Σ|m|)"),
}


#: SI unit of the kinds of internal unit :meth:`Solution.to_xarray` records.
_SI_UNITS = {"length": "m", "mass": "kg", "time": "s", "momentum": "kg m s-1",
             "angular_momentum": "kg m2 s-1", "energy": "J"}


@dataclass
class Solution:
    """Saved states of a run plus what produced them.

    Attributes
    ----------
    t
        Saved times, shape ``(n,)`` (internal time unit; always includes start and end).
    y
        Saved states, shape ``(n, dim)``.
    method
        Integrator name.
    steps
        Number of steps taken.
    wall_time
        Seconds spent integrating (excluding compilation when the kernels were warm).
    system
        The system integrated (for the diagnostics).
    nfev
        Right-hand-side / force evaluations.
    events
        :class:`~poissonkit.numerics.events.EventRecord` of events that stopped the run.
    step, tol
        What was asked for.
    message
        Integrator status message.
    """

    t: np.ndarray
    y: np.ndarray
    method: str
    steps: int
    wall_time: float
    system: HasEnergy | None = None
    nfev: int = 0
    events: list[EventRecord] = field(default_factory=list)
    step: float | None = None
    tol: float | None = None
    message: str = ""
    extra: dict[str, Any] = field(default_factory=dict)

    @property
    def y_final(self) -> np.ndarray:
        """The last saved state."""
        return self.y[-1]

    # ------------------------------------------------------------------ diagnostics
    def energy(self) -> np.ndarray:
        """``H`` at every saved state."""
        return np.asarray(self.system.energy(self.y), dtype=float)

    def drifts(self) -> dict[str, Drift]:
        """Every diagnostic the system defines, absolute and relative with its scale
        (:func:`poissonkit.numerics.diagnostics.drifts`)."""
        return diagnostics.drifts(self.system, self.y)

    def energy_error(self, relative: bool = True) -> np.ndarray:
        """Energy error over time: relative, ``|H(t) − H(0)| / |H(0)|`` (absolute if
        ``H(0) = 0``; the default), or absolute, ``|H(t) − H(0)|`` (``relative=False``)."""
        found = diagnostics.energy_error(self.system, self.y)
        return found.relative if relative else found.absolute

    def casimir_drift(self) -> np.ndarray:
        """Relative Casimir drift ``max_k |ΔC_k| / s_k`` over time
        (:func:`~poissonkit.numerics.diagnostics.casimir_drift`); zeros if the system has none."""
        found = (diagnostics.casimir_drift(self.system, self.y)
                 if offers(self.system, HasCasimirs) else None)
        return np.zeros(len(self.t)) if found is None else found.relative

    def linear_momentum_drift(self) -> np.ndarray:
        """``|P(t) − P(0)| / max_i |p_i(0)|`` of the total linear momentum; zeros for a system
        that is not made of bodies."""
        if not offers(self.system, HasBodyMomenta):
            return np.zeros(len(self.t))
        return diagnostics.linear_momentum_drift(self.system, self.y).relative

    def momentum_drift(self) -> np.ndarray:
        """Same as :meth:`linear_momentum_drift` (the older name)."""
        return self.linear_momentum_drift()

    def angular_momentum_drift(self) -> np.ndarray:
        """``|j(t) − j(0)| / (Σ|r_i × p_i| + Σ|m_k|)`` of the total angular momentum (seed 000
        eq. 21) at ``t = 0``; zeros for a system that is not made of bodies."""
        if not offers(self.system, HasBodyMomenta):
            return np.zeros(len(self.t))
        return diagnostics.angular_momentum_drift(self.system, self.y).relative

    def orbital_elements(self, primary: int | str | None = "dominant") -> OrbitalElements:
        """Osculating orbital elements of every body at every saved state (REBOUND's names:
        ``a, e, inc, Omega, omega, M, f``; lengths in SI, or in the system's units for
        ``NBodySystem(units=...)``; radians), for a system of point masses under all-pairs
        gravity.

        Parameters
        ----------
        primary
            The body (name or index) the elements are about; ``None``: Jacobi elements in the
            order of the bodies (as REBOUND's ``orbits()``); ``"dominant"`` (default): about the
            body heavier than ten times all the others, Jacobi elements when there is none.

        Returns
        -------
        OrbitalElements
            Arrays of shape ``(time, bodies)``; ``nan`` for the primary.

        Raises
        ------
        InputError
            If the system is not point masses under gravity, or ``primary`` names no body.
        """
        from poissonkit.numerics.elements import system_elements

        return system_elements(self.system, self.y, primary)

    def _relative_drift(self, quantity: str) -> np.ndarray:
        """The relative drift named ``quantity`` (one of
        :data:`~poissonkit.numerics.diagnostics.QUANTITIES`) over time."""
        methods = {"energy_error": self.energy_error, "casimir_drift": self.casimir_drift,
                   "linear_momentum_drift": self.linear_momentum_drift,
                   "angular_momentum_drift": self.angular_momentum_drift}
        return methods[quantity]()

    def summary(self) -> dict[str, Any]:
        """Plain-data summary: method, steps, wall time, events, and for each diagnostic the
        system defines ``max_abs_*``, ``max_rel_*`` and ``*_scale``
        (:mod:`poissonkit.numerics.diagnostics`)."""
        out: dict[str, Any] = {
            "method": self.method,
            "steps": int(self.steps),
            "nfev": int(self.nfev),
            "wall_time": float(self.wall_time),
            "t_start": float(self.t[0]),
            "t_end": float(self.t[-1]),
            "saved": len(self.t),
            "step": self.step,
            "tol": self.tol,
            "message": self.message,
            "events": [e.__dict__ for e in self.events],
        }
        if self.system is not None:
            found = self.drifts()
            out.update(diagnostics.report(found))
            out["final_rel_energy_error"] = float(found["energy_error"].relative[-1])
        return out

    # ------------------------------------------------------------------ display
    def __repr__(self) -> str:
        return (f"Solution(method={self.method!r}, steps={int(self.steps)}, "
                f"t=[{float(self.t[0]):.6g}, {float(self.t[-1]):.6g}], saved={len(self.t)}, "
                f"dim={self.y.shape[-1] if self.y.ndim == 2 else 0})")

    def _rows(self) -> list[tuple[str, str]]:
        s = self.summary()
        rows = [("method", str(s["method"])), ("steps", str(s["steps"])),
                ("t", f"{s['t_start']:.6g} .. {s['t_end']:.6g} ({s['saved']} saved states)"),
                ("wall time", f"{s['wall_time']:.3g} s"),
                ("step" if s["step"] is not None else "tol",
                 f"{s['step'] if s['step'] is not None else s['tol']}")]
        for key, label in (("max_rel_energy_error", "max |ΔH|/|H|"),
                           ("max_rel_casimir_drift", "max Casimir drift"),
                           ("max_rel_linear_momentum_drift", "max |ΔP|/max|p_i(0)|"),
                           ("max_rel_angular_momentum_drift", "max |Δj|/(Σ|r×p|+Σ|m|)")):
            if key in s:  # only what the system defines
                rows.append((label, f"{s[key]:.2e}"))
        rows += [("event", f"{e.kind} at t = {e.time:.6g}") for e in self.events]
        if s["message"]:
            rows.append(("message", str(s["message"])))
        return rows

    def __str__(self) -> str:
        """Method, steps, time span, wall time and the largest invariant drifts."""
        return text_block(f"Solution ({self._system_name()})", self._rows())

    def _system_name(self) -> str:
        # a compiled system is named by the symbolic system it was compiled from
        named = (self.system.hamiltonian_system if offers(self.system, CompiledFrom)
                 else self.system)
        return str((named.name if offers(named, HasName) else "")
                   or type(self.system).__name__)

    def _repr_pretty_(self, p: PrettyPrinter, cycle: bool) -> None:
        p.text("Solution(...)" if cycle else str(self))

    def _repr_html_(self) -> str:
        """HTML table of :meth:`summary` (Jupyter)."""
        return html_table(f"Solution ({self._system_name()})", self._rows())

    def _repr_latex_(self) -> str:
        """:meth:`summary` as a LaTeX array."""
        return latex_table(self._rows())

    # ------------------------------------------------------------------ export
    def layout(self) -> tuple[str, ...]:
        """Names of the state components (the system's ``layout``, else ``y0 .. y{n-1}``)."""
        dim = self.y.shape[-1]
        layout = self.system.layout if offers(self.system, HasLayout) else None
        names = tuple(str(n) for n in (layout or ()))
        return names if len(names) == dim else tuple(f"y{i}" for i in range(dim))

    def to_xarray(self):
        """The run as an :class:`xarray.Dataset` (needs the optional ``xarray`` package).

        Returns
        -------
        xarray.Dataset
            ``y`` with dimensions ``(time, component)`` (component names from the system's
            layout; ``time`` as in ``poissonkit run``'s ``trajectory.nc``: seconds for a system
            in internal units, else the solver's time, with ``time_internal`` and the older
            name ``t`` the solver's time along it), the relative drifts ``energy_error``,
            ``casimir_drift``, ``linear_momentum_drift``, ``angular_momentum_drift`` along
            ``time`` when the system is known, and the run's
            method, steps, wall time, step and tolerance as attributes (``None`` left out, so
            the dataset writes to netCDF/zarr as is). For a system in internal units
            (:class:`~poissonkit.contracts.HasScales`) the SI value of one internal unit of
            each kind is an attribute ``internal_unit_<kind>`` (with ``..._units``), and
            ``t_si`` [s] a coordinate along ``time`` (the same values as ``time``). For a system
            in the user's units (``NBodySystem(units=...)``) ``time`` is in its time unit (its
            ``units`` attribute) and the attributes ``units_length``, ``units_time``,
            ``units_mass``, ``units_G`` name the units. (``poissonkit run`` writes the richer
            ``time × body × component`` form: :mod:`poissonkit.report.trajectory`.)

        Raises
        ------
        MissingDependencyError
            If xarray is not installed (``pip install xarray``).
        """
        try:
            import xarray as xr
        except ImportError:
            raise MissingDependencyError(
                "Solution.to_xarray needs xarray: pip install xarray") from None
        data = {"y": (("time", "component"), np.asarray(self.y, dtype=float))}
        if self.system is not None:
            for name in diagnostics.QUANTITIES:
                data[name] = (("time",), np.asarray(self._relative_drift(name), dtype=float))
        attrs = {"method": self.method, "steps": int(self.steps), "nfev": int(self.nfev),
                 "wall_time": float(self.wall_time), "step": self.step, "tol": self.tol,
                 "message": self.message, "system": self._system_name() if self.system else None}
        t = np.asarray(self.t, dtype=float)
        # the dimension is "time", as in trajectory.nc; "t" stays readable as a coordinate
        coords: dict[str, object] = {"time": t, "time_internal": ("time", t), "t": ("time", t),
                                     "component": list(self.layout())}
        scales = self.system.scales if offers(self.system, HasScales) else None
        if isinstance(scales, Scales):
            for kind, unit in _SI_UNITS.items():
                attrs[f"internal_unit_{kind}"] = float(scales.unit(kind))
                attrs[f"internal_unit_{kind}_units"] = unit
            t_si = t * float(scales.time)
            coords["time"] = ("time", t_si, {"units": "s"})
            coords["t_si"] = ("time", t_si, {"units": "s"})
        units = units_of(self.system)
        if not units.is_si:  # a system in the user's units (NBodySystem(units=...))
            coords["time"] = ("time", t, {"units": units.label("time", text=False)})
            attrs.update(units.attributes())
        return xr.Dataset(data, coords=coords,
                          attrs={k: v for k, v in attrs.items() if v is not None})

    def plot(self, ax=None, invariants=("energy", "casimirs", "angular_momentum"),
             kind: str = "drifts", components: Sequence[str] | None = None):
        """Plot the drift of the invariants against time, log scale, or the state itself.

        Parameters
        ----------
        ax
            A matplotlib ``Axes`` to draw on; a new figure is made if ``None``.
        invariants
            One or more of ``"energy"``, ``"casimirs"``, ``"momentum"``, ``"angular_momentum"``.
            Drifts that are zero throughout (e.g. a system without Casimirs) are skipped.
        kind
            ``"drifts"`` (the default: the invariants above) or ``"state"``: the state
            components against time (named by the system's layout).
        components
            With ``kind="state"``: the names of the components to draw (default: all).

        Returns
        -------
        matplotlib.axes.Axes
            The axes drawn on.

        Raises
        ------
        InputError
            For an unknown invariant, kind or component name, or drifts of a solution without
            its system.
        """
        if kind == "state":
            return self._plot_state(ax, components)
        if kind != "drifts":
            raise InputError(f"Solution.plot: kind must be 'drifts' or 'state', got {kind!r}")
        if self.system is None:
            raise InputError("Solution.plot needs the solution's system (solution.system)")
        if isinstance(invariants, str):  # one name, not its letters
            invariants = (invariants,)
        ax = _plot_axes(ax, "invariant", invariants, DRIFTS)
        t = np.asarray(self.t, dtype=float)
        for name in invariants:
            method, label = DRIFTS[name]
            values = np.asarray(self._relative_drift(method), dtype=float)
            if not np.any(values > 0):
                continue
            # zeros (e.g. at t = 0) cannot be drawn on a log axis
            ax.semilogy(t, np.where(values > 0, values, np.nan), label=label)
        ax.set_xlabel(_time_label(self.system))
        ax.set_ylabel("relative drift")
        ax.set_title(f"{self._system_name()}: {self.method}, {int(self.steps)} steps")
        if ax.get_legend_handles_labels()[0]:
            ax.legend(loc="best")
        return ax

    def _plot_state(self, ax, components: Sequence[str] | None):
        """:meth:`plot` with ``kind="state"``: each chosen state component against time."""
        names = self.layout()
        chosen = list(names) if components is None else (
            [components] if isinstance(components, str) else list(components))
        ax = _plot_axes(ax, "component", chosen, names)
        t = np.asarray(self.t, dtype=float)
        y = np.asarray(self.y, dtype=float)
        for name in chosen:
            ax.plot(t, y[:, names.index(name)], label=name)
        ax.set_xlabel(_time_label(self.system))
        ax.set_ylabel("state (internal units)")
        ax.set_title(f"{self._system_name()}: {self.method}, {int(self.steps)} steps")
        if 0 < len(chosen) <= 12:  # a legend of a whole N-body state would hide the plot
            ax.legend(loc="best", fontsize="small")
        return ax


def _time_label(system: object) -> str:
    """The time axis label of :meth:`Solution.plot`: the system's time unit when it has one."""
    units = units_of(system)
    return "t (internal units)" if units.is_si else f"t [{units.label('time')}]"


def _plot_axes(ax, what: str, chosen: Sequence[str], available: Sequence[str]):
    """The axes :meth:`Solution.plot` draws on (new ones if ``ax`` is ``None``), after checking
    that every ``chosen`` name is ``available``."""
    unknown = [c for c in chosen if c not in available]
    if unknown:
        raise InputError(f"Solution.plot: unknown {what} {unknown[0]!r}; available: "
                         f"{', '.join(available)}")
    if ax is None:
        import matplotlib.pyplot as plt

        _fig, ax = plt.subplots(figsize=(6.4, 3.6))
    return ax
