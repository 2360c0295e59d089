"""Speed against error for the Chaplygin ball and the Routh sphere (docs/performance.md).

For each system: a reference run (DOP853, tol 1e-13), then
* the time-changed implicit midpoint rule in tau (``ConformalIntegrator``, compiled and python
  backends) at several steps, and
* the direct physical-time integration of X = N P dH with DOP853 (compiled RHS) at several
  tolerances and with the implicit midpoint rule in t,
printing the final-state error, the largest invariant drift and the wall time. Ratios are
against the compiled DOP853 run of about the same error, measured in the same process.

Run:  python benchmarks/bench_nonholonomic.py [--t-end 20] [--quick]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from poissonkit_nonholonomic.ball import chaplygin_ball
from poissonkit_nonholonomic.routh import routh_sphere

from poissonkit.numerics.conformal import (
    ConformalIntegrator,
    invariant_drift,
    solve_direct,
)
from poissonkit.numerics.system import compile_system


def _row(name, err, drift, wall, steps):
    print(f"  {name:34s} err {err:9.2e}  max-casimir-drift {drift:9.2e}  wall {wall:8.4f} s"
          f"  steps {steps}")
    return {"name": name, "err": err, "drift": drift, "wall": wall}


def bench_python(label, hsys, y0, t_end, steps, tols):
    """Python backend only (lambdified field, scipy DOP853 and the numpy midpoint loop): used for
    the Routh sphere, whose compile_system (symbolic Jacobian of the rank-2 bivector field) does
    not finish in 20 minutes."""
    print(f"\n== {label} [python backend]: t_end = {t_end}, y0 = {[float(v) for v in y0]}")
    from poissonkit.numerics.conformal import LambdifiedSystem

    cp = ConformalIntegrator(hsys, y0, backend="python")
    L = LambdifiedSystem(hsys)  # the physical-time field (cp.compiled is the tau field)
    ref, _ = solve_direct(hsys, y0, t_end, tol=1e-13, backend="python", compiled=L)
    y_ref = ref.y[-1]
    cas = list(L.casimir_names) + [n for n in L.integral_names if "Jellett" in n]
    rows = []
    for tol in tols:
        sol, wall = solve_direct(hsys, y0, t_end, tol=tol, backend="python", compiled=L)
        d = invariant_drift(L, sol.y)
        rows.append(_row(f"direct scipy DOP853 tol={tol:g}", float(np.max(np.abs(sol.y[-1] - y_ref))),
                         max(d[c] for c in cas), wall, sol.steps))
    for h in steps:
        sol = cp.solve(y0, t_end, h)
        d = sol.invariant_drift()
        rows.append(_row(f"tau-midpoint python h={h:g}", float(np.max(np.abs(sol.y_final - y_ref))),
                         max(d[c] for c in cas), sol.wall_time, sol.steps))
    _ratios(rows)
    return rows


def _ratios(rows):
    base = [r for r in rows if r["name"].startswith("direct")]
    print("  wall-time ratios against the cheapest direct run at least as accurate:")
    for r in rows:
        if r["name"].startswith("direct"):
            continue
        cands = [b for b in base if b["err"] <= r["err"]]
        if not cands:
            print(f"    {r['name']:34s} (more accurate than every direct run)")
            continue
        b = max(cands, key=lambda b: b["err"])
        print(f"    {r['name']:34s} {r['wall'] / b['wall']:7.2f} x  (vs {b['name']}; "
              f"casimir drift {r['drift']:.1e} vs {b['drift']:.1e})")


def bench(label, hsys, y0, t_end, steps, tols, quick):
    print(f"\n== {label}: t_end = {t_end}, y0 = {[float(v) for v in y0]}")
    t0 = time.perf_counter()
    compiled = compile_system(hsys)
    print(f"  compile_system: {time.perf_counter() - t0:.1f} s")
    ref = solve_direct(hsys, y0, t_end, method="dop853", tol=1e-13, compiled=compiled)
    ref = solve_direct(hsys, y0, t_end, method="dop853", tol=1e-13, compiled=compiled)  # warm
    y_ref = ref.y[-1]
    cas = list(compiled.casimir_names)
    rows = []

    def casdrift(y):
        d = invariant_drift(compiled, y)
        return max(d[c] for c in cas) if cas else 0.0

    for tol in tols:
        sol = solve_direct(hsys, y0, t_end, method="dop853", tol=tol, compiled=compiled)
        rows.append(_row(f"direct dop853 tol={tol:g}", float(np.max(np.abs(sol.y[-1] - y_ref))),
                         casdrift(sol.y), sol.wall_time, sol.steps))
    t0 = time.perf_counter()
    cc = ConformalIntegrator(hsys, y0, backend="compiled")
    cc.solve(y0, min(t_end, 0.1), 0.05)  # numba compilation of the midpoint loop
    solve_direct(hsys, y0, min(t_end, 0.1), method="midpoint", step=0.05, compiled=compiled)
    print(f"  time-changed system compiled + warmed up: {time.perf_counter() - t0:.1f} s")
    for h in steps:
        sol = cc.solve(y0, t_end, h)
        rows.append(_row(f"tau-midpoint compiled h={h:g}", float(np.max(np.abs(sol.y_final - y_ref))),
                         max(sol.invariant_drift()[c] for c in cas) if cas else 0.0,
                         sol.wall_time, sol.steps))
        if not quick:
            sol = solve_direct(hsys, y0, t_end, method="midpoint", step=h, tol=1e-14,
                               compiled=compiled)
            rows.append(_row(f"t-midpoint compiled h={h:g}", float(np.max(np.abs(sol.y[-1] - y_ref))),
                             casdrift(sol.y), sol.wall_time, sol.steps))
    _ratios(rows)
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--t-end", type=float, default=20.0)
    ap.add_argument("--quick", action="store_true", help="fewer runs")
    ap.add_argument("--only", choices=("ball", "routh"), help="one system only")
    ap.add_argument("--python-only", action="store_true", help="skip the numba-compiled runs")
    args = ap.parse_args()
    steps = [0.04, 0.02, 0.01, 0.005]
    tols = [1e-6, 1e-8, 1e-10]
    if args.only in (None, "ball") and not args.python_only:
        bench("Chaplygin ball I=(1,2,3), d=1", chaplygin_ball(1, 2, 3, 1),
              np.array([0.0, 0.6, 0.8, 1.0, -0.5, 0.2]), args.t_end, steps, tols, args.quick)
    if args.only in (None, "ball"):
        bench_python("Chaplygin ball I=(1,2,3), d=1", chaplygin_ball(1, 2, 3, 1),
                     np.array([0.0, 0.6, 0.8, 1.0, -0.5, 0.2]), args.t_end, steps, tols)
    if args.only in (None, "routh"):
        bench_python("Routh sphere R=2, a=1/2, m=3, I1=5, I3=7, U=10 gamma3", routh_sphere(),
                     np.array([0.3, 0.0, np.sqrt(0.91), 0.3, -0.2, 1.0]), args.t_end, steps, tols)


if __name__ == "__main__":
    main()
