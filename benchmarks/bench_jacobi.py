"""Jacobi check: poissonkit's ``check_jacobi`` vs poissongeometry's ``is_poisson_bivector``.

Cases (all given to both sides in PoissonGeometry's dict format, coordinates ``x1 .. xn``):

* e(3) on R^6;
* seed 000's 18-dimensional ``canonical(r, p) + e(3) + e(3)``;
* the Chaplygin-ball bracket (survey (38)) with symbolic ``d, a1, a2, a3`` and
  ``g = sqrt(1 - d (a1 x1^2 + a2 x2^2 + a3 x3^2))``.

Times are CPU seconds of this process (``time.process_time``) for both sides, so that other
load on a shared machine does not distort the ratio; wall times are printed too. Ours is timed
twice: ``check`` (``check_jacobi`` on a built Bivector, exact method — the
``auto`` default picks it for all three cases) and ``parse+check`` (building the Bivector from the
same string dict first). The baseline, ``PoissonGeometry(dim).is_poisson_bivector(dict)``, runs once
per case (it takes tens of seconds and more); ``--baseline-timeout`` caps each run, and a
capped run is reported as a lower bound. Both answers are compared.

Run::

    python benchmarks/bench_jacobi.py            # everything (several minutes)
    python benchmarks/bench_jacobi.py --quick    # ours only, no baseline

Needs ``poissongeometry`` (bench/test extra).
"""

from __future__ import annotations

import argparse
import signal
import statistics
import time

import sympy as sp


def e3_dict() -> dict:
    return {(1, 5): "x3", (1, 6): "-x2", (2, 4): "-x3", (2, 6): "x1", (3, 4): "x2",
            (3, 5): "-x1", (4, 5): "x6", (4, 6): "-x5", (5, 6): "x4"}


def two_tops_dict() -> dict:
    out = {(1, 4): "1", (2, 5): "1", (3, 6): "1"}
    for off in (6, 12):
        for (i, j), v in e3_dict().items():
            sign = "-" if v.startswith("-") else ""
            k = int(v.lstrip("-x")) + off
            out[(i + off, j + off)] = f"{sign}x{k}"
    return out


def chaplygin_dict() -> tuple[dict, tuple[str, ...]]:
    g = "sqrt(1 - d*(a1*x1**2 + a2*x2**2 + a3*x3**2))"
    MAg = "(a1*x1*x4 + a2*x2*x5 + a3*x3*x6)"
    gam = {1: "x1", 2: "x2", 3: "x3"}
    mom = {1: "x4", 2: "x5", 3: "x6"}
    out = {}
    # upper block g Gamma: Gamma[i, j] = eps_ijk gamma_k
    eps = {(1, 2): (3, 1), (1, 3): (2, -1), (2, 3): (1, 1)}
    for (i, j), (k, s) in eps.items():
        sign = "" if s > 0 else "-"
        out[(i, j + 3)] = f"{sign}{g}*{gam[k]}"
        out[(j, i + 3)] = f"{'-' if s > 0 else ''}{g}*{gam[k]}"
        # lower block g [M]_eps - d (M, A gamma)/g Gamma
        out[(i + 3, j + 3)] = f"{sign}({g}*{mom[k]} - d*{MAg}*{gam[k]}/{g})"
    return out, ("d", "a1", "a2", "a3")


def ours(bivector: dict, dim: int, params: tuple[str, ...] = (), repeat: int = 5):
    from poissonkit.structure import Bivector, check_jacobi
    from poissonkit.structure.parsing import parse_expression

    coords = sp.symbols(f"x1:{dim + 1}", real=True)
    extra = {p: sp.Symbol(p, positive=True) for p in params}

    def build():
        mat = sp.zeros(dim, dim)
        for (i, j), v in bivector.items():
            e = parse_expression(v, coords, extra)
            mat[i - 1, j - 1], mat[j - 1, i - 1] = e, -e
        return Bivector.from_matrix(mat, coords)

    P = build()
    checks, totals, walls, result = [], [], [], None
    for _ in range(repeat):
        t0, w0 = time.process_time(), time.perf_counter()
        result = check_jacobi(P)
        checks.append(time.process_time() - t0)
        walls.append(time.perf_counter() - w0)
        t0 = time.process_time()
        check_jacobi(build())
        totals.append(time.process_time() - t0)
    return result, statistics.median(checks), statistics.median(totals), statistics.median(walls)


class _Timeout(Exception):
    pass


def theirs(bivector: dict, dim: int, timeout: float):
    from poisson.poisson import PoissonGeometry

    def handler(signum, frame):
        raise _Timeout

    old = signal.signal(signal.SIGALRM, handler)
    signal.setitimer(signal.ITIMER_REAL, timeout)
    t0, w0 = time.process_time(), time.perf_counter()
    try:
        answer = PoissonGeometry(dim).is_poisson_bivector({k: v for k, v in bivector.items()})
    except _Timeout:
        answer = None
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)
    return answer, time.process_time() - t0, time.perf_counter() - w0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="skip the poissongeometry baseline")
    ap.add_argument("--baseline-timeout", type=float, default=900.0,
                    help="cap of one baseline run in seconds (default 900)")
    args = ap.parse_args()
    cha, params = chaplygin_dict()
    cases = [("e(3)", e3_dict(), 6, ()), ("canonical + e(3) + e(3) (18-dim)", two_tops_dict(), 18, ()),
             ("Chaplygin ball, symbolic d, a1..a3", cha, 6, params)]
    print(f"{'case':38s} {'ours check':>11s} {'parse+check':>12s} {'poissongeometry':>16s}"
          f" {'ratio':>9s} {'ratio(parse)':>12s}   wall: ours / theirs")
    for name, biv, dim, prm in cases:
        res, t_check, t_total, w_check = ours(biv, dim, prm)
        line = f"{name:38s} {t_check:10.4f}s {t_total:11.4f}s"
        if args.quick:
            print(line + f" {'-':>16s}   (ours: {'Poisson' if res.is_poisson else 'NOT Poisson'},"
                  f" {res.method}; wall {w_check:.4f}s)")
            continue
        answer, t_base, w_base = theirs(biv, dim, args.baseline_timeout)
        bound = ">" if answer is None else " "
        line += (f" {bound}{t_base:14.2f}s {bound}{t_base / t_check:8.0f}x"
                 f" {bound}{t_base / t_total:11.0f}x   {w_check:.4f}s / {w_base:.1f}s")
        if answer is not None and answer != res.is_poisson:
            line += "  DISAGREE"
        print(line, flush=True)
    print("CPU seconds; ours: median of 5 runs (auto = exact method); baseline: one run")


if __name__ == "__main__":
    main()
