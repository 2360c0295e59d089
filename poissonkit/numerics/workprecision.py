"""Speed against error: reference solution, method sweeps, time-to-error tables, CSV and PNG.

Usage (what ``poissonkit bench`` does)::

    ref = reference(system, y0, t_end)                 # two methods, their agreement reported
    pts = sweep(system, y0, t_end, ref, plan(...))     # every method over steps / tolerances
    write_csv("wp.csv", pts); plot("wp.png", pts)
    time_to_error(pts, 1e-6)                           # {method: seconds or None}

Error measure (nondimensional, relative): the final state is cut into its 3-vectors
(``r_k, p_k, ν_k, m_k``) and the error is ``max_blocks |Δ block| / |block_ref|`` (blocks whose
reference norm is below ``1e-12`` of the largest use the largest norm instead). Unlike a plain
``|Δy|/|y|`` this is not diluted by large blocks (fast spins carry ``|m| ≫ |p|``).

Wall time is the solver's own ``wall_time`` after a warm-up call of the same method, so
one-time compilation is excluded.
"""

from __future__ import annotations

import csv
import math
import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from poissonkit.contracts import HasEnergy, HasRunCost, Solver, Trajectory
from poissonkit.errors import InputError, PoissonkitError
from poissonkit.numerics.diagnostics import energy_error

__all__ = [
    "Reference", "Solver", "WorkPoint", "final_state_error", "method_kind", "plan", "plot",
    "read_csv", "reference", "sweep", "table", "time_to_error", "write_csv",
]


def _default_solver() -> Solver:
    from poissonkit.numerics.solver import solve

    return solve


def final_state_error(y: np.ndarray, y_ref: np.ndarray) -> float:
    """Block-relative error of a final state (see the module docstring).

    Raises
    ------
    InputError
        If the shapes differ or the length is not a multiple of 3.
    """
    y = np.asarray(y, dtype=float).reshape(-1)
    y_ref = np.asarray(y_ref, dtype=float).reshape(-1)
    if y.shape != y_ref.shape or y.size % 3:
        raise InputError("states must have equal length divisible by 3, "
                         f"got {y.shape}, {y_ref.shape}")
    if not np.all(np.isfinite(y)):
        return math.inf
    d = np.linalg.norm((y - y_ref).reshape(-1, 3), axis=1)
    s = np.linalg.norm(y_ref.reshape(-1, 3), axis=1)
    floor = 1e-12 * float(s.max()) if s.max() > 0 else 1.0
    s = np.where(s > floor, s, float(s.max()) or 1.0)
    return float(np.max(d / s))


def _final(sol: Trajectory) -> np.ndarray:
    y = np.asarray(sol.y, dtype=float)
    t = np.asarray(sol.t, dtype=float)
    if y.ndim == 1:
        return y
    if y.shape[0] == t.shape[0]:
        return y[-1]
    return y[:, -1]


def _max_rel_energy_error(system: HasEnergy, t: np.ndarray, y: np.ndarray) -> float:
    """``max_rel_energy_error`` of :mod:`poissonkit.numerics.diagnostics` over the saved states
    ``y`` (rows or, from other solvers, columns)."""
    y = np.asarray(y, dtype=float)
    rows = y if y.shape[0] == np.asarray(t).shape[0] else y.T
    return energy_error(system, rows).max_relative


@dataclass(frozen=True)
class Reference:
    """A high-accuracy final state and how well two independent methods agree on it.

    Attributes
    ----------
    y_end
        The reference final state (from ``primary``).
    primary, secondary
        ``(method, setting_kind, setting)`` of the two solves.
    agreement
        :func:`final_state_error` of the secondary against the primary.
    wall_time
        Seconds spent on both.
    """

    y_end: np.ndarray
    primary: tuple[str, str, float]
    secondary: tuple[str, str, float]
    agreement: float
    wall_time: float


def _call(solver: Solver, system: HasEnergy, y0: ArrayLike, t_end: float, method: str,
          kind: str, value: float, save_every: int) -> Trajectory:
    kw: dict[str, object] = {"method": method, "progress": False, "save_every": save_every}
    kw["step" if kind == "step" else "tol"] = value
    return solver(system, y0, t_end, **kw)


def method_kind(method: str) -> str:
    """``"step"`` for fixed-step methods (splitting, midpoint), ``"tol"`` for adaptive ones,
    from the integrator registry (``family``/``order``; unknown names default to ``"tol"``)."""
    try:
        from poissonkit.plugin import integrator

        e = integrator(method)
    except PoissonkitError:
        return "step" if method.startswith(("splitting", "midpoint", "verlet")) else "tol"
    fam = e.family
    if fam in ("scipy", "adaptive") or "adaptive" in fam:
        return "tol"
    return "step"


def reference(system: HasEnergy, y0: ArrayLike, t_end: float, *,
              primary: tuple[str, str, float] | None = None,
              secondary: tuple[str, str, float] | None = None, solver: Solver | None = None
              ) -> Reference:
    """Compute a reference final state with two independent methods.

    Defaults: ``splitting8`` with step ``T/20000`` of the run (``t_end/20000`` capped at 5e-3
    internal units) as the primary, scipy ``dop853`` at ``tol = 1e-13`` as the check.

    Raises
    ------
    IntegrationError
        Propagated from the solver.
    """
    solver = solver or _default_solver()
    if not (math.isfinite(t_end) and t_end > 0):
        raise InputError(f"t_end must be positive, got {t_end!r}")
    primary = primary or ("splitting8", "step", min(5e-3, t_end / 20000))
    secondary = secondary or ("dop853", "tol", 1e-13)
    w = time.perf_counter()
    a = _call(solver, system, y0, t_end, *primary, save_every=10**9)
    b = _call(solver, system, y0, t_end, *secondary, save_every=10**9)
    ya, yb = _final(a), _final(b)
    return Reference(y_end=ya, primary=primary, secondary=secondary,
                     agreement=final_state_error(yb, ya), wall_time=time.perf_counter() - w)


@dataclass(frozen=True)
class WorkPoint:
    """One solve of the sweep."""

    method: str
    kind: str
    setting: float
    steps: int
    wall_time: float
    final_error: float
    max_rel_energy_error: float
    note: str = ""

    @property
    def max_energy_error(self) -> float:
        """Same as ``max_rel_energy_error`` (the older name)."""
        return self.max_rel_energy_error


def plan(methods: Iterable[str], t_end: float, *, step_range: tuple[float, float] = (0.5, 0.005),
         tols: Sequence[float] = (1e-4, 1e-6, 1e-8, 1e-10, 1e-12), n_steps: int = 6
         ) -> dict[str, tuple[str, list[float]]]:
    """Default sweep: fixed-step methods over ``n_steps`` log-spaced steps in ``step_range``
    (internal time), adaptive ones over ``tols``."""
    out: dict[str, tuple[str, list[float]]] = {}
    for m in methods:
        kind = method_kind(m)
        if kind == "step":
            hs = np.geomspace(step_range[0], step_range[1], n_steps)
            out[m] = ("step", [float(t_end / math.ceil(t_end / h)) for h in hs])
        else:
            out[m] = ("tol", list(tols))
    return out


def sweep(system: HasEnergy, y0: ArrayLike, t_end: float, ref: Reference,
          settings: Mapping[str, tuple[str, Sequence[float]]], *, solver: Solver | None = None,
          repeats: int = 1, time_budget: float | None = None,
          on_point: Callable[[WorkPoint], None] | None = None) -> list[WorkPoint]:
    """Solve with every method and setting; one :class:`WorkPoint` each.

    Parameters
    ----------
    settings
        ``{method: (kind, values)}`` with ``kind`` ``"step"`` or ``"tol"`` (see :func:`plan`).
    repeats
        Best-of-``repeats`` wall time per point (solves faster than 0.2 s are repeated until
        0.2 s were spent, at most 20 times).
    time_budget
        Stop refining a method once one solve took longer than this many seconds.
    on_point
        Called with each point as it is measured (progress output).

    A method that fails (typed poissonkit error) at some setting is recorded with infinite error
    and the message in ``note``; a method that cannot even start (any exception in its warm-up)
    gets one such point and is skipped.
    """
    solver = solver or _default_solver()
    pts: list[WorkPoint] = []
    for method, (kind, values) in settings.items():
        # warm-up: compile kernels and caches outside the timed region
        try:  # the finest setting: the one least likely to fail on its own
            _call(solver, system, y0, min(t_end, 1e-2), method, kind, float(values[-1]), 10**9)
        except PoissonkitError:
            pass  # a typed failure: each point records its own outcome below
        except Exception as exc:  # noqa: BLE001 - a broken method must not stop the sweep
            p = WorkPoint(method, kind, float(values[0]), 0, math.inf, math.inf, math.inf,
                          f"{type(exc).__name__}: {exc}")
            pts.append(p)
            if on_point:
                on_point(p)
            continue
        for v in values:
            best, sol, note = math.inf, None, ""
            err = eerr = math.inf
            steps = 0
            try:
                # best of `repeats`; fast solves are repeated until 0.2 s were spent (at most
                # 20 runs): the minimum is robust against other load on the machine
                k, spent = 0, 0.0
                while k < max(1, repeats) or (spent < 0.2 and k < 20):
                    w = time.perf_counter()
                    sol = _call(solver, system, y0, t_end, method, kind, float(v), 10**9)
                    # a solver that does not time itself (scipy): the call's own time
                    own = sol.wall_time if isinstance(sol, HasRunCost) else None
                    wall = float(own or (time.perf_counter() - w))
                    best = min(best, wall)
                    spent += time.perf_counter() - w
                    k += 1
                err = final_state_error(_final(sol), ref.y_end)
                eerr = _max_rel_energy_error(system, sol.t, sol.y)
                steps = int(sol.steps) if isinstance(sol, HasRunCost) else 0
            except PoissonkitError as exc:
                note = f"{type(exc).__name__}: {exc}"
            p = WorkPoint(method, kind, float(v), steps, best, err, eerr, note)
            pts.append(p)
            if on_point:
                on_point(p)
            if time_budget is not None and math.isfinite(best) and best > time_budget:
                break
    return pts


def time_to_error(points: Iterable[WorkPoint], target: float) -> dict[str, float | None]:
    """Wall time each method needs to reach ``final_error <= target``.

    Along each method's points sorted by wall time, the first crossing of ``target`` is
    interpolated linearly in ``(log wall, log error)``; ``None`` if never reached. A method
    already below the target at its cheapest point reports that point's time (an upper bound).
    """
    by: dict[str, list[WorkPoint]] = {}
    for p in points:
        by.setdefault(p.method, []).append(p)
    out: dict[str, float | None] = {}
    for m, ps in by.items():
        ps = sorted((p for p in ps if math.isfinite(p.wall_time) and p.wall_time > 0),
                    key=lambda p: p.wall_time)
        out[m] = None
        for k, p in enumerate(ps):
            if p.final_error <= target:
                if k == 0 or not math.isfinite(ps[k - 1].final_error) or ps[k - 1].final_error <= 0:
                    out[m] = p.wall_time
                else:
                    q = ps[k - 1]
                    le0, le1 = math.log(q.final_error), math.log(max(p.final_error, 1e-300))
                    lt0, lt1 = math.log(q.wall_time), math.log(p.wall_time)
                    f = (math.log(target) - le0) / (le1 - le0) if le1 != le0 else 1.0
                    out[m] = math.exp(lt0 + f * (lt1 - lt0))
                break
    return out


CSV_FIELDS = ("method", "kind", "setting", "steps", "wall_time", "final_error",
              "max_rel_energy_error", "note")


def write_csv(path: str | Path, points: Iterable[WorkPoint]) -> Path:
    """One row per point, columns :data:`CSV_FIELDS` (written atomically)."""
    from poissonkit.files.atomic import atomic_path

    path = Path(path)
    with atomic_path(path) as tmp, tmp.open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=CSV_FIELDS)
        w.writeheader()
        for p in points:
            w.writerow(asdict(p))
    return path


def read_csv(path: str | Path) -> list[WorkPoint]:
    """Points written by :func:`write_csv` (also older files with a ``max_energy_error``
    column)."""
    out = []
    with Path(path).open() as fh:
        for row in csv.DictReader(fh):
            out.append(WorkPoint(row["method"], row["kind"], float(row["setting"]),
                                 int(row["steps"]), float(row["wall_time"]),
                                 float(row["final_error"]),
                                 float(row.get("max_rel_energy_error",
                                               row.get("max_energy_error", "nan"))),
                                 row.get("note", "")))
    return out


def table(points: Sequence[WorkPoint], targets: Sequence[float] = (1e-6, 1e-9)) -> str:
    """Markdown table of time-to-error per method (``—`` if not reached)."""
    cols = [time_to_error(points, t) for t in targets]
    methods = list(dict.fromkeys(p.method for p in points))
    head = "| method | " + " | ".join(f"time to {t:.0e} [s]" for t in targets) + " |"
    lines = [head, "|---|" + "---|" * len(targets)]
    for m in methods:
        cells = [f"{c[m]:.3g}" if c.get(m) is not None else "—" for c in cols]
        lines.append(f"| {m} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def plot(path: str | Path, points: Sequence[WorkPoint], *, title: str = "") -> Path:
    """Two log–log panels: final-state error and max energy error against wall time."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2), dpi=100)
    methods = list(dict.fromkeys(p.method for p in points))
    for m in methods:
        ps = sorted((p for p in points if p.method == m), key=lambda p: p.wall_time)
        w = [p.wall_time for p in ps]
        for ax, errors in zip(axes, ([p.final_error for p in ps],
                                     [p.max_rel_energy_error for p in ps])):
            v = [max(e, 1e-17) if math.isfinite(e) else np.nan for e in errors]
            ax.loglog(w, v, "o-", markersize=3, linewidth=1, label=m)
    for ax, lab in zip(axes, ("final-state error (block-relative)", "max relative energy error")):
        ax.set_xlabel("wall time [s]")
        ax.set_ylabel(lab)
        ax.grid(True, which="both", color="0.9", linewidth=0.5)
    axes[0].legend(fontsize=7)
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    from poissonkit.files.atomic import atomic_path

    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format=path.suffix.lstrip(".") or "png")
    plt.close(fig)
    return path
