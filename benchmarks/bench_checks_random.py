"""Random-point field checks against the exact method, in the same process.

For each system, the field claims (first integrals, ``X = N P dH``, invariant measure) are
checked with ``method="exact"`` (baseline) and ``method="random"`` (3 points, one shared
``RandomPoints``); the script prints both times and the ratio exact / random. Also prints the
wall time of ``verify_system`` (mode ``auto``) for the BMF ball and, with ``--routh``, the
Routh sphere without its Jacobi check.

Usage::

    python benchmarks/bench_checks_random.py            # Chaplygin ball, Veselova
    python benchmarks/bench_checks_random.py --bmf      # + the BMF ball (exact: minutes)
    python benchmarks/bench_checks_random.py --routh    # + verify_system of the Routh sphere
"""

from __future__ import annotations

import argparse
import time

from poissonkit.structure.checks import (
    is_conformally_hamiltonian,
    is_first_integral,
    is_invariant_measure,
)
from poissonkit.structure.randompoints import RandomPoints


def _field_claims(system, method: str) -> tuple[float, bool]:
    t0 = time.perf_counter()
    # both methods on the system's constraint surface (the unit sphere here)
    kw: dict = {"method": method, "constraints": system.constraints}
    if method == "random":
        kw["points"] = RandomPoints(system.coords, system.constraints, trials=3, seed=20140301)
    ok = True
    for F in system.integrals.values():
        ok &= bool(is_first_integral(system, F, **kw))
    if system.original is not None:
        ok &= bool(is_conformally_hamiltonian(system.original, system.structure,
                                              system.hamiltonian, system.multiplier, **kw))
    if system.measure is not None:
        ok &= bool(is_invariant_measure(system, system.measure, **kw))
    return time.perf_counter() - t0, ok


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bmf", action="store_true", help="include the BMF ball (slow exact)")
    parser.add_argument("--routh", action="store_true", help="verify_system of the Routh sphere")
    args = parser.parse_args()
    from poissonkit_nonholonomic import ball, routh, veselova
    from poissonkit_nonholonomic.verify import verify_system

    systems = [("nh.chaplygin_ball", ball.chaplygin_ball()), ("nh.veselova", veselova.veselova())]
    if args.bmf:
        systems.append(("nh.chaplygin_ball_sphere_bmf", ball.chaplygin_ball_sphere_bmf()))
    print(f"{'system':32s} {'exact [s]':>10s} {'random [s]':>11s} {'exact/random':>13s}")
    for name, s in systems:
        tr, okr = _field_claims(s, "random")   # random first: exact then cannot profit from
        te, oke = _field_claims(s, "exact")    # derivatives cached by sympy
        assert okr and oke, name
        print(f"{name:32s} {te:10.3f} {tr:11.3f} {te / tr:13.1f}")
    t0 = time.perf_counter()
    rep = verify_system(ball.chaplygin_ball_sphere_bmf())
    print(f"verify_system(nh.chaplygin_ball_sphere_bmf) auto: {time.perf_counter() - t0:.2f} s, "
          f"ok={rep['ok']}")
    if args.routh:
        t0 = time.perf_counter()
        rep = verify_system(routh.routh_sphere(), jacobi=False)
        print(f"verify_system(nh.routh_sphere, jacobi=False) auto: "
              f"{time.perf_counter() - t0:.2f} s, ok={rep['ok']}")


if __name__ == "__main__":
    main()
