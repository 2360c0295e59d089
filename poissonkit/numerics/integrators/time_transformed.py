"""Time-transformed (logarithmic-Hamiltonian) splitting for close encounters, order 2 to 10.

The physical time ``t`` becomes a coordinate of an extended phase space with conjugate momentum
``p_t``, and the new Hamiltonian, in the fictitious time ``s``, is

    Γ = g₀ [ln(T + p_t) − ln(C − V)],     p_t = C − H(y₀),   g₀ = C − V(y₀),

with ``H = T + V`` the system's kinetic and potential energy and ``C`` a constant shift (the
``shift`` parameter) such that ``C − V > 0``. On ``Γ = 0`` (which holds initially) its flow is
the physical flow reparametrised by ``dt/ds = g₀/(C − V)``: the physical step shrinks where the
potential well is deep, i.e. at pericentre. This is the logarithmic Hamiltonian of
S. Mikkola and K. Tanikawa, "Algorithmic regularization of the few-body problem", MNRAS 310
(1999) 745, and "Explicit symplectic algorithms for time-transformed Hamiltonians", Celest.
Mech. Dyn. Astron. 74 (1999) 287 (``C = 0``), in the general form ``f(T + p_t) − f(C − V)`` of
M. Preto and S. Tremaine, "A class of symplectic integrators with adaptive timestep for
separable Hamiltonian systems", AJ 118 (1999) 2532 (``f = ln``). The constant ``g₀`` only
rescales ``s`` so that ``step`` is the physical step at the initial state. With ``exponent``
``k ≠ 1`` the transform is Preto–Tremaine's ``f(x) = g₀^k x^{1−k}/(1−k)``, i.e.
``dt/ds = (g₀/(C − V))^k`` (``k = 1/2`` suits ``1/r³`` dipolar encounters better than the
logarithm, which is exact for Kepler orbits at order 2); everything below holds for any ``k``
with ``g₀/(·)`` read as ``(g₀/(·))^k``.

``Γ`` is separable, ``Γ_A(T, p_t) + Γ_B(V)``, and since ``t`` does not appear, ``p_t`` is
constant; both flows are the system's own exact Poisson sub-flows run for a rescaled time:

* ``Γ_A`` for ``Δs``: ``T`` is constant along the kinetic flow, so it is the exact drift
  (:mod:`~poissonkit.numerics.integrators.splitting`'s ``φ_T``) for ``τ = Δs g₀/(T + p_t)``,
  and ``t += τ``;
* ``Γ_B`` for ``Δs``: ``V`` is constant along the kick (positions and axes fixed), so it is the
  exact kick ``φ_V`` for ``σ = Δs g₀/(C − V)``.

They are composed with the same symmetric drift–kick tables as the splitting (Strang, Suzuki's
order 4, Kahan–Li's orders 6 and 8: :data:`~poissonkit.numerics.integrators.splitting.WEIGHTS`;
Sofroniou–Spaletta's order 10 of ``splitting10_ss``), so the method is symplectic in the
extended phase space, of order 2–10 in ``s``, and keeps
``|ν|``, ``(ν, m)``, total linear and angular momentum to round-off at any step (each stage is
an exact Poisson map of the original bracket). The energy error is bounded without drift
(``H − H₀ = (T + p_t) − (C − V)`` is the modified-``Γ`` error of a symplectic map).

The drift's rate ``g₀/(T + p_t)`` and the kick's ``g₀/(C − V)`` agree only up to the energy
error ``δH``, a relative rate error ``δH/(C − V)``: with a kinetic energy far larger than
``|V|`` (fast spins) this sets an accuracy floor (about 1e-9 on the seed orbit; see
``docs/numerics.md``), lowered by a larger ``C``.

**Tracked kinetic energy** (``track_kinetic=True``). The floor is round-off, not truncation:
``T + p_t`` computed from the momenta carries their accumulated round-off (``ε|m|`` per kick),
amplified by ``T/|V|`` (445 on the seed encounter) into the rate, i.e. a clock error of the
orbit (measured: the final-state error at small steps is a time shift of 3e-10–8e-10 with a
residual of 1e-11). With the option, ``T + p_t`` starts at ``C − V(y₀)`` (``Γ = 0``) and each
kick adds its work ``Σ w δ (u + δ/2)`` from its exact increments ``δ`` (two bodies: in the
kick's own pass over the forces; N bodies: the kick applied once more to a zero state); the
drift leaves ``T`` unchanged. The method is the same in exact
arithmetic; the floor falls to the ordinary splitting's (1e-11–1e-10 on the encounter). A
state changed outside the loop (event location, restart) is resynchronised from its momenta.

Each stage costs one force evaluation: the system's ``forces`` kernel returns ``V`` and leaves
the forces in the scratch arrays, from which the kick is applied (no second evaluation).

**Output at physical times.** Steps in ``s`` land at irregular times; the loop saves every
``save_every``-th step end. The step that would pass ``t_end`` is undone and replaced by one
ordinary composition step (same coefficients, physical time) of the remaining ``Δt``, which is
shorter than the transformed step it replaces at that place, so it is at least as accurate and
costs one step — a secant solve for the last ``Δs`` would cost 3–4 steps for the same accuracy.
Events (contact, escape, grazing watch) are detected at step ends and located as in the
splitting (ordinary composition steps over the sub-interval).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numba
import numpy as np

from poissonkit.contracts import (CompiledFunction, CompiledKernels, Event, HasCompiledKernels,
                                  HasKineticSplit, HasStateCheck, System)
from poissonkit.errors import InputError, IntegrationError
from poissonkit.numerics.events import event_thresholds
from poissonkit.numerics.integrators.base import (NONFINITE, RUNNING, RawResult, SaveBuffer,
                                                  check_step, state_digest, step_end_kernels,
                                                  step_tail)
from poissonkit.numerics.integrators.capabilities import TIME_TRANSFORMED
from poissonkit.numerics.integrators.compositions import TABLES
from poissonkit.numerics.integrators.driver import Control, LoopProblem, LoopState, drive
from poissonkit.numerics.integrators.glue import ChunkResult, Scratch, guard_division
from poissonkit.numerics.integrators.splitting import WEIGHTS, drift_kick_coefficients
from poissonkit.numerics.jit import jit
from poissonkit.numerics.kernels import all_finite, copy_into
from poissonkit.numerics.nbody import apply_forces
from poissonkit.traits import offers
from poissonkit.validation import finite_number

#: loop status codes beyond :mod:`~poissonkit.numerics.integrators.base`'s
KINETIC_LOST, SHIFT_TOO_SMALL, NO_PROGRESS = 8, 9, 10

# layouts of the forces left in ``work`` by ``kernels.forces``
_TWO_BODY, _NBODY = 0, 1


# --------------------------------------------------------------------------- system adapters
@numba.njit(cache=True, error_model="numpy")
def kinetic_energy(y, idx, w):
    """``T = ½ Σ_k w_k y[idx_k]²`` (the kinetic energy is diagonal in the momenta ``p, m``)."""
    e = 0.0
    for k in range(idx.shape[0]):
        v = y[idx[k]]
        e += w[k] * v * v
    return 0.5 * e


@numba.njit(cache=True, error_model="numpy")
def kick_work(y, dy, idx, w):
    """``T(y + dy) − T(y) = Σ_k w_k dy_k (y_k + dy_k/2)`` over the momentum slots ``idx``: the
    work of a kick from its exact increments ``dy``, free of the cancellation of two large
    kinetic energies (fast spins) and of the round-off of the kicked momenta."""
    e = 0.0
    for k in range(idx.shape[0]):
        d = dy[idx[k]]
        e += w[k] * d * (y[idx[k]] + 0.5 * d)
    return e


@numba.njit(cache=True, error_model="numpy")
def _apply_two_body(y, h, data, work):
    """Kick ``p, m', m''`` by ``h`` times the forces left in ``work.partials`` by ``forces``."""
    f = work.partials
    for d in range(3):
        y[3 + d] += h * f[d]
        y[9 + d] += h * f[3 + d]
        y[15 + d] += h * f[6 + d]


@numba.njit(cache=True, error_model="numpy")
def _kick_tracked_two_body(y, h, idx, w, kz, data, work):
    """:func:`_apply_two_body` fused with :func:`kick_work` (same numbers, one pass): kicks
    ``y`` and returns the kick's work (``idx`` lists the slots of ``p, m', m''`` in the order of
    ``work.partials``)."""
    f = work.partials
    e = 0.0
    for k in range(idx.shape[0]):
        d = h * f[k]
        u = y[idx[k]]
        e += w[k] * d * (u + 0.5 * d)
        y[idx[k]] = u + d
    return e


@numba.njit(cache=True, error_model="numpy", inline="always")
def _power(x, k):
    """``x**k`` without a general ``pow`` for the usual exponents 1 and 1/2."""
    if k == 1.0:
        return x
    if k == 0.5:
        return math.sqrt(x)
    return x**k


def _layout(system: System, name: str) -> tuple[int, np.ndarray, np.ndarray]:
    """(forces layout, momentum slots, kinetic weights) of a system of bodies."""
    if not offers(system, HasKineticSplit):
        raise InputError(f"{name} needs a TwoBodySystem or NBodySystem (a system of bodies "
                         "with exact kinetic/potential flows and a forces kernel); "
                         f"{type(system).__name__} is neither — use a splitting, 'midpoint' or "
                         "a scipy method")
    split = system.kinetic_split()
    return (_TWO_BODY if split.layout == "two_body" else _NBODY,
            np.asarray(split.momenta, dtype=np.int64), np.asarray(split.weights, dtype=float))


# --------------------------------------------------------------------------- compiled loop
_runners: dict[tuple[int, int],
               tuple[CompiledFunction, CompiledFunction, CompiledKernels]] = {}


def _runner(kernels: CompiledKernels, layout: int) -> CompiledFunction:
    """The compiled time loop specialised to one system's kernels (cached)."""
    key = (id(kernels.forces), layout)
    hit = _runners.get(key)
    if hit is not None:
        return hit[0]
    drift, forces = kernels.drift, kernels.forces
    remember = step_end_kernels(kernels)[0]
    tail = step_tail(kernels)
    apply = _apply_two_body if layout == _TWO_BODY else apply_forces

    @jit
    def kick_tracked_bodies(y, h, kidx, kw, kz, data, work):
        """Kick ``y``; returns the kick's work from its increments (the kick applied to ``kz``,
        zero in the momentum slots)."""
        for i in range(kidx.shape[0]):
            kz[kidx[i]] = 0.0
        apply(kz, h, data, work)
        e = kick_work(y, kz, kidx, kw)
        apply(y, h, data, work)
        return e

    kick_tracked = _kick_tracked_two_body if layout == _TWO_BODY else kick_tracked_bodies

    @jit
    def plain_step(y, h, a, b, data, work):
        """One ordinary composition step of physical time ``h``."""
        nb = b.shape[0]
        for s in range(nb):
            drift(y, a[s] * h, data)
            forces(y, data, work)
            apply(y, b[s] * h, data, work)
        drift(y, a[nb] * h, data)

    @jit
    def tt_step(y, ds, a, b, pt, c, g0, kexp, kidx, kw, data, work, wk, kz):
        """One step ``Δs`` in fictitious time; returns ``(Δt, status, offending value)``.
        ``wk`` empty: the drift's rate reads ``T(y) + p_t``; else ``wk[0]`` carries
        ``T + p_t``, advanced by each kick's work, whose increments the kick leaves in the
        momentum slots of ``kz`` (zero elsewhere)."""
        nb = b.shape[0]
        dt = 0.0
        tracked = wk.shape[0] > 0
        for s in range(nb + 1):
            w = wk[0] if tracked else kinetic_energy(y, kidx, kw) + pt
            if not w > 0.0:
                return dt, KINETIC_LOST, w
            tau = a[s] * ds * _power(g0 / w, kexp)
            drift(y, tau, data)
            dt += tau
            if s == nb:
                break
            v = forces(y, data, work)
            den = c - v
            if not den > 0.0:
                return dt, SHIFT_TOO_SMALL, v
            hk = b[s] * ds * _power(g0 / den, kexp)
            if tracked:
                wk[0] += kick_tracked(y, hk, kidx, kw, kz, data, work)
            else:
                apply(y, hk, data, work)
        return dt, RUNNING, 0.0

    @jit
    def run(y, t0, t_end, ds, a, b, pt, c, g0, kexp, kidx, kw, data, work, save_every, step0,
            max_steps, out_t, out_y, contact, escape, watch, trial, prev, prev2, hist, wk, kz):
        """Advance ``y`` in place. Returns (status, t, steps_done_in_call, n_saved, value)
        (``prev``, ``prev2``, ``hist`` as in the splitting's loop; ``wk``, ``kz`` as in
        ``tt_step``)."""
        nsave = 0
        t = t0
        k = 0
        track = contact > 0.0 or escape > 0.0 or watch > 0.0
        while k < max_steps:
            gstep = step0 + k + 1
            if track:
                remember(y, prev, prev2, hist, t)
            copy_into(y, trial)
            w_start = wk[0] if wk.shape[0] > 0 else 0.0
            dt, code, bad = tt_step(y, ds, a, b, pt, c, g0, kexp, kidx, kw, data, work, wk, kz)
            if code != RUNNING:
                copy_into(trial, y)  # leave the last good state for the error message
                return code, t, k, nsave, bad
            if math.isnan(dt) or not all_finite(y):
                return NONFINITE, t, k + 1, nsave, 0.0
            if not dt > 0.0:
                copy_into(trial, y)
                return NO_PROGRESS, t, k, nsave, dt
            last = not t + dt < t_end
            if last:  # undo, and finish with an ordinary step of the remaining time
                copy_into(trial, y)
                if wk.shape[0] > 0:
                    wk[0] = w_start
                plain_step(y, t_end - t, a, b, data, work)
                t = t_end
            else:
                t += dt
            k += 1
            status, nsave, value = tail(y, y, t, RUNNING, last, last or gstep % save_every == 0,
                                        track, data, work, contact, escape, watch, hist, out_t,
                                        out_y, nsave)
            if status != RUNNING:
                return status, t, k, nsave, value
        return RUNNING, t, k, nsave, 0.0

    _runners[key] = (run, plain_step, kernels)
    return run


def _plain(kernels: CompiledKernels, layout: int) -> CompiledFunction:
    _runner(kernels, layout)
    return _runners[(id(kernels.forces), layout)][1]


class TimeTransformedSplitting:
    """Logarithmic-Hamiltonian time-transformed composition of the exact sub-flows (module doc).

    Parameters
    ----------
    order
        2, 4, 6, 8 or 10 (in the fictitious time ``s``; 10 composes 35 stages, the weights of
        ``splitting10_ss``).
    shift
        The constant ``C`` of ``ln(C − V)`` (internal energy unit); ``C − V`` must stay
        positive. ``0`` is Mikkola–Tanikawa's logarithmic Hamiltonian, right for attractive
        potentials (``V < 0``); give ``C > max V`` when the potential can be positive. The
        physical step is ``step · ((C − V(y₀))/(C − V(y)))^k``: a larger ``C`` adapts less.
    exponent
        ``k`` of the time transform ``dt/ds = ((C − V(y₀))/(C − V))^k``: ``1`` is the
        logarithmic Hamiltonian (``f = ln``; exact Kepler orbits at order 2, right for ``1/r``
        potentials); for steeper potentials (dipoles, ``1/r³``) ``k ≈ 1/2`` shrinks the step
        like ``r^{3/2}`` instead of ``r³`` (Preto–Tremaine's ``f(x) = x^{1−k}/(1−k)``).
    track_kinetic
        Carry ``T + p_t`` from kick to kick by each kick's work (module doc, "Tracked kinetic
        energy") instead of recomputing it from the momenta: the same method in exact
        arithmetic, without the round-off floor of fast spins (``T ≫ |V|``). ``False`` (the
        default) keeps the original loop bit for bit.
    """

    family = TIME_TRANSFORMED.family
    capabilities = TIME_TRANSFORMED.capabilities

    def __init__(self, order: int = 6, shift: float = 0.0, exponent: float = 1.0,
                 track_kinetic: bool = False) -> None:
        if order not in WEIGHTS and order != 10:
            raise InputError(f"logh order must be one of {sorted(WEIGHTS) + [10]}, "
                             f"got {order!r}")
        shift = finite_number(shift, f"logh{order}: shift")
        try:
            exponent = float(exponent)
        except (TypeError, ValueError):
            raise InputError(f"logh{order}: exponent must be a number, got {exponent!r}") \
                from None
        if not (math.isfinite(exponent) and 0 < exponent <= 3):
            raise InputError(f"logh{order}: exponent must be in (0, 3], got {exponent!r}")
        self.order = order
        self.shift = shift
        self.exponent = exponent
        self.track_kinetic = bool(track_kinetic)
        # order 10: Sofroniou–Spaletta's s35odr10, the weights of ``splitting10_ss``
        weights = WEIGHTS[order] if order in WEIGHTS else TABLES["splitting10_ss"].weights
        self.a, self.b = drift_kick_coefficients(weights)
        self.name = f"logh{order}"

    #: shift of :meth:`for_close_approach` in units of ``|V(y₀)|``: ``dt/ds = (C − V₀)/(C − V)``
    #: then shrinks the step at a pericentre 12× deeper than the start like ``k = 1/2`` would
    #: (0.26 against 0.28), without the two square roots per stage of ``k = 1/2``
    CLOSE_APPROACH_SHIFT = 3.0

    @classmethod
    def for_close_approach(cls, system: System, y0: np.ndarray) -> TimeTransformedSplitting:
        """The tuning that needs the fewest force evaluations per accuracy on eccentric close
        approaches of tops (``docs/performance.md``, "Force evaluations per accuracy"): order
        10, tracked kinetic energy, exponent 1 and shift ``3 |V(y₀)|``: the registry's
        ``logh10`` with options ``track_kinetic=True, shift=3|V(y₀)|`` (bit-identical).

        Raises
        ------
        InputError
            ``V(y₀) ≥ 0`` (no well to adapt to; the largest ``V`` of the run is not known) or
            ``system`` has no forces kernel.
        """
        if not offers(system, HasCompiledKernels) or system.kernels.forces is None:
            raise InputError(f"{type(system).__name__} has no forces kernel: a time-transformed "
                             "splitting needs a system of bodies")
        v0 = float(system.kernels.forces(np.array(y0, dtype=float), system.data,
                                         system.work()))
        if not v0 < 0:
            raise InputError(f"close-approach tuning needs an attractive start, V(y0) < 0; got "
                             f"V(y0) = {v0:.6g} (give logh8 a shift above the largest V)")
        return cls(10, shift=cls.CLOSE_APPROACH_SHIFT * abs(v0), track_kinetic=True)

    @property
    def stages(self) -> int:
        """Number of force evaluations per step."""
        return len(self.b)

    def integrate(self, system: System, y0: np.ndarray, t_end: float, *, step: float | None,
                  tol: float | None, events: Sequence[Event] = (), progress: bool = False,
                  save_every: int = 1, t0: float = 0.0,
                  control: Control | None = None) -> RawResult:
        """Integrate from ``t0`` to ``t_end``; ``step`` is the fictitious-time step ``Δs``,
        equal to the physical step at the initial state (see :func:`drive` for ``control``)."""
        if not offers(system, HasCompiledKernels) or not system.kernels.splittable:
            raise InputError(f"{self.name} needs a system with exact kinetic/potential flows "
                             f"(NBodySystem, TwoBodySystem); {type(system).__name__} has none")
        layout, kidx, kw = _layout(system, self.name)
        kernels = system.kernels
        if kernels.forces is None:
            raise InputError(f"{self.name}: {type(system).__name__} has no forces kernel")
        if offers(system, HasStateCheck):
            system.check_state(y0)
        ds = check_step(step, t_end - t0, self.name)
        y = np.array(y0, dtype=float)
        data, work = system.data, system.work()
        C = self.shift
        V0 = float(kernels.forces(np.array(y0, dtype=float), data, work))
        T0 = float(kinetic_energy(y, kidx, kw))
        H0 = float(kernels.energy(np.array(y0, dtype=float), data, system.work()))
        if not (math.isfinite(V0) and math.isfinite(H0)):
            raise InputError(f"{self.name}: the energy at the initial state is not finite")
        # the kinetic weights must reproduce the system's own energy (guards the layout)
        if abs(H0 - (T0 + V0)) > 1e-9 * (abs(T0) + abs(V0) + 1e-300):
            raise InputError(f"{self.name}: kinetic energy of {type(system).__name__} is not "
                             "the diagonal form in (p, m) this method assumes")
        g0 = C - V0
        if not g0 > 0:
            raise InputError(
                f"{self.name}: shift C = {C:.6g} must exceed the potential energy at the start, "
                f"V(y0) = {V0:.6g} (the time transform uses ln(C - V)); give the integrator "
                f"option shift > {V0:.6g}, e.g. solve(..., options={{'shift': "
                f"{V0 + abs(V0) + 1:.3g}}})")
        pt = C - H0
        contact, escape, watch = event_thresholds(events)
        run = _runner(kernels, layout)
        plain = _plain(kernels, layout)
        trial = np.empty_like(y)
        scratch = Scratch(y.size)
        a, b, kexp = self.a, self.b, self.exponent
        # tracked T + p_t: carry "w" = [T + p_t] valid for the state carry "w_at" (it starts at
        # C - V(y0), Γ = 0); a state changed outside the loop (event location) is
        # resynchronised from its momenta; both are checkpointed (bit-identical resume)
        kz = np.zeros(y.size if self.track_kinetic else 0)
        carry = {"w": np.array([g0]), "w_at": y.copy()} if self.track_kinetic else {}
        untracked = np.empty(0)

        def tracked(st: LoopState) -> np.ndarray:
            if not st.carry:
                return untracked
            wk, at = st.carry["w"], st.carry["w_at"]
            if not np.array_equal(st.y, at):
                wk[0] = kinetic_energy(st.y, kidx, kw) + pt
            return wk

        def chunk(st: LoopState, max_steps: int, buf: SaveBuffer) -> ChunkResult:
            status, t_new, k, nsave, value = run(
                st.y, st.t, t_end, ds, a, b, pt, C, g0, kexp, kidx, kw, data, work, save_every,
                st.steps, max_steps, buf.cur_t, buf.cur_y, contact, escape, watch, trial,
                st.prev, st.prev2, st.hist, tracked(st), kz)
            if st.carry:
                st.carry["w_at"][:] = st.y
            st.detail = value
            return status, t_new, k, nsave, k * len(b), value

        def one_step(ys: np.ndarray, ts: float, done_steps: int) -> tuple[int, float]:
            w1 = np.array([kinetic_energy(ys, kidx, kw) + pt]) if kz.size else untracked
            out = run(ys, ts, t_end, ds, a, b, pt, C, g0, kexp, kidx, kw, data, work,
                      save_every, done_steps, 1, scratch.t, scratch.y, 0.0, 0.0, 0.0, trial, ys,
                      ys, scratch.hist, w1, kz)
            return out[0], out[1]

        def advance(ys: np.ndarray, s: float) -> np.ndarray:
            yc = np.array(ys, dtype=float)
            plain(yc, s, a, b, data, work)
            return yc

        def failure(status: int, st: LoopState) -> Exception | None:
            bad = st.detail
            where = f"at step {st.steps + 1} (t = {st.t:.10g})"
            if status == SHIFT_TOO_SMALL:
                return IntegrationError(
                    f"{self.name}: C - V <= 0 {where}: the potential energy V = {bad:.6g} "
                    f"reached the shift C = {C:.6g}; give the integrator option shift above "
                    "the largest potential energy of the run")
            if status == KINETIC_LOST:
                return IntegrationError(
                    f"{self.name}: T + p_t = {bad:.3g} <= 0 {where}: the energy error exceeds "
                    "the margin C - V; use a smaller step or a larger shift")
            if status == NO_PROGRESS:
                return IntegrationError(
                    f"{self.name}: the physical time did not advance {where} (Δt = {bad:.3g}): "
                    "the fictitious-time step is far too large; use a smaller step")
            return None

        def done(st: LoopState) -> bool:
            return st.t >= t_end

        problem = {"method": self.name, "ds": float(ds).hex(), "t0": float(t0).hex(),
                   "t_end": float(t_end).hex(), "shift": float(C).hex(),
                   "exponent": float(self.exponent).hex(),
                   "save_every": save_every, "dim": int(y.size),
                   # progress-bar granularity only (the number of steps is not known ahead)
                   "n_total": max(1, math.ceil((t_end - t0) / ds)),
                   "y0": state_digest(y0)}
        if self.track_kinetic:  # existing runs keep their problem key (checkpoints)
            problem["track_kinetic"] = True
        raw = drive(LoopProblem(
            self.name, system, y, t0, t_end,
            guard_division(self.name, chunk, lambda st: (one_step, st.y.copy())), advance, done,
            problem, 4096, events, progress, save_every, control, failure, carry=carry))
        raw.extra.update(step=ds, order=self.order, shift=C, exponent=self.exponent,
                         time_transformed=True)
        if self.track_kinetic:
            raw.extra["track_kinetic"] = True
        return raw
