"""Baselines: :func:`scipy.integrate.solve_ivp` (RK45, DOP853, Radau, LSODA) on the compiled RHS.

Each right-hand-side call goes Python → numba, so these are dominated by per-step Python
overhead; they are references and baselines, not the fast path. Events map to scipy terminal
events, located by root finding on the dense output. They cannot be checkpointed (the step-size
controller's state is internal to scipy).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
from scipy.integrate import solve_ivp

from poissonkit.contracts import Event, HasCompiledKernels, HasJacobian, NumericsSystem, System
from poissonkit.errors import InputError, IntegrationError, NonFiniteStateError
from poissonkit.numerics.events import EventRecord, check_events, raise_or_record
from poissonkit.numerics.integrators.base import RawResult
from poissonkit.numerics.integrators.capabilities import SCIPY
from poissonkit.numerics.integrators.driver import Control
from poissonkit.traits import offers


class ScipyIVP:
    """Adapter for one ``solve_ivp`` method.

    Parameters
    ----------
    method
        ``"RK45"``, ``"DOP853"``, ``"Radau"`` or ``"LSODA"``.
    atol
        Absolute tolerance; ``0`` means "same as ``tol``".
    max_step
        Largest step (``0`` = unlimited).
    """

    family = SCIPY.family
    capabilities = SCIPY.capabilities

    def __init__(self, method: str = "DOP853", atol: float = 0.0, max_step: float = 0.0) -> None:
        if method not in ("RK45", "DOP853", "Radau", "LSODA"):
            raise InputError(f"unsupported scipy method {method!r}")
        self.method = method
        self.name = method.lower()
        self.order = {"RK45": 5, "DOP853": 8, "Radau": 5, "LSODA": 0}[method]
        self.atol = float(atol)
        self.max_step = float(max_step)

    def integrate(self, system: System, y0: np.ndarray, t_end: float, *, step: float | None,
                  tol: float | None, events: Sequence[Event] = (), progress: bool = False,
                  save_every: int = 1, t0: float = 0.0,
                  control: Control | None = None) -> RawResult:
        """Integrate with ``rtol = tol`` (default 1e-9) and ``atol`` (default ``tol``).

        ``control`` must be ``None``: scipy's step-size controller cannot be checkpointed
        (:func:`~poissonkit.numerics.solve` streams the rows after the run instead).
        """
        if control is not None:
            from poissonkit.errors import CapabilityError

            raise CapabilityError(self.name, "checkpoint", "scipy methods take no run "
                                  "controls (checkpoint, stream, stop)")
        from poissonkit.numerics.solver import MAX_STEPS

        rtol = 1e-9 if tol is None else float(tol)
        atol = self.atol or rtol
        if self.max_step > 0 and (t_end - t0) / self.max_step > MAX_STEPS:
            # scipy would step for days (or fail deep inside on a subnormal max_step)
            raise InputError(f"{self.name}: max_step {self.max_step!r} would take more than "
                             f"{MAX_STEPS:.0e} steps to reach t_end = {t_end!r}")
        counter = [0]
        fun: Callable[[float, np.ndarray], np.ndarray]
        if offers(system, HasCompiledKernels):
            data, work, f = system.data, system.work(), system.kernels.rhs

            def fun(t: float, y: np.ndarray) -> np.ndarray:
                out = np.empty_like(y)
                counter[0] += 1
                try:
                    f(y, data, work, out)
                except ZeroDivisionError:
                    raise NonFiniteStateError(counter[0], t, f"{self.name}: division by zero in "
                                              f"a compiled kernel at evaluation {counter[0]} "
                                              "(two bodies at the same place?)") from None
                if not np.all(np.isfinite(out)):
                    raise NonFiniteStateError(counter[0], t, f"{self.name}: non-finite RHS at "
                                              f"evaluation {counter[0]}")
                return out
        elif offers(system, NumericsSystem):
            rhs = system.rhs

            def fun(t: float, y: np.ndarray) -> np.ndarray:
                counter[0] += 1
                return np.asarray(rhs(t, y), dtype=float)
        else:
            raise InputError(f"{self.name} needs a system with rhs(t, y) or compiled kernels; "
                             f"{type(system).__name__} has neither")
        events = check_events(events)
        if events and not offers(system, HasCompiledKernels):
            raise InputError(f"{self.name}: events need a system with compiled kernels "
                             f"(distances, radii); {type(system).__name__} has none")
        ev_funcs = []
        for ev in events:
            if not ev.terminal:
                raise InputError(f"{self.name}: {type(ev).__name__} needs a splitting or the "
                                 "midpoint method (scipy locates sign changes only)")

            def g(t, y, ev=ev):
                return ev.value(system, y)
            g.terminal = True  # type: ignore[attr-defined]
            ev_funcs.append((ev, g))
        kwargs: dict[str, object] = {"rtol": rtol, "atol": atol}
        if self.max_step > 0:
            kwargs["max_step"] = self.max_step
        if step is not None and self.method != "LSODA":
            kwargs["first_step"] = float(step)
        if self.method in ("Radau",) and offers(system, HasJacobian):
            kwargs["jac"] = system.jacobian
        res = solve_ivp(fun, (t0, t_end), np.asarray(y0, dtype=float), method=self.method,
                        events=[e[1] for e in ev_funcs] or None, **kwargs)
        records: list = []
        if res.status == -1:
            raise IntegrationError(f"{self.name} failed: {res.message}")
        ts, ys = res.t, res.y.T
        if not np.all(np.isfinite(ys)):
            bad = int(np.argmax(~np.all(np.isfinite(ys), axis=1)))
            raise NonFiniteStateError(bad, float(ts[max(bad - 1, 0)]), f"{self.name}")
        steps = len(ts) - 1
        if res.status == 1:
            for (ev, _), te, ye in zip(ev_funcs, res.t_events, res.y_events):
                if len(te):
                    yv = ye[0]
                    g = ev.value(system, yv)
                    value = (ev.radius - g) if ev.kind == "escape" else \
                        g if ev.kind == "contact" else g + ev.distance
                    # scipy's root finder (brentq on the dense output) stops at 4 eps |t|
                    bracket = 4 * np.finfo(float).eps * max(abs(te[0]), 1.0)
                    rec = EventRecord(ev.kind, steps, float(te[0]), float(value),
                                      time_error=float(bracket))
                    raise_or_record(ev, rec, records, system, yv)  # names who touched
                    ts[-1], ys[-1] = te[0], yv
                    break
        keep = np.zeros(len(ts), dtype=bool)
        keep[::save_every] = True
        keep[-1] = True
        return RawResult(ts[keep], ys[keep], steps, nfev=int(res.nfev), events=records,
                         message=res.message, extra={"rtol": rtol, "atol": atol})

