"""The compiled Wisdom–Holman time loop around one system's kernels."""

from __future__ import annotations

import numpy as np

from poissonkit.contracts import CompiledFunction, CompiledKernels
from poissonkit.numerics.integrators.base import NONFINITE, RUNNING, step_end_kernels, step_tail
from poissonkit.numerics.integrators.wisdom_holman.kepler import drift_all
from poissonkit.numerics.integrators.wisdom_holman.kicks import (gravity_kick,
                                                                 gravity_modified_kick,
                                                                 gravity_steps, kick_kernels)
from poissonkit.numerics.jit import jit

runners: dict[tuple[int, bool, bool],
              tuple[CompiledFunction, CompiledFunction, CompiledKernels]] = {}


def runner(kernels: CompiledKernels, pure_gravity: bool, corrected: bool = True
           ) -> tuple[CompiledFunction, CompiledFunction]:
    """The compiled Wisdom–Holman loop and corrector around one system's kernels (cached).

    ``pure_gravity``: the interaction is Newtonian gravity alone, so the kick is the dedicated
    pair loop :func:`gravity_kick_accel` instead of the system's general force kernel.
    ``corrected``: the loop may be called with a corrector kick (``tau ≠ 0``) or a symplectic
    corrector (``proc`` rows); without, those paths are left out of the compiled loop (a
    compile-time constant: the plain map compiles no corrector), and calling it with either
    is an error of the caller.
    """
    key = (id(kernels.forces), bool(pure_gravity), bool(corrected))
    hit = runners.get(key)
    if hit is not None:
        return hit[0], hit[1]
    remember = step_end_kernels(kernels)[0]
    tail = step_tail(kernels)

    kk = kick_kernels(kernels.forces, pure_gravity)
    kick, correct, modified_kick = kk.kick, kk.correct, kk.modified_kick
    process, sync_processed, sync = kk.process, kk.sync_processed, kk.sync
    corrected = bool(corrected)  # a compile-time constant of `run` (its branches are pruned)

    @jit
    def run(y, xj, uj, carried, m, mfrac, inv_eta, gm, gmass, t_orig, t_end, h, n_total, c, dk,
            tau, proc, data, work, save_every, step0, max_steps, out_t, out_y, contact, escape,
            watch, prev, prev2, hist):
        """Advance the Jacobi state ``xj, uj`` (written to ``y`` at every save and on return).

        Returns (status, t, steps done, saved, value). The last step ends at ``t_end`` itself
        (``t_orig + n_total h`` may miss it by an ulp, and a piece of a sampled run that ends
        short of its end reads as stopped by an event). Without corrector the last drift of a
        step is merged into the first drift of the next; with it, the closing corrector of a
        step and the opening one of the next are one kick (both depend on positions only).
        ``carried = [pending drift, corrector opened]`` is that merge's state between calls:
        a call ends by writing into ``y`` the state at ``t`` computed from *copies*, so where
        a chunk ends never changes the arithmetic (resumed runs are bit-identical). With a
        symplectic corrector ``proc`` (rows of ``Z`` operators), ``xj, uj`` are the processed
        coordinates and every state written to ``y`` is corrected first.

        With events, every step end is synchronised into ``y`` and checked; ``prev``, ``prev2``
        and ``hist`` are the event-search memory (see :mod:`poissonkit.numerics.locate`).
        """
        n = m.shape[0]
        ybuf = y.copy()
        r = np.empty((n, 3))
        u = np.empty((n, 3))
        a = np.empty((n, 3))
        aj = np.empty((n, 3))
        xt = np.empty((n, 3))
        a_plus = np.empty((n, 3))
        ns = dk.shape[0]
        nsave = 0
        pending = carried[0]
        opened = carried[1] != 0.0
        track = contact > 0.0 or escape > 0.0 or watch > 0.0
        # the corrector kick: with a symplectic corrector in the middle of the (one-stage)
        # step, sharing the kick's force evaluation; else on both ends (SABAC_n)
        mid = tau != 0.0 and proc.shape[0] > 0
        ends = tau != 0.0 and not mid
        ok = True
        t = t_orig + step0 * h
        next_save = (step0 // save_every + 1) * save_every
        k = 0
        while k < max_steps:
            if pure_gravity and not track and not ends:
                # the steps before the next one that writes out, in one tight call
                free = min(max_steps - k, next_save - (step0 + k) - 1,
                           n_total - (step0 + k) - 1)
                if free > 0:
                    pending, fine = gravity_steps(xj, uj, free, pending, c, dk, h,
                                                  2.0 * tau if mid else 0.0, m, mfrac, inv_eta,
                                                  gm, gmass, r, a, aj, xt, a_plus)
                    ok = fine and ok
                    k += free
                    t = t_orig + (step0 + k) * h
                    continue
            gstep = step0 + k + 1
            if track:
                remember(y, prev, prev2, hist, t)
            # (the corrector kick is a call, not inlined: with gravity alone it is
            # gravity_correct's arithmetic, compiled once instead of at each site)
            if corrected and ends and not opened:
                correct(xj, uj, tau, m, mfrac, inv_eta, gm, gmass, ybuf, r, a, aj, xt, a_plus,
                        data, work)
            for s in range(ns):
                # (one call site per inlined kernel: each site is compiled again)
                ok = drift_all(xj, uj, gm, pending + c[0] * h if s == 0 else c[s] * h) and ok
                # (the gravity-only calls take no force-kernel tuple: passing it, even to an
                # inlined function, costs reference counting at every call)
                if corrected and mid:
                    if pure_gravity:
                        gravity_modified_kick(xj, uj, dk[s] * h, 2.0 * tau, m, mfrac, inv_eta,
                                              gm, gmass, r, a, aj, xt, a_plus)
                    else:
                        modified_kick(xj, uj, dk[s] * h, 2.0 * tau, m, mfrac, inv_eta, gm,
                                      gmass, ybuf, r, a, aj, xt, a_plus, data, work)
                elif pure_gravity:
                    gravity_kick(xj, uj, dk[s] * h, m, mfrac, inv_eta, gm, gmass, r, a, aj)
                else:
                    kick(xj, uj, dk[s] * h, m, mfrac, inv_eta, gm, gmass, ybuf, r, a, aj, data,
                         work)
            pending = 0.0
            last = gstep >= n_total
            k += 1
            t = t_end if last else t_orig + gstep * h
            saving = gstep == next_save  # (a counter: no integer division per step)
            if saving:
                next_save += save_every
            need = last or saving or track
            if ends or need:
                ok = drift_all(xj, uj, gm, c[ns] * h) and ok
            if corrected and ends:
                tau_end = tau if need else 2.0 * tau
                correct(xj, uj, tau_end, m, mfrac, inv_eta, gm, gmass, ybuf, r, a, aj, xt,
                        a_plus, data, work)
                opened = not need
            elif not need:
                pending = c[ns] * h
            if not need:
                continue
            if corrected:
                ok = sync_processed(xj, uj, proc, h, m, mfrac, inv_eta, gm, gmass, data, work, y,
                                    r, u) and ok
            else:
                sync(xj, uj, m, mfrac, inv_eta, y, r, u)
            status, nsave, value = tail(y, y, t, RUNNING if ok else NONFINITE, last,
                                        last or saving, track, data, work, contact, escape,
                                        watch, hist, out_t, out_y, nsave)
            if status == NONFINITE:
                carried[0] = pending
                carried[1] = 1.0 if opened else 0.0
            if status != RUNNING:
                return status, t, k, nsave, value
        # chunk done between saves: the state at t, from copies (the merge state is kept)
        carried[0] = pending
        carried[1] = 1.0 if opened else 0.0
        xc = xj.copy()
        uc = uj.copy()
        ok = drift_all(xc, uc, gm, pending) and ok
        if corrected and opened:
            correct(xc, uc, -tau, m, mfrac, inv_eta, gm, gmass, ybuf, r, a, aj, xt, a_plus, data,
                    work)
        if corrected:
            ok = sync_processed(xc, uc, proc, h, m, mfrac, inv_eta, gm, gmass, data, work, y, r,
                                u) and ok
        else:
            sync(xc, uc, m, mfrac, inv_eta, y, r, u)
        return RUNNING if ok else NONFINITE, t, k, nsave, 0.0

    runners[key] = (run, process, kernels)
    return run, process
