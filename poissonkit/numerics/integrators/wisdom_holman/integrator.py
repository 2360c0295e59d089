"""The Wisdom–Holman integrator: options, checks and the glue around the shared driver."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from poissonkit.contracts import (DeclaresGravityOnly, Event, HasBodies, HasCompiledKernels,
                                  HasExternalFields, HasGravity, System)
from poissonkit.errors import InputError
from poissonkit.numerics.events import event_thresholds
from poissonkit.numerics.integrators.base import RawResult, SaveBuffer, StepFn, note_left_regime
from poissonkit.numerics.integrators.capabilities import WISDOM_HOLMAN
from poissonkit.numerics.integrators.driver import Control, LoopProblem, LoopState, drive
from poissonkit.numerics.integrators.glue import (ChunkResult, Scratch, describe, fixed_grid,
                                                  guard_division)
from poissonkit.numerics.integrators.wisdom_holman.jacobi import jacobi_of
from poissonkit.numerics.integrators.wisdom_holman.loop import runner
from poissonkit.numerics.integrators.wisdom_holman.regime import regime_problems
from poissonkit.numerics.integrators.wisdom_holman.tables import (CORRECTOR_G, TABLE_ORDERS,
                                                                  blanes_coefficients,
                                                                  corrector_operators,
                                                                  saba_coefficients)
from poissonkit.traits import offers


class WisdomHolman:
    """Wisdom–Holman splittings in Jacobi coordinates (see the module docstring).

    Parameters
    ----------
    stages
        ``n`` = 1 … 4 kicks per step of ``SABA_n`` (``n = 1``: the classical Wisdom–Holman map).
    corrector
        Add the ``SABAC_n`` corrector (removes the ``ε² h²`` error term; 3 extra force
        evaluations per step).
    table
        ``""`` for ``SABA_n``, else one of the Blanes et al. (2013) methods ``"10_4"``,
        ``"8_6_4"``, ``"10_6_4"``, ``"h8_4_4"``, ``"h8_6_4"``, ``"h10_6_4"`` (see
        :mod:`~poissonkit.numerics.integrators.wh_tables`; ``stages`` is then ignored).
    correctors
        Order 3, 5, 7, 11 or 17 of the Wisdom–Holman–Touma symplectic corrector applied to the
        map with ``stages = 1`` (as WHFast's ``corrector``), 0 for none: the state is carried in
        processed coordinates and corrected only where it is written out.

    Notes
    -----
    Needs an :class:`~poissonkit.numerics.nbody.NBodySystem` of moving point masses (no tops, no
    fixed bodies) with orientation-free potentials including Newtonian gravity between every
    pair (``AllPairs("gravity")``); body 0 is the central mass. When gravity is the only
    interaction (and there is no cutoff) the kick is a dedicated pair loop.
    """

    family = WISDOM_HOLMAN.family
    capabilities = WISDOM_HOLMAN.capabilities

    def __init__(self, stages: int = 1, corrector: bool = False, table: str = "",
                 correctors: int = 0) -> None:
        self.table = str(table)
        self.correctors = int(correctors)
        self.stages = int(stages)
        self.corrector = bool(corrector)
        if self.table:
            if self.corrector or self.correctors:
                raise InputError("the Blanes et al. tables take no corrector")
            self.c, self.d = blanes_coefficients(self.table)
            self.order = min(TABLE_ORDERS[self.table])
        else:
            self.c, self.d = saba_coefficients(self.stages)
            self.order = 4 if (self.corrector and self.stages >= 2) else 2
        # corrector kick τ = g h³ on each side of a step (SABAC_n: g = −g_n/2). With the
        # symplectic corrector, the ε² h² term left by the conjugation is half the kernel's:
        # half the kick cancels both (as WHFast's modified kick, h²/12 of the jerk per step,
        # against SABACM_1's h²/6)
        self.g = -CORRECTOR_G[self.stages] / 2.0 if self.corrector else 0.0
        if self.corrector and self.correctors:
            self.g /= 2.0
        self.proc = np.zeros((0, 2))
        if self.correctors:
            if self.table or self.stages != 1:
                raise InputError("symplectic correctors (correctors=k) apply to the Wisdom–Holman"
                                 f" map, stages=1; got stages={self.stages}")
            self.proc = corrector_operators(self.correctors)
        base = "wisdom_holman" + ("_corrected" if corrector else "")
        if self.table:
            self.name = f"{base}_{self.table}"
        else:
            self.name = base + (f"{self.stages}" if self.stages != 1 else "")
        if self.correctors:
            self.name += f"_c{self.correctors}"

    def integrate(self, system: System, y0: np.ndarray, t_end: float, *,
                  step: float | None, tol: float | None, events: Sequence[Event] = (),
                  progress: bool = False, save_every: int = 1, t0: float = 0.0,
                  control: Control | None = None) -> RawResult:
        """Integrate from ``t0`` to ``t_end`` with fixed step ``step`` on the shared driver
        (:func:`~poissonkit.numerics.integrators.driver.drive`: located events, checkpoints,
        streaming, stop requests)."""
        if not (offers(system, HasGravity) and offers(system, HasBodies)
                and offers(system, HasCompiledKernels)) or system.kernels.forces is None:
            raise InputError(f"{self.name} needs an NBodySystem of point masses with gravity; "
                             f"{type(system).__name__} is not one — use a splitting instead")
        G = system.gravity_constant()  # raises a typed error naming what is missing
        if system.n_tops or system.n_moving != len(system.bodies):
            raise InputError(f"{self.name} needs moving point masses only (no tops, no fixed "
                             "bodies)")
        if offers(system, HasExternalFields) and system.external_fields:
            # the Jacobi splitting lets the centre of mass drift freely: an external force on
            # it has no place in the kick
            raise InputError(f"{self.name} does not take external fields (the centre of mass "
                             "would drift freely); use a splitting instead")
        kernels = system.kernels
        h, n_total = fixed_grid(self.name, step, t0, t_end)
        contact, escape, watch = event_thresholds(events)
        # a map without corrector (tau = g h³ = 0, no `proc` rows) compiles a loop without one
        run, process = runner(kernels, _gravity_only(system),
                              corrected=self.g != 0.0 or self.proc.shape[0] > 0)
        y = np.array(y0, dtype=float)
        m = np.ascontiguousarray(system.data.mass, dtype=float)
        eta = np.cumsum(m)
        mfrac, inv_eta = m / eta, 1.0 / eta
        gm = G * eta
        gmass = G * m
        data, work = system.data, system.work()
        proc = self.proc
        xj, uj = jacobi_of(y, m)
        if proc.shape[0]:  # physical → processed coordinates
            process(xj, uj, proc, -1.0, h, m, mfrac, inv_eta, gm, gmass, data, work)
        tau = self.g * h ** 3
        c, dk = self.c, self.d
        per_step = dk.shape[0] + (3 if self.corrector else 0)
        scratch = Scratch(y.size)
        masses = (m, mfrac, inv_eta, gm, gmass)

        def chunk(st: LoopState, max_steps: int, buf: SaveBuffer) -> ChunkResult:
            status, t_new, k, nsave, value = run(
                st.y, st.carry["xj"], st.carry["uj"], st.carry["merge"], *masses, t0, t_end, h,
                n_total, c, dk, tau, proc, data, work, save_every, st.steps, max_steps,
                buf.cur_t, buf.cur_y, contact, escape, watch, st.prev, st.prev2, st.hist)
            return status, t_new, k, nsave, k * per_step, value

        def replay(st: LoopState) -> tuple[StepFn, np.ndarray]:
            start = {key: arr.copy() for key, arr in st.carry.items()}

            def one_step(ys: np.ndarray, ts: float, done: int) -> tuple[int, float]:
                out = run(ys, start["xj"], start["uj"], start["merge"], *masses, t0, t_end, h,
                          n_total, c, dk, tau, proc, data, work, save_every, done, 1, scratch.t,
                          scratch.y, 0.0, 0.0, 0.0, ys, ys, scratch.hist)
                return out[0], out[1]
            return one_step, st.y.copy()

        def advance(ys: np.ndarray, s: float) -> np.ndarray:
            # one whole step of length s from a state (event location)
            yc = np.array(ys, dtype=float)
            xs, us = jacobi_of(yc, m)
            if proc.shape[0]:
                process(xs, us, proc, -1.0, s, *masses, data, work)
            ts = self.g * s ** 3
            run(yc, xs, us, np.zeros(2), *masses, 0.0, s, s, 1, c, dk, ts, proc, data, work, 1, 0,
                1, scratch.t, scratch.y, 0.0, 0.0, 0.0, yc, yc, scratch.hist)
            return yc

        raw = drive(LoopProblem(
            self.name, system, y, t0, t_end, guard_division(self.name, chunk, replay), advance,
            lambda st: st.steps >= n_total,
            describe(self.name, h, t0, t_end, n_total, save_every, y, G=float(G).hex()),
            min(n_total // save_every + 2, 4096), events, progress, save_every, control,
            carry={"xj": xj, "uj": uj, "merge": np.zeros(2)}))
        raw.nfev = raw.steps * per_step
        raw.extra.update(step=h, stages=self.stages, corrector=self.corrector)
        # read from the saved states after the run: the trajectory is untouched
        names = tuple(str(b.name) for b in system.bodies)
        exact = m.shape[0] == 2 and _gravity_only(system)  # H_I = 0: no regime to leave
        note_left_regime(raw, self.name,
                         regime_problems(raw.y, m, float(G), h, names, exact=exact))
        if self.table:
            raw.extra["table"] = self.table
        if self.correctors:
            raw.extra["correctors"] = self.correctors
        return raw


def _gravity_only(system: System) -> bool:
    """True when Newtonian gravity over all bodies is the system's only interaction (no
    cutoff, no external field): the kick can then use :func:`gravity_kick_accel`."""
    return offers(system, DeclaresGravityOnly) and system.gravity_only

