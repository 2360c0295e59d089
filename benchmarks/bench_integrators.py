"""Time to a final-state error of 1e-7: compiled splittings vs scipy DOP853 on the same RHS.

Usage::

    python benchmarks/bench_integrators.py [--target 1e-7] [--quick]

Two problems in nondimensional units (both two-body centre-of-mass systems, compiled RHS):

* ``orbit``: two dipolar tops with a short-range repulsion (``U = (c3 − 3 c1 c2)/r³ + 1/(2 r⁶)``,
  μ = 2, α = 3, 5) on a bounded near-circular orbit with co-rotating axes, 20 periods;
* ``encounter``: two dumbbell magnets (Zub's seed eq. (16), half-lengths l = 0.5, charges 1)
  on a fly-by whose closest approach is below 1.5 l (printed), spinning (α|m| ≈ 5).

The reference is DOP853 at rtol = atol = 1e-14, checked against the order-8 splitting at a small
step (their difference is printed). Each method is swept over steps (splittings) or tolerances
(DOP853); the cheapest run whose error ``max|y − y_ref| / max|y_ref|`` is ≤ the target is
reported, with wall time (compiled kernels warm; best of 3) and the ratio to DOP853.
"""

from __future__ import annotations

import argparse

import numpy as np
import sympy as sp

from poissonkit.errors import PoissonkitError
from poissonkit.numerics import TwoBodySystem, solve

R, C1, C2, C3 = sp.symbols("r c1 c2 c3", real=True)


def unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


def dumbbell(l1, l2, k1, k2):
    U = 0
    for e1 in (1, -1):
        for e2 in (1, -1):
            R2 = R**2 + l1**2 + l2**2 + 2 * R * (e2 * l2 * C2 - e1 * l1 * C1) - 2 * e1 * e2 * l1 * l2 * C3
            U += e1 * e2 / sp.sqrt(R2)
    return k1 * k2 * U


def problems():
    bound = (C3 - 3 * C1 * C2) / R**3 + R**-6 / 2
    orbit = TwoBodySystem(None, None, 3.0, 5.0, bound, reduced_mass=2.0)
    v = np.sqrt(1.5)
    y_orbit = np.concatenate([[1, 0, 0], [0, 2 * v, 0], unit([np.cos(.05), np.sin(.05), 0]),
                              [0.05, 0, v / 3], unit([np.cos(.05), -np.sin(.05), 0.05]),
                              [0, -0.05, v / 5]])
    period = 2 * np.pi / v
    enc = TwoBodySystem(None, None, 4.0, 4.0, dumbbell(0.5, 0.5, 1.0, 1.0), reduced_mass=1.0)
    # closest approach 0.74 = 1.48 l (printed by main)
    y_enc = np.concatenate([[-4, 0.15, 0], [1.0, 0, 0], unit([1, 0.3, 0.2]), [0.2, 0.1, 1.2],
                            [1.0, 0, 0], [1.0, -0.3, 0.4]])
    return {"orbit": (orbit, y_orbit, 20 * period), "encounter": (enc, y_enc, 8.0)}


def timed(system, y0, t_end, method, **kw):
    best, sol = np.inf, None
    for _ in range(3):
        sol = solve(system, y0, t_end, method, save_every=10**9, **kw)
        best = min(best, sol.wall_time)
    return best, sol


def error(sol, ref):
    return float(np.max(np.abs(sol.y[-1] - ref)) / np.max(np.abs(ref)))


def sweep(system, y0, t_end, ref, target, method, values, kind, options=None):
    """Cheapest run reaching ``target`` over a decreasing sequence of steps / tolerances."""
    for val in values:
        kw = {"step": val} if kind == "step" else {"tol": val, "options": {"atol": val}}
        if options:
            kw["options"] = {**kw.get("options", {}), **options}
        try:
            wall, sol = timed(system, y0, t_end, method, **kw)
        except PoissonkitError as exc:  # a too-large step may blow up: try the next one
            print(f"    {method} {kind}={val:.3g}: {type(exc).__name__}")
            continue
        err = error(sol, ref)
        if err <= target:
            return wall, val, err, sol.steps
    return np.nan, np.nan, np.nan, 0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--target", type=float, default=1e-7)
    ap.add_argument("--quick", action="store_true", help="fewer sweep points")
    args = ap.parse_args()
    import warnings

    warnings.filterwarnings("ignore", message="At least one element of `rtol`")
    for name, (system, y0, t_end) in problems().items():
        ref = solve(system, y0, t_end, "dop853", tol=1e-14, options={"atol": 1e-14})
        check = solve(system, y0, t_end, "splitting8", step=t_end / 20000)
        rmin = np.min(np.linalg.norm(ref.y[:, :3], axis=1))
        print(f"\n{name}: t_end = {t_end:.4g}, min distance {rmin:.3g}, reference check "
              f"|DOP853(1e-14) − splitting8(h = t_end/2e4)| = {error(check, ref.y[-1]):.2e}, "
              f"max energy error of the reference {np.max(ref.energy_error()):.1e}")
        yref = ref.y[-1]
        factor = 1.25 if not args.quick else 1.6
        rows = []
        tols = [10.0 ** (-k) for k in np.arange(6, 14.5, 0.5)]
        rows.append(("dop853",) + sweep(system, y0, t_end, yref, args.target, "dop853", tols, "tol"))
        for method, h0 in (("splitting4", 0.05), ("splitting6", 0.1), ("splitting8", 0.2)):
            steps = [h0 / factor**k for k in range(40)]
            rows.append((method,) + sweep(system, y0, t_end, yref, args.target, method, steps,
                                          "step"))
            if name == "encounter":
                rows.append((method + " adaptive",) + sweep(
                    system, y0, t_end, yref, args.target, method, steps, "step",
                    {"adaptive": True}))
                rows.append((method + " adaptive it=0",) + sweep(
                    system, y0, t_end, yref, args.target, method, steps, "step",
                    {"adaptive": True, "iterations": 0}))
        base = rows[0][1]
        print(f"  {'method':<22}{'wall [ms]':>10}{'step/tol':>11}{'error':>10}{'steps':>8}"
              f"{'DOP853/this':>13}")
        for meth, wall, val, err, nst in rows:
            print(f"  {meth:<22}{1e3 * wall:>10.2f}{val:>11.3g}{err:>10.1e}{nst:>8}"
                  f"{base / wall:>13.1f}")


if __name__ == "__main__":
    main()
