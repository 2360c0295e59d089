"""``check_integrator``: an integrator against what its
:class:`~poissonkit.plugin.IntegratorEntry` declares.

* **order** — errors against a known solution (:mod:`poissonkit.testing.problems`) over steps
  ``T/N``, ``N = 8·√2^k``; the slope of ``log error`` over ``log step`` on the three smallest steps
  in the asymptotic range (error below 1e-3, above the reference's floor and round-off) must be
  the declared order ± :data:`SLOPE_TOL`. A method that takes its steps from ``tol`` (family
  ``"scipy"`` or order 0) must converge as ``tol`` falls instead.
* **capabilities** — each declared one is exercised: ``checkpoint`` (stop or kill, resume:
  bit-identical to the uninterrupted run), ``stop`` (a stop request gives a clean partial
  result), ``events`` / ``located_events`` (a radial free fall stops at the collision, at the
  exact time :func:`~poissonkit.testing.oracles.free_fall_time` within one step, or within
  0.01 step when located).
"""

from __future__ import annotations

import itertools
import math
import tempfile
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from poissonkit.errors import CapabilityError, PoissonkitError
from poissonkit.plugin.contributions import IntegratorEntry
from poissonkit.testing.lookup import findings_for
from poissonkit.testing.problems import Problem, free_fall, problem_for
from poissonkit.testing.report import Findings

SLOPE_TOL = 0.3
LADDER = sorted({round(8 * 2 ** (k / 2)) for k in range(21)})
EPS = float(np.finfo(float).eps)


def _error(p: Problem, method: str, options: Mapping[str, Any], **kw: Any) -> float:
    from poissonkit.numerics import solve

    sol = solve(p.system, p.y0, p.t_end, method, options=dict(options), **kw)
    return float(np.max(np.abs(np.asarray(sol.y[-1]) - p.truth)))


def check_order(e: IntegratorEntry, out: Findings, options: Mapping[str, Any]) -> None:
    """The declared order (or convergence in ``tol``)."""
    p = problem_for(e)
    if e.family == "scipy" or e.order == 0:
        tols = (1e-4, 1e-6, 1e-8, 1e-10)
        errs = [_error(p, e.name, options, tol=t) for t in tols]
        if not all(b < a for a, b in itertools.pairwise(errs)) or errs[-1] > 1e-3 * errs[0]:
            out.add("order", f"does not converge as tol falls on {p.name}: errors "
                             f"{', '.join(f'{x:.2g}' for x in errs)} at tol {tols}")
        return
    measured: list[tuple[int, float]] = []
    usable: list[tuple[int, float]] = []
    for n in LADDER:
        try:
            err = _error(p, e.name, options, step=p.t_end / n)
        except PoissonkitError:  # too coarse a step for an implicit solve: try a finer one
            if usable:
                raise
            measured.append((n, math.inf))
            continue
        measured.append((n, err))
        # round-off grows with the number of steps, unless the sums are compensated
        scale = EPS * max(1.0, float(np.abs(p.truth).max()))
        floor = max(p.floor, scale * (1000 if options.get("compensated") else 200 * n))
        if floor <= err <= 1e-3:
            usable.append((n, err))
        elif usable:  # below the floor: smaller steps only measure round-off
            break
    if len(usable) < 3:
        out.add("order", f"fewer than three steps in the asymptotic range on {p.name} "
                         f"(N, error): {[(n, f'{x:.2g}') for n, x in measured]}")
        return
    n_, err_ = np.array(usable[-3:]).T
    slope = float(np.polyfit(np.log(p.t_end / n_), np.log(err_), 1)[0])
    if abs(slope - e.order) > SLOPE_TOL:
        out.add("order", f"observed order {slope:.2f} on {p.name}, declared {e.order} "
                         f"(tolerance ±{SLOPE_TOL}); (N, error): "
                         f"{[(int(n), f'{x:.2g}') for n, x in usable]}")


class _StopAfter:
    """A stop request that becomes true at its ``n``-th look."""

    def __init__(self, n: int) -> None:
        self.n, self.looks = n, 0

    def __call__(self) -> bool:
        self.looks += 1
        return self.looks >= self.n


def check_checkpoint(e: IntegratorEntry, out: Findings, options: Mapping[str, Any]) -> None:
    """Interrupted (stopped, or all but the first checkpoint deleted) and resumed: the same
    bits as the uninterrupted run."""
    from poissonkit.numerics import solve
    from poissonkit.numerics.checkpoint import Checkpoint

    p = problem_for(e)
    kw: dict[str, Any] = {"step": p.t_end / 200, "save_every": 7, "options": dict(options)}
    ref = solve(p.system, p.y0, p.t_end, e.name, **kw)
    with tempfile.TemporaryDirectory() as tmp:
        ck = Checkpoint(Path(tmp) / "ck", 37, keep=100)
        if e.capabilities.stop:
            solve(p.system, p.y0, p.t_end, e.name, checkpoint=ck, stop=_StopAfter(2), **kw)
        else:
            solve(p.system, p.y0, p.t_end, e.name, checkpoint=ck, **kw)
            files = sorted(Path(ck.folder).iterdir())
            for f in files[1:]:
                f.unlink()
        done = solve(p.system, p.y0, p.t_end, e.name, checkpoint=ck, resume=True, **kw)
    if "resumed_from" not in done.extra:
        out.add("checkpoint", "a resumed run does not say it resumed (extra['resumed_from'])")
    if not (np.array_equal(done.t, ref.t) and np.array_equal(done.y, ref.y)):
        diff = float(np.max(np.abs(np.asarray(done.y[-1]) - np.asarray(ref.y[-1]))))
        out.add("checkpoint", f"resume is not bit-identical to the uninterrupted run (final "
                              f"state differs by {diff:.3g})")


def check_stop(e: IntegratorEntry, out: Findings, options: Mapping[str, Any]) -> None:
    """A stop request: a clean partial result, marked interrupted."""
    from poissonkit.numerics import solve

    p = problem_for(e)
    sol = solve(p.system, p.y0, p.t_end, e.name, step=p.t_end / 400, options=dict(options),
                stop=_StopAfter(1))
    if not sol.extra.get("interrupted") or not sol.t[-1] < p.t_end:
        out.add("stop", f"a stop request is ignored: the run ends at t = {sol.t[-1]:.6g} of "
                        f"{p.t_end:.6g} (interrupted: {sol.extra.get('interrupted')})")
    elif not np.all(np.isfinite(sol.y)):
        out.add("stop", "the partial result of a stopped run is not finite")


def check_events(e: IntegratorEntry, out: Findings, options: Mapping[str, Any]) -> None:
    """A radial free fall from 1 to the collision distance 0.5."""
    from poissonkit.numerics import solve
    from poissonkit.numerics.events import Collision

    system, y0, mu = free_fall()
    t_hit = free_fall_time_for(mu)
    step = t_hit / 100
    try:
        sol = solve(system, y0, 2 * t_hit, e.name, step=step, options=dict(options),
                    events=(Collision(0.5),))
    except CapabilityError as exc:  # e.g. a method that needs a symbolic system
        out.advise(f"events not checked: the free fall of two bodies is refused ({exc})")
        return
    if not sol.events:
        out.add("events", f"no collision recorded in a free fall that collides at t = "
                          f"{t_hit:.6g}; the run ends at {sol.t[-1]:.6g}")
        return
    t_ev = float(sol.events[0].time)
    if e.capabilities.located_events:
        if abs(t_ev - t_hit) > 0.01 * step:
            out.add("located_events", f"collision located at t = {t_ev:.10g}, exact "
                                      f"{t_hit:.10g}: off by {abs(t_ev - t_hit) / step:.3g} "
                                      "steps (tolerance 0.01 step)")
    elif not (t_hit - 1e-3 * t_hit <= t_ev <= t_hit + step * 1.001):
        out.add("events", f"collision recorded at t = {t_ev:.6g}, exact {t_hit:.6g}: not "
                          f"within the step ({step:.3g}) that crosses it")


def free_fall_time_for(mu: float) -> float:
    """Fall time of :func:`~poissonkit.testing.problems.free_fall` to the distance 0.5."""
    from poissonkit.testing.oracles import free_fall_time

    return free_fall_time(1.0, 0.5, mu)


def _default_options(e: IntegratorEntry) -> dict[str, Any]:
    """Compensated summation where declared, so round-off stays below high-order errors."""
    return {"compensated": True} if any(p.name == "compensated" for p in e.params) else {}


def check_integrator(integrator: IntegratorEntry | str, *,
                     options: Mapping[str, Any] | None = None,
                     checks: Sequence[str] | None = None) -> None:
    """Check an integrator: its declared order and capabilities; raise :class:`CheckFailed`.

    Parameters
    ----------
    integrator
        The :class:`~poissonkit.plugin.IntegratorEntry` or its registered name (the entry must
        be registered: runs find it by name).
    options
        Integrator options (default: ``compensated`` where it exists).
    checks
        Subset of ``("order", "checkpoint", "stop", "events")`` (default: the order and every
        declared capability).

    Raises
    ------
    CheckFailed
    """
    e, out = findings_for(integrator, "integrator", IntegratorEntry)
    opts = dict(options) if options is not None else _default_options(e)
    caps = e.capabilities
    declared = ["order"] + [c for c, on in (("checkpoint", caps.checkpoint),
                                            ("stop", caps.stop),
                                            ("events", caps.events or caps.located_events))
                            if on]
    runs = {"order": check_order, "checkpoint": check_checkpoint, "stop": check_stop,
            "events": check_events}
    for name in checks or declared:
        with out.guard(name):
            runs[name](e, out, opts)
    out.raise_if_any()


__all__ = ["check_integrator"]
