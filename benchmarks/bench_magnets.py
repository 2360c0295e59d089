"""Cost per evaluation of each magnet model, relative to the point dipole, and (with
``--accuracy``) the error table of the cheap models against the exact cylinder.

Usage::

    python benchmarks/bench_magnets.py              # timings (ratios to the dipole)
    python benchmarks/bench_magnets.py --accuracy   # error table of docs/magnets.md

Timings call the compiled kernels ``f(r, c1, c2, c3)`` from a compiled loop (what the N-body
right-hand side does), after a warm-up call, all in the same process.
"""

from __future__ import annotations

import argparse
import math
import time

import numba
import numpy as np

from poissonkit.numerics.potentials import compile_potential
from poissonkit.plugin import potential

A, H, M = 1.25e-3, 20e-3, 1.58359e6
MU = M * math.pi * A * A * H

PARAMS = {
    "dipole": dict(moment1=MU, moment2=MU),
    "dumbbell": dict(moment1=MU, moment2=MU, half_length1=H / 2, half_length2=H / 2),
    "dumbbell_octupole": dict(moment1=MU, moment2=MU, radius1=A, radius2=A, length1=H,
                              length2=H),
    "cylinder": dict(magnetization1=M, magnetization2=M, radius1=A, radius2=A, length1=H,
                     length2=H),
    "dipole_cylinder_field": dict(magnetization1=M, radius1=A, length1=H, moment2=MU),
    "dumbbell_cylinder_field": dict(magnetization1=M, radius1=A, length1=H, moment2=MU,
                                    half_length2=H / 2),
    "dipole_loop": dict(current1=10.0, radius1=0.01, moment2=MU),
    "loops": dict(current1=10.0, current2=10.0, radius1=0.01, radius2=0.01),
    "superconducting_rings": dict(flux1=1e-6, flux2=1e-6, radius1=0.01, radius2=0.01,
                                  wire_radius1=1e-4, wire_radius2=1e-4),
}


@numba.njit
def _loop(kern, rs, c1, c2, c3):
    total = 0.0
    for i in range(rs.shape[0]):
        total += kern(rs[i], c1[i], c2[i], c3[i])[1]
    return total


def _configs(n: int, seed: int = 0):
    rng = np.random.default_rng(seed)
    v = rng.normal(size=(n, 3, 3))
    v /= np.linalg.norm(v, axis=2)[:, :, None]
    e, n1, n2 = v[:, 0], v[:, 1], v[:, 2]
    rs = rng.uniform(0.03, 0.3, size=n)
    return rs, (e * n1).sum(1), (e * n2).sum(1), (n1 * n2).sum(1)


def timings(repeat: int = 3) -> dict[str, float]:
    """Seconds per evaluation of every model (best of ``repeat``)."""
    out = {}
    for name, params in PARAMS.items():
        kern = compile_potential(potential(name), params)
        n = 20000 if name in ("dipole", "dumbbell", "dumbbell_octupole") else 40
        cfg = _configs(n)
        _loop(kern, *(x[:2] for x in cfg))  # compile the loop for this kernel
        best = math.inf
        for _ in range(repeat):
            t0 = time.perf_counter()
            _loop(kern, *cfg)
            best = min(best, (time.perf_counter() - t0) / n)
        out[name] = best
    return out


def accuracy_table() -> list[tuple]:
    """Worst relative force error, torque and energy error (over the dipole scale) of each
    cheap model vs the exact cylinder, per separation, over coaxial, side-by-side, T and
    random orientations."""
    from poissonkit.pairs import OverlapError, pair_interaction

    z, x = np.array([0, 0, 1.0]), np.array([1.0, 0, 0])
    rng = np.random.default_rng(2)
    families = [("coax", z, z, z), ("coax-anti", z, z, -z), ("side", x, z, z),
                ("side-anti", x, z, -z), ("T", x, x, z)]
    for k in range(8):
        v = rng.normal(size=(3, 3))
        v /= np.linalg.norm(v, axis=1)[:, None]
        families.append((f"random{k}", v[0], v[1], v[2]))
    rows = []
    for sep in (0.005, 0.010, 0.022, 0.025, 0.030, 0.050, 0.100, 0.200, 0.500, 1.0):
        worst = {m: [0.0, 0.0, 0.0] for m in ("dipole", "dumbbell", "dumbbell_octupole")}
        for _, e, n1, n2 in families:
            try:
                ex = pair_interaction("cylinder", sep * e, n1, n2, magnetization=M, radius=A,
                                      length=H)
            except OverlapError:
                continue
            scale = 1e-7 * MU * MU / sep ** 3
            for m in worst:
                o = pair_interaction(m, sep * e, n1, n2, magnetization=M, radius=A, length=H)
                w = worst[m]
                w[0] = max(w[0], np.linalg.norm(o.force - ex.force) / np.linalg.norm(ex.force))
                w[1] = max(w[1], max(np.linalg.norm(o.torque1 - ex.torque1),
                                     np.linalg.norm(o.torque2 - ex.torque2)) / scale)
                w[2] = max(w[2], abs(o.energy - ex.energy) / scale)
        rows.append((sep, worst))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--accuracy", action="store_true", help="print the error table")
    args = parser.parse_args()
    if args.accuracy:
        from poissonkit_magnets.fidelity import estimated_error

        print("| sep mm | model | F rel err | T err / dipole scale | U err / dipole scale "
              "| estimate (F) |")
        print("|---|---|---|---|---|---|")
        for sep, worst in accuracy_table():
            for m, (f, t, u) in worst.items():
                est = estimated_error(m, sep, A, H)
                print(f"| {sep * 1e3:g} | {m} | {f:.1e} | {t:.1e} | {u:.1e} | {est:.1e} |")
        return
    t = timings()
    base = t["dipole"]
    print(f"{'model':26s} {'s/eval':>10s} {'ratio to dipole':>16s}")
    for name, sec in t.items():
        print(f"{name:26s} {sec:10.2e} {sec / base:16.1f}")


if __name__ == "__main__":
    main()
