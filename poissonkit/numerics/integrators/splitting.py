"""Poisson splitting with exact sub-flows, composed symmetrically to order 2, 4, 6 and 8.

``H = T + V`` with ``T = Σ p²/2M + Σ α m²/2`` and ``V = Σ U_ij``. Both flows are exact Poisson
maps:

* ``φ_T(h)``: ``r += h p/M`` and each top's axis ``ν`` rotates about its (fixed) ``m`` by the
  angle ``α|m|h`` (Rodrigues); ``p, m`` unchanged;
* ``φ_V(h)``: ``r, ν`` fixed, ``p += h F``, ``m += h T`` (linear in ``h``).

Hence ``|ν|``, ``(ν, m)``, total linear momentum and total angular momentum are preserved to
round-off at any step size (the kick's torques are orthogonal to ``ν`` and balance the forces'
moment, ``T_i + T_j + r × F = 0``). The base method is Strang's
``S(h) = φ_T(h/2) φ_V(h) φ_T(h/2)``; higher orders compose it symmetrically,
``S(w_m h) … S(w_1 h) S(w_0 h) S(w_1 h) … S(w_m h)``:

* order 4: Suzuki's fractal 5-stage composition, ``w = (p, p, 1 − 4p, p, p)``,
  ``p = 1/(4 − 4^{1/3})`` (M. Suzuki, Phys. Lett. A 146 (1990) 319);
* order 6: Kahan & Li's 9-stage s9odr6 (W. Kahan, R.-C. Li, Math. Comp. 66 (1997) 1089);
* order 8: Kahan & Li's 15-stage s15odr8 (same paper). At equal cost these give 10³–10⁴×
  smaller errors than Yoshida's solutions A (order 6) and D (order 8), which stay available in
  ``WEIGHTS_YOSHIDA`` (H. Yoshida, Phys. Lett. A 150 (1990) 262, Tables 1–2).

Runge–Kutta–Nyström (RKN) splittings. ``T`` is quadratic in the momenta ``(p, m)`` with
coefficients independent of the configuration ``(r, ν)``, ``V`` depends on the configuration
only, and ``{ν_i, ν_j} = {r_i, ν_j} = {r_i, r_j} = 0``. So ``{V, T}`` is linear in ``(p, m)``,
``{V, {V, T}} = Σ |∂_r V|²/M + Σ α |ν × ∂_ν V|²`` depends on the configuration alone, and
``{V, {V, {V, T}}} = 0`` — the condition under which splitting methods need fewer order
conditions (S. Blanes, P. C. Moan, J. Comput. Appl. Math. 142 (2002) 313). The optimised
RKN tables in :data:`SCHEMES` use it: Blanes & Moan's SRKN_6^b (order 4, 6 force evaluations
per step) and SRKN_14^a (order 6, 14), the winners of ``benchmarks/bench_kernels.py`` among
the optimised tables tried there. Their order is only guaranteed for such ``T + V`` systems,
which every splittable system here is. Kick-first tables (``a_0 = a_s = 0``) merge the
last kick of a step with the first of the next ("first same as last"), so a step costs one
force evaluation less than its number of kicks whenever no state has to be saved in between.

The whole time loop is compiled (numba). A system that offers
:class:`~poissonkit.numerics.integrators.base.LoopKernels` (e.g. moving point masses with
central all-pairs potentials, :mod:`poissonkit.numerics.nbody.direct`) is integrated with
those: the same numbers, with the kick inlined into the loop.

With ``adaptive=True`` the step is ``h_n = h · (g(y_n) + g(y_{n+1}))/2`` with
``g = min(1, (d_min/d_ref)^{3/2})`` (``d_min`` the smallest pair distance; the time-symmetrised
criterion of Hut, Makino & McMillan, ApJ 443 (1995) L93, solved by fixed-point iteration),
which refines close encounters; invariants are still kept to round-off.

With ``compensated=True`` every increment of the drift and the kick (``r``, ``p``, ``m`` and the
rotation of ``ν`` written as an increment) is added by Kahan's compensated summation
(W. Kahan, Comm. ACM 8 (1965) 40), carrying the rounding errors in a second array ``c`` (state
``y − c``, checkpointed with ``y``). On orbits that amplify perturbations ~1e5-fold, as the
seed scenes, this moves the final-state error floor from ~1e-10 to ~1e-12 for ~1.2× the time
per step.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from poissonkit.contracts import (CompiledFunction, CompiledKernels, Event, HasCompiledKernels,
                                  HasStateCheck, System)
from poissonkit.errors import InputError
from poissonkit.numerics.events import event_thresholds
from poissonkit.numerics.integrators.base import (RUNNING, HasLoopKernels, RawResult, SaveBuffer,
                                                  StepFn, check_step, step_tail)
from poissonkit.numerics.integrators.capabilities import SPLITTING
from poissonkit.numerics.integrators.compositions import TABLES as HIGH_ORDER_TABLES
from poissonkit.numerics.integrators.compositions import HighOrderTable
from poissonkit.numerics.integrators.driver import Control, LoopProblem, LoopState, drive
from poissonkit.numerics.integrators.glue import (ChunkResult, Scratch, describe, fixed_grid,
                                                  guard_division)
from poissonkit.numerics.jit import jit
from poissonkit.numerics.kernels import copy_into
from poissonkit.traits import offers

# --------------------------------------------------------------------------- coefficients
_SUZUKI_P = 1.0 / (4.0 - 4.0 ** (1.0 / 3.0))
#: outermost first, centre last (the centre weight w_0 = 1 − 2 Σ w_i is added by _weights)
_YOSHIDA6_A = (0.784513610477560, 0.235573213359357, -1.17767998417887)
_YOSHIDA8_D = (0.914844246229740, 0.253693336566229, -1.44485223686048, -0.158240635368243,
               1.93813913762276, -1.96061023297549, 0.102799849391985)


#: Kahan & Li (1997), outermost first, centre last (the centre follows from the sum = 1)
_KAHAN_LI6 = (0.39216144400731413928, 0.33259913678935943860, -0.70624617255763935981,
              0.082213596293550800230)
_KAHAN_LI8 = (0.74167036435061295345, -0.40910082580003159400, 0.19075471029623837995,
              -0.57386247111608226666, 0.29906418130365592384, 0.33462491824529818378,
              0.31529309239676659663)


def _symmetric(outer_to_inner: tuple[float, ...]) -> list[float]:
    w0 = 1.0 - 2.0 * sum(outer_to_inner)
    return list(outer_to_inner) + [w0] + list(reversed(outer_to_inner))


WEIGHTS: dict[int, list[float]] = {
    2: [1.0],
    4: [_SUZUKI_P, _SUZUKI_P, 1.0 - 4.0 * _SUZUKI_P, _SUZUKI_P, _SUZUKI_P],
    6: _symmetric(_KAHAN_LI6),
    8: _symmetric(_KAHAN_LI8),
}

#: Yoshida's compositions of order 6 and 8, for comparison.
WEIGHTS_YOSHIDA: dict[int, list[float]] = {
    6: _symmetric(_YOSHIDA6_A),
    8: _symmetric(_YOSHIDA8_D),
}


def drift_kick_coefficients(weights: list[float]) -> tuple[np.ndarray, np.ndarray]:
    """Merge Strang stages ``S(w h)`` into ``φ_T(a_0 h) φ_V(b_0 h) … φ_V(b_{s-1} h) φ_T(a_s h)``."""
    s = len(weights)
    a = np.empty(s + 1)
    b = np.array(weights, dtype=float)
    a[0] = weights[0] / 2
    for k in range(1, s):
        a[k] = (weights[k - 1] + weights[k]) / 2
    a[s] = weights[-1] / 2
    return a, b


@dataclass(frozen=True)
class Scheme:
    """A drift–kick table ``φ_T(a_0 h) φ_V(b_0 h) φ_T(a_1 h) … φ_V(b_{s-1} h) φ_T(a_s h)``.

    Attributes
    ----------
    name
        Integrator name (``splitting<order>_<authors>``).
    order
        Classical order; for ``nystrom`` tables only on ``T + V`` systems with
        ``{V, {V, {V, T}}} = 0`` (every splittable system, see the module doc).
    a, b
        Drift and kick coefficients, ``len(a) = len(b) + 1``, each summing to 1.
    reference
        Where the coefficients come from.
    nystrom
        True for RKN tables (fewer order conditions, see above).
    """

    name: str
    order: int
    a: tuple[float, ...]
    b: tuple[float, ...]
    reference: str
    nystrom: bool = False

    def __post_init__(self) -> None:
        if len(self.a) != len(self.b) + 1 or not self.b:
            raise InputError(f"scheme {self.name!r}: need len(a) = len(b) + 1 >= 2")
        for label, c in (("a", self.a), ("b", self.b)):
            if abs(math.fsum(c) - 1.0) > 1e-14:
                raise InputError(f"scheme {self.name!r}: coefficients {label} sum to "
                                 f"{math.fsum(c)!r}, not 1")

    @property
    def fsal(self) -> bool:
        """Kick-first and kick-last: consecutive steps share one force evaluation."""
        return self.a[0] == 0.0 and self.a[-1] == 0.0

    @property
    def evaluations(self) -> int:
        """Force evaluations per step in a long run (kicks, less one if :attr:`fsal`)."""
        return len(self.b) - (1 if self.fsal else 0)


def symmetric_kick_first(a_outer: tuple[float, ...], b_outer: tuple[float, ...]) -> Scheme:
    """Arrays of a symmetric kick-first table from its outer halves (helper for the tables).

    ``b_outer`` are the kicks from the outside in, ``a_outer`` the drifts between them; the
    central coefficient(s) follow from ``Σ a = Σ b = 1``: one central kick and two equal
    central drifts if ``len(b_outer) == len(a_outer) + 1``, else two equal central kicks and one
    central drift. Returns a placeholder :class:`Scheme` holding ``a, b``.
    """
    if len(b_outer) == len(a_outer) + 1:
        ac = 0.5 - math.fsum(a_outer)
        bc = 1.0 - 2.0 * math.fsum(b_outer)
        a = (0.0, *a_outer, ac, ac, *reversed(a_outer), 0.0)
        b = (*b_outer, bc, *reversed(b_outer))
    else:
        ac = 1.0 - 2.0 * math.fsum(a_outer)
        bc = 0.5 - math.fsum(b_outer)
        a = (0.0, *a_outer, ac, *reversed(a_outer), 0.0)
        b = (*b_outer, bc, bc, *reversed(b_outer))
    return Scheme("", 0, a, b, "")


def _table(name: str, order: int, half: Scheme, reference: str, nystrom: bool) -> Scheme:
    return Scheme(name, order, half.a, half.b, reference, nystrom)


_BLANES_MOAN = ("S. Blanes, P. C. Moan, Practical symplectic partitioned Runge–Kutta and "
                "Runge–Kutta–Nyström methods, J. Comput. Appl. Math. 142 (2002) 313–330")

#: SRKN_14^a drifts and kicks from the outside in (the central ones follow from the sums)
_SRKN14A_A = (0.0378593198406116, 0.102635633102435, -0.0258678882665587, 0.314241403071447,
              -0.130144459517415, 0.106417700369543, -0.00879424312851058)
_SRKN14A_B = (0.09171915262446165, 0.183983170005006, -0.05653436583288827,
              0.004914688774712854, 0.143761127168358, 0.328567693746804)

#: Optimised tables selectable by name (``Splitting(scheme=...)``); the registered ones are
#: listed in :mod:`poissonkit.numerics.hooks`.
SCHEMES: dict[str, Scheme] = {s.name: s for s in (
    # Blanes & Moan SRKN_6^b, order 4, 7 kicks (6 evaluations with FSAL)
    _table("splitting4_bm", 4, symmetric_kick_first(
        (0.245298957184271, 0.604872665711080),
        (0.0829844064174052, 0.396309801498368, -0.0390563049223486)),
        _BLANES_MOAN + ", SRKN_6^b", nystrom=True),
    # Blanes & Moan SRKN_14^a, order 6, 14 kicks between 15 drifts (drift first)
    Scheme("splitting6_bm", 6,
           (*_SRKN14A_A, 1.0 - 2.0 * math.fsum(_SRKN14A_A), *reversed(_SRKN14A_A)),
           (*_SRKN14A_B, 0.5 - math.fsum(_SRKN14A_B), 0.5 - math.fsum(_SRKN14A_B),
            *reversed(_SRKN14A_B)),
           _BLANES_MOAN + ", SRKN_14^a", nystrom=True),
)}


def _high_order(t: HighOrderTable) -> Scheme:
    a, b = drift_kick_coefficients(list(t.weights)) if t.weights else (t.a, t.b)
    return Scheme(t.name, t.order, tuple(map(float, a)), tuple(map(float, b)), t.reference,
                  t.nystrom)


# orders 8 and 10 beyond the Blanes–Moan tables (Sofroniou–Spaletta, Blanes–Casas–Escorihuela)
SCHEMES.update((t.name, _high_order(t)) for t in HIGH_ORDER_TABLES.values())


# --------------------------------------------------------------------------- compiled loop
_runners: dict[tuple[int, bool], tuple[CompiledFunction, CompiledKernels]] = {}


def _runner(kernels: CompiledKernels, compensated: bool = False) -> CompiledFunction:
    """The compiled time loop specialised to one system's kernels (cached).

    With ``compensated`` the loop uses the kernels' compensated drift and kick, which carry the
    rounding error of every increment in a second array ``c`` (the state is ``y − c``); saved
    rows are ``y − c``. Without it the loop's arithmetic is the plain one (``c`` unused).
    """
    key = (id(kernels.kick), bool(compensated))
    hit = _runners.get(key)
    if hit is not None:
        return hit[0]
    min_distance = kernels.min_distance
    tail = step_tail(kernels, compensated)
    # the kernels are called directly at each call site, never through an inlined wrapper:
    # an inlined function's arguments are copies of the caller's variables, and numba counts
    # a reference to every array of `data` and `work` for each copy (~100 atomic operations
    # per stage, as much as a small system's kick)
    plain_drift, plain_kick = kernels.drift, kernels.kick
    comp_drift, comp_kick = kernels.drift_compensated, kernels.kick_compensated
    comp = bool(compensated)  # a compile-time constant of the closures below

    @jit(inline="always")
    def one_step(y, c, h, a, b, data, work):
        nb = b.shape[0]
        for s in range(nb):
            if comp:
                comp_drift(y, c, a[s] * h, data)
                comp_kick(y, c, b[s] * h, data, work)
            else:
                plain_drift(y, a[s] * h, data)
                plain_kick(y, b[s] * h, data, work)
        if comp:
            comp_drift(y, c, a[nb] * h, data)
        else:
            plain_drift(y, a[nb] * h, data)

    @jit(inline="always")
    def fsal_step(y, c, h, a, b, data, work, pending, merge):
        # kick-first table (a_0 = a_s = 0): `pending` = this step's first kick was already
        # applied (merged into the previous step's last kick); `merge` = do the same now
        # (one drift and one kick call site: each is inlined where it is called)
        nb = b.shape[0]
        for s in range(1 if pending else 0, nb):
            if s > 0:
                if comp:
                    comp_drift(y, c, a[s] * h, data)
                else:
                    plain_drift(y, a[s] * h, data)
            # kicks at one configuration add exactly: B(b h) B(b' h) = B((b + b') h)
            hb = (b[nb - 1] + b[0]) * h if merge and s == nb - 1 else b[s] * h
            if comp:
                comp_kick(y, c, hb, data, work)
            else:
                plain_kick(y, hb, data, work)

    @jit
    def g_factor(y, data, work, dref):
        d = min_distance(y, data, work)
        if d >= dref:
            return 1.0
        return (d / dref) ** 1.5

    @jit
    def remember(y, c, dst):
        # the state y − c of a compensated loop (y itself otherwise)
        if comp:
            for i in range(y.shape[0]):
                dst[i] = y[i] - c[i]
        else:
            copy_into(y, dst)

    @jit
    def run(y, c, t_orig, t0, t_end, h, n_total, adaptive, dref, iters, a, b, fsal, data, work,
            save_every, step0, max_steps, out_t, out_y, contact, escape, watch, trial, ctrial,
            prev, prev2, hist):
        """Advance ``y`` in place. Returns (status, t, steps_done_in_call, n_saved, value).

        ``c`` is the compensation array of a compensated loop (state ``y − c``; unused, may be
        empty, otherwise); ``ctrial`` is its scratch copy for the adaptive trial step.

        ``fsal`` (kick-first tables, fixed step, no events): consecutive steps share their
        boundary kick; ``y`` is a true state again at every saved step and when returning.

        With events, ``prev``/``prev2`` receive the states at the two previous step ends and
        ``hist`` = [D_a, D_b, D_c, t_a, t_b] the smallest centre distances there and now and
        the two previous start times (see :mod:`poissonkit.numerics.locate`).
        """
        nsave = 0
        t = t0
        k = 0
        track = contact > 0.0 or escape > 0.0 or watch > 0.0
        pending = False
        while k < max_steps:
            gstep = step0 + k + 1
            if track:
                copy_into(prev, prev2)
                remember(y, c, prev)
                hist[0] = hist[1]
                hist[1] = hist[2]
                hist[3] = hist[4]
                hist[4] = t
            if adaptive:
                # the trial steps and the step itself: one call site of `one_step`
                g0 = g_factor(y, data, work, dref)
                hk = h * g0
                last = False
                for it in range(iters + 1):
                    hs = hk
                    if it < iters:
                        copy_into(y, trial)
                        if comp:
                            copy_into(c, ctrial)
                        hs = min(hk, t_end - t)
                    else:
                        last = t + hk >= t_end
                        if last:
                            hk = t_end - t
                        hs = hk
                    one_step(y, c, hs, a, b, data, work)
                    if it < iters:
                        hk = 0.5 * h * (g0 + g_factor(y, data, work, dref))
                        copy_into(trial, y)
                        if comp:
                            copy_into(ctrial, c)
                t = t_end if last else t + hk
            elif fsal:
                merge = not track and gstep < n_total and gstep % save_every != 0 and \
                    k + 1 < max_steps
                fsal_step(y, c, h, a, b, data, work, pending, merge)
                pending = merge
                last = gstep >= n_total
                t = t_end if last else t_orig + gstep * h
            else:
                one_step(y, c, h, a, b, data, work)
                last = gstep >= n_total
                t = t_end if last else t_orig + gstep * h
            k += 1
            status, nsave, value = tail(y, c, t, RUNNING, last, last or gstep % save_every == 0,
                                        track, data, work, contact, escape, watch, hist, out_t,
                                        out_y, nsave)
            if status != RUNNING:
                return status, t, k, nsave, value
        return RUNNING, t, k, nsave, 0.0

    _runners[key] = (run, kernels)
    return run


class Splitting:
    """Symmetric composition of the exact kinetic and potential flows (see module doc).

    Parameters
    ----------
    order
        2, 4, 6 or 8 (the compositions of Strang steps in :data:`WEIGHTS`).
    scheme
        Instead of ``order``: a table of :data:`SCHEMES` by name (e.g. ``"splitting4_bm"``) or a
        :class:`Scheme`; its order replaces ``order``.
    adaptive
        Use the time-symmetrised distance-based step (close encounters).
    reference_distance
        ``d_ref`` of the adaptive step factor (internal length); 0 = initial smallest distance.
    iterations
        Fixed-point iterations of the symmetrised step (each costs one extra step).
    compensated
        Add every drift and kick increment with Kahan-compensated summation (the system's
        ``drift_compensated``/``kick_compensated`` kernels; :class:`~poissonkit.errors.InputError`
        if it has none). Removes the round-off floor of long runs at small steps (final-state
        errors ~1e-10 on the seed scenes become ~1e-12) for ~1.2× the time per step; off by
        default, and then the arithmetic is exactly the plain one.
    """

    family = SPLITTING.family
    capabilities = SPLITTING.capabilities

    def __init__(self, order: int = 6, adaptive: bool = False, reference_distance: float = 0.0,
                 iterations: int = 1, scheme: str | Scheme | None = None,
                 compensated: bool = False) -> None:
        if isinstance(scheme, str):
            if scheme not in SCHEMES:
                raise InputError(f"unknown splitting scheme {scheme!r}; available: "
                                 f"{', '.join(sorted(SCHEMES))}")
            scheme = SCHEMES[scheme]
        if scheme is not None and not isinstance(scheme, Scheme):
            raise InputError(f"scheme must be a name or a Scheme, got {type(scheme).__name__}")
        if scheme is None and order not in WEIGHTS:
            raise InputError(f"splitting order must be one of {sorted(WEIGHTS)}, got {order!r}")
        if iterations < 0:
            raise InputError(f"iterations must be >= 0, got {iterations!r}")
        if not isinstance(compensated, (bool, np.bool_)):
            raise InputError(f"compensated must be True or False, got {compensated!r}")
        self.compensated = bool(compensated)
        self.adaptive = bool(adaptive)
        self.reference_distance = float(reference_distance)
        self.iterations = int(iterations)
        if scheme is None:
            self.order = order
            self.a, self.b = drift_kick_coefficients(WEIGHTS[order])
            base = f"splitting{order}"
        else:
            self.order = scheme.order
            self.a, self.b = np.array(scheme.a), np.array(scheme.b)
            base = scheme.name
        self.name = base + ("_adaptive" if adaptive else "") + \
            ("_compensated" if self.compensated else "")

    @property
    def fsal(self) -> bool:
        """Kick-first table: consecutive fixed steps share their boundary kick."""
        return bool(self.a[0] == 0.0 and self.a[-1] == 0.0 and len(self.b) > 1)

    @property
    def stages(self) -> int:
        """Number of potential kicks per step (force evaluations: :attr:`evaluations`)."""
        return len(self.b)

    @property
    def evaluations(self) -> int:
        """Force evaluations per fixed step in a long run (one less than the kicks if FSAL)."""
        return len(self.b) - (1 if self.fsal else 0)

    def integrate(self, system: System, y0: np.ndarray, t_end: float, *, step: float | None,
                  tol: float | None, events: Sequence[Event] = (), progress: bool = False,
                  save_every: int = 1, t0: float = 0.0,
                  control: Control | None = None) -> RawResult:
        """Integrate from ``t0`` to ``t_end`` with the compiled loop (see :func:`drive` for
        ``control``: checkpoints, streaming, stop requests)."""
        if not offers(system, HasCompiledKernels) or not system.kernels.splittable:
            raise InputError(f"{self.name} needs a system with exact kinetic/potential flows "
                             f"(NBodySystem, TwoBodySystem); {type(system).__name__} has none — "
                             "use 'midpoint' or a scipy method")
        # a leaner form of the kernels for the loop (same numbers), if the system has one
        lean = system.loop_kernels() if offers(system, HasLoopKernels) else None
        kernels, data, work = (lean if lean is not None
                               else (system.kernels, system.data, system.work()))
        comp = self.compensated
        if comp and kernels.kick_compensated is None:
            raise InputError(f"{self.name}: compensated=True needs compensated drift/kick kernels, "
                             f"which {type(system).__name__} does not have (TwoBodySystem and "
                             "NBodySystem have them); use compensated=False")
        if offers(system, HasStateCheck):
            system.check_state(y0)
        if self.adaptive:  # the base step as given; the loop adapts it
            h = check_step(step, t_end - t0, self.name)
            n_total = max(1, math.ceil((t_end - t0) / h - 1e-12))
        else:
            h, n_total = fixed_grid(self.name, step, t0, t_end)
        contact, escape, watch = event_thresholds(events)
        run = _runner(kernels, comp)
        fsal = self.fsal and not self.adaptive
        y = np.array(y0, dtype=float)
        trial = np.empty_like(y)
        # compensation arrays (state = y − c); empty and unused in the plain loop
        ctrial = np.zeros_like(y) if comp else np.empty(0)
        dref = self.reference_distance
        if self.adaptive and dref <= 0:
            dref = float(kernels.min_distance(y, data, work))
            if not np.isfinite(dref) or dref <= 0:
                raise InputError("adaptive splitting needs at least two bodies at distinct places")
        scratch = Scratch(y.size)
        table = (self.adaptive, dref, self.iterations, self.a, self.b, fsal, data, work)

        def chunk(st: LoopState, max_steps: int, buf: SaveBuffer) -> ChunkResult:
            status, t_new, k, nsave, value = run(
                st.y, st.comp, t0, st.t, t_end, h, n_total, *table, save_every, st.steps,
                max_steps, buf.cur_t, buf.cur_y, contact, escape, watch, trial, ctrial, st.prev,
                st.prev2, st.hist)
            return status, t_new, k, nsave, 0, value

        def replay(st: LoopState) -> tuple[StepFn, np.ndarray]:
            cs = st.comp.copy()

            def one_step(ys: np.ndarray, ts: float, done: int) -> tuple[int, float]:
                out = run(ys, cs, t0, ts, t_end, h, n_total, *table, save_every, done, 1,
                          scratch.t, scratch.y, 0.0, 0.0, 0.0, trial, ctrial, ys, ys,
                          scratch.hist)
                return out[0], out[1]
            return one_step, st.y.copy()

        def advance(ys: np.ndarray, s: float) -> np.ndarray:
            # one step from a state (event location): the compensation starts from zero
            yc = np.array(ys, dtype=float)
            cc = np.zeros_like(yc) if comp else ctrial
            run(yc, cc, 0.0, 0.0, s, s, 1, False, dref, 0, self.a, self.b, fsal, data, work, 1,
                0, 1, scratch.t, scratch.y, 0.0, 0.0, 0.0, trial, ctrial, yc, yc, scratch.hist)
            return yc - cc if comp else yc

        def done(st: LoopState) -> bool:
            return st.t >= t_end if self.adaptive else st.steps >= n_total

        # "compensated" only when set, so that checkpoints of plain runs keep their description
        more = {"dref": float(dref).hex(), **({"compensated": True} if comp else {})}
        raw = drive(LoopProblem(
            self.name, system, y, t0, t_end, guard_division(self.name, chunk, replay), advance,
            done, describe(self.name, h, t0, t_end, n_total, save_every, y, **more),
            min(n_total // save_every + 2, 4096) if not self.adaptive else 4096, events,
            progress, save_every, control, compensated=comp))
        if self.adaptive:
            raw.nfev = raw.steps * self.stages * (1 + self.iterations)
        else:  # FSAL: one more kick wherever a state was saved (upper bound)
            raw.nfev = raw.steps * self.evaluations + (len(raw.t) if fsal else 0)
        raw.extra.update(step=h, order=self.order, adaptive=self.adaptive, compensated=comp)
        return raw
