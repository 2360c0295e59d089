"""Speed against error for the Chaplygin ball and the Routh sphere (docs/performance.md).

For each system: a reference run (DOP853, tol 1e-13), then
* the time-changed implicit midpoint rule in tau (``ConformalIntegrator``, compiled and python
  backends) at several steps, and
* the direct physical-time integration of X = N P dH with DOP853 (compiled RHS) at several
  tolerances and with the implicit midpoint rule in t,
printing the final-state error, the largest invariant drift and the wall time. Ratios are
against the compiled DOP853 run of about the same error, measured in the same process.

The Routh sphere runs on the compiled path too (its large rational field takes the
large-expression code path of ``poissonkit.numerics.codegen``): by default from its original
equations (``field="original"``, checked against ``P dH``), ``--routh-field bivector`` compiles
``P dH`` itself. It also prints the code-generation and numba times, the compiled RHS against
the lambdified one at random states, and the speed-up of the compiled runs over the python
backend's runs of the same method.

Run:  python benchmarks/bench_nonholonomic.py [--t-end 20] [--quick] [--only routh]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from poissonkit_nonholonomic.ball import chaplygin_ball
from poissonkit_nonholonomic.routh import routh_sphere

from poissonkit.numerics.conformal import (
    ConformalIntegrator,
    LambdifiedSystem,
    invariant_drift,
    solve_direct,
)
from poissonkit.numerics.system import compile_system

REPEAT = 3  # timed runs per configuration (the fastest is kept: the machine may be loaded)


def _row(name, err, drift, wall, steps, idrift=None):
    extra = f"  max-integral-drift {idrift:9.2e}" if idrift is not None else ""
    print(f"  {name:34s} err {err:9.2e}  max-casimir-drift {drift:9.2e}{extra}  wall {wall:8.4f} s"
          f"  steps {steps}")
    return {"name": name, "err": err, "drift": drift, "wall": wall, "idrift": idrift}


def _best(run, wall_of, repeat=REPEAT):
    """Run ``run()`` ``repeat`` times; the result with the smallest wall time."""
    results = [run() for _ in range(repeat)]
    return min(results, key=wall_of)


def bench_python(label, hsys, y0, t_end, steps, tols):
    """Python backend only (lambdified field, scipy DOP853 and the numpy midpoint loop): the
    baseline of the compiled runs."""
    print(f"\n== {label} [python backend]: t_end = {t_end}, y0 = {[float(v) for v in y0]}")

    cp = ConformalIntegrator(hsys, y0, backend="python")
    L = LambdifiedSystem(hsys)  # the physical-time field (cp.compiled is the tau field)
    ref, _ = solve_direct(hsys, y0, t_end, tol=1e-13, backend="python", compiled=L)
    y_ref = ref.y[-1]
    cas = list(L.casimir_names) + [n for n in L.integral_names if "Jellett" in n]
    rows = []
    for tol in tols:
        sol, wall = _best(lambda tol=tol: solve_direct(hsys, y0, t_end, tol=tol,
                                                       backend="python", compiled=L),
                          lambda r: r[1])
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


def bench(label, hsys, y0, t_end, steps, tols, quick, field="bivector"):
    print(f"\n== {label} [compiled, field={field}]: t_end = {t_end}, y0 = {[float(v) for v in y0]}")
    t0 = time.perf_counter()
    compiled = compile_system(hsys, field=field)
    t1 = time.perf_counter()
    compiled.rhs(0.0, y0)
    t2 = time.perf_counter()
    compiled.jacobian(0.0, y0)
    t3 = time.perf_counter()
    compiled.energy(y0), compiled.casimirs(y0), compiled.integrals(y0)
    t4 = time.perf_counter()
    print(f"  compile_system: {t1 - t0:.1f} s code generation; numba: rhs {t2 - t1:.1f} s, "
          f"jacobian {t3 - t2:.1f} s (incl. its code generation), invariants {t4 - t3:.1f} s; "
          f"total {t4 - t0:.1f} s")
    ref = solve_direct(hsys, y0, t_end, method="dop853", tol=1e-13, compiled=compiled)
    ref = solve_direct(hsys, y0, t_end, method="dop853", tol=1e-13, compiled=compiled)  # warm
    y_ref = ref.y[-1]
    cas = list(compiled.casimir_names)
    ints = list(compiled.integral_names)
    rows = []

    def drifts(d):
        return (max(d[c] for c in cas) if cas else 0.0), (max(d[c] for c in ints) if ints else None)

    def casdrift(y):
        return drifts(invariant_drift(compiled, y))

    for tol in tols:
        sol = _best(lambda tol=tol: solve_direct(hsys, y0, t_end, method="dop853", tol=tol,
                                                 compiled=compiled), lambda r: r.wall_time)
        cd, idr = casdrift(sol.y)
        rows.append(_row(f"direct dop853 tol={tol:g}", float(np.max(np.abs(sol.y[-1] - y_ref))),
                         cd, sol.wall_time, sol.steps, idr))
    t0 = time.perf_counter()
    cc = ConformalIntegrator(hsys, y0, backend="compiled", field=field)
    cc.solve(y0, min(t_end, 0.1), 0.05)  # numba compilation of the midpoint loop
    solve_direct(hsys, y0, min(t_end, 0.1), method="midpoint", step=0.05, compiled=compiled)
    print(f"  time-changed system compiled + warmed up: {time.perf_counter() - t0:.1f} s")
    for h in steps:
        sol = _best(lambda h=h: cc.solve(y0, t_end, h), lambda r: r.wall_time)
        cd, idr = drifts(sol.invariant_drift())
        rows.append(_row(f"tau-midpoint compiled h={h:g}", float(np.max(np.abs(sol.y_final - y_ref))),
                         cd, sol.wall_time, sol.steps, idr))
        if not quick:
            sol = _best(lambda h=h: solve_direct(hsys, y0, t_end, method="midpoint", step=h,
                                                 tol=1e-14, compiled=compiled),
                        lambda r: r.wall_time)
            cd, idr = casdrift(sol.y)
            rows.append(_row(f"t-midpoint compiled h={h:g}", float(np.max(np.abs(sol.y[-1] - y_ref))),
                             cd, sol.wall_time, sol.steps, idr))
    _ratios(rows)
    return rows


def check_rhs(hsys, compiled, y0, count=200, seed=1):
    """Largest relative difference of the compiled RHS from the lambdified ``N P dH`` at random
    states near ``y0`` (gamma kept on the unit sphere)."""
    L = LambdifiedSystem(hsys)
    rng = np.random.default_rng(seed)
    worst = 0.0
    for _ in range(count):
        y = np.array(y0, dtype=float) + rng.normal(scale=0.5, size=len(y0))
        y[:3] /= np.linalg.norm(y[:3])
        a, b = compiled.rhs(0.0, y), L.rhs(0.0, y)
        worst = max(worst, float(np.max(np.abs(a - b)) / max(1.0, np.max(np.abs(b)))))
    print(f"  compiled RHS vs lambdified N P dH at {count} random states: max rel. diff {worst:.1e}")
    return worst


def speedups(compiled_rows, python_rows):
    """Wall-time ratio python / compiled for the same method and step / tolerance."""
    print("  speed-up of the compiled path over the python backend (same method and step/tol):")
    py = {r["name"].split()[-1] + (" midpoint" if "midpoint" in r["name"] else " dop853"): r
          for r in python_rows}
    for r in compiled_rows:
        key = r["name"].split()[-1] + (" midpoint" if "midpoint" in r["name"] else " dop853")
        if key in py and r["name"].startswith(("direct", "tau")):
            p = py[key]
            print(f"    {r['name']:34s} {p['wall'] / r['wall']:8.1f} x  (err {r['err']:.1e} vs "
                  f"{p['err']:.1e})")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--t-end", type=float, default=20.0)
    ap.add_argument("--quick", action="store_true", help="fewer runs")
    ap.add_argument("--only", choices=("ball", "routh"), help="one system only")
    ap.add_argument("--python-only", action="store_true", help="skip the numba-compiled runs")
    ap.add_argument("--routh-field", choices=("original", "bivector"), default="original",
                    help="compile the Routh sphere from its original equations or from P dH")
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
        label = "Routh sphere R=2, a=1/2, m=3, I1=5, I3=7, U=10 gamma3"
        hs = routh_sphere()
        y0 = np.array([0.3, 0.0, np.sqrt(0.91), 0.3, -0.2, 1.0])
        rows = []
        if not args.python_only:
            rows = bench(label, hs, y0, args.t_end, steps, tols, True, field=args.routh_field)
            check_rhs(hs, compile_system(hs, field=args.routh_field), y0)
        prows = bench_python(label, hs, y0, args.t_end, steps, tols)
        if rows:
            speedups(rows, prows)


if __name__ == "__main__":
    main()
