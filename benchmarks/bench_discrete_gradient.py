"""Speed against error: discrete gradient against implicit midpoint (docs/performance.md).

Three symbolic systems with non-constant brackets and Hamiltonians that are not quadratic (so
midpoint keeps the energy only to O(h^2)): so(3) with a quartic H (average vector field, 2
Gauss-Legendre nodes), the Chaplygin ball in conformal form (Gonzalez discrete gradient) and
Plank's Lotka-Volterra bracket with H = sum x_i - i ln x_i (Gonzalez). For each system and
step: the final-state error against DOP853 at rtol 1e-13, the largest relative energy error
along the run, the wall time (fastest of five runs, compiled code warm), the evaluations per
step (one evaluation = one pass over the field or the discrete gradient) and the ratio of the
discrete gradient's time to midpoint's at the same step, measured in the same process.

Run:  python benchmarks/bench_discrete_gradient.py [--t-end 20] [--plot docs/img/x.png]
"""

from __future__ import annotations

import argparse

import numpy as np
import sympy as sp

from poissonkit.numerics import compile_system, solve
from poissonkit.plugin import system
from poissonkit.structure import Bivector, HamiltonianSystem
from poissonkit.structure.blocks import so3

REPEAT = 5
STEPS = (0.04, 0.02, 0.01, 0.005)


def systems():
    """(label, compiled system, initial state) of the three cases."""
    P = so3()
    m1, m2, m3 = P.coords
    H = (m1**2 + m2**2 / 2 + m3**2 / 3) / 2 + (m1**4 + 2 * m3**4) / 4 + m1 * m2 * m3**2
    yield "so(3), quartic H", compile_system(HamiltonianSystem(P, H)), np.array([0.6, -0.8, 0.5])
    ball = system("nh.chaplygin_ball").build(I1=1, I2=2, I3=3, d=1)
    yield "Chaplygin ball", compile_system(ball), np.array([0.0, 0.6, 0.8, 1.0, -0.5, 0.2])
    x = sp.symbols("x1 x2 x3", positive=True)
    a = sp.Matrix([[0, 1, -1], [-1, 0, 1], [1, -1, 0]])
    Pl = Bivector.from_matrix(sp.Matrix(3, 3, lambda i, j: a[i, j] * x[i] * x[j]), x)
    Hl = sum(x[i] - (i + 1) * sp.log(x[i]) for i in range(3))
    yield ("Plank Lotka-Volterra", compile_system(HamiltonianSystem(Pl, Hl)),
           np.array([1.5, 1.0, 2.0]))


def run(cs, y0, t_end, method, h):
    """(final state, max relative energy error, best wall time, evaluations per step)."""
    sols = [solve(cs, y0, t_end, method, step=h, save_every=10) for _ in range(REPEAT)]
    sol = min(sols, key=lambda s: s.wall_time)
    e = cs.energy(sol.y)
    return (sol.y[-1], float(np.max(np.abs(e - e[0])) / abs(e[0])), sol.wall_time,
            sol.nfev / sol.steps)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--t-end", type=float, default=20.0)
    ap.add_argument("--plot", default="", help="write the speed-error figure (PNG) here")
    args = ap.parse_args()
    rows = []
    print("| system | h | method | final error | max rel. energy error | wall (s) | evals/step "
          "| DG/midpoint time |")
    print("|---|---|---|---|---|---|---|---|")
    for label, cs, y0 in systems():
        ref = solve(cs, y0, args.t_end, "dop853", tol=1e-13, options={"atol": 1e-14}).y[-1]
        for method in ("discrete_gradient", "midpoint"):  # compile once before timing
            solve(cs, y0, 0.1, method, step=0.01)
        for h in STEPS:
            out = {m: run(cs, y0, args.t_end, m, h) for m in ("discrete_gradient", "midpoint")}
            ratio = out["discrete_gradient"][2] / out["midpoint"][2]
            for m, (yend, de, wall, evals) in out.items():
                err = float(np.max(np.abs(yend - ref)))
                shown = f"{ratio:.2f}" if m == "discrete_gradient" else ""
                print(f"| {label} | {h} | {m} | {err:.1e} | {de:.1e} | {wall:.4f} | "
                      f"{evals:.2f} | {shown} |")
                rows.append((label, m, h, err, de, wall))
    if args.plot:
        import matplotlib
        import matplotlib.ticker

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        labels = list(dict.fromkeys(r[0] for r in rows))
        fig, axes = plt.subplots(1, len(labels), figsize=(4 * len(labels), 3.4))
        for ax, label in zip(axes, labels):
            for m, style in (("discrete_gradient", "o-"), ("midpoint", "s--")):
                pts = [(r[5], r[3], r[4]) for r in rows if r[0] == label and r[1] == m]
                ax.loglog([p[0] for p in pts], [p[1] for p in pts], style, label=f"{m}: state")
                ax.loglog([p[0] for p in pts], [max(p[2], 1e-17) for p in pts], style,
                          alpha=0.45, label=f"{m}: energy")
            ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
            ax.set_title(label)
            ax.set_xlabel("wall time (s)")
            ax.grid(True, which="both", alpha=0.3)
        axes[0].set_ylabel("final-state error / max rel. energy error")
        axes[-1].legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(args.plot, dpi=110)


if __name__ == "__main__":
    main()
