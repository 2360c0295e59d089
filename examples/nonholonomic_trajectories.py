"""Integrate each non-holonomic system in physical time and plot a trajectory with the drift of
its invariants (<out>/nonholonomic_<name>.png; the docs/nonholonomic/ pages show these PNGs).

Conformally Hamiltonian systems go through the time change dtau = |N| dt with the implicit
midpoint rule (poissonkit.numerics.conformal); the BMF ball, whose multiplier d/(g s) changes sign
on the sphere, is integrated directly with DOP853.

Run:  python examples/nonholonomic_trajectories.py [--out DIR] [--t-end 20] [NAME ...]

The PNGs go to ./nonholonomic-img by default, so a trial run never rewrites tracked files.
To regenerate the images shown in the docs, write them over the tracked ones on purpose:

    python examples/nonholonomic_trajectories.py --out docs/img
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from poissonkit_nonholonomic import ball, routh, suslov, veselova

from poissonkit.numerics.conformal import (
    ConformalIntegrator,
    LambdifiedSystem,
    solve_direct,
)

Y6 = np.array([0.0, 0.6, 0.8, 1.0, -0.5, 0.2])
CASES = {
    "chaplygin_ball": (ball.chaplygin_ball, Y6, "conformal"),
    "chaplygin_gyrostat": (ball.chaplygin_gyrostat, Y6, "conformal"),
    "chaplygin_ball_sphere_bmf": (ball.chaplygin_ball_sphere_bmf, Y6, "direct"),
    "veselova": (veselova.veselova, np.array([0.0, 0.6, 0.8, 0.4, -0.3, 0.5]), "conformal"),
    "veselova_gyrostat": (veselova.veselova_gyrostat, np.array([0.0, 0.6, 0.8, 0.4, -0.3, 0.5]),
                          "conformal"),
    "routh_sphere": (routh.routh_sphere, np.array([0.3, 0.0, np.sqrt(0.91), 0.3, -0.2, 1.0]),
                     "conformal"),
    "suslov": (suslov.suslov, np.array([0.0, 0.6, 0.8, 1.0, 0.5, 0.0]), "conformal"),
    "suslov_potential": (suslov.suslov_potential, np.array([0.0, 0.6, 0.8, 0.3, -0.2, 0.0]),
                         "conformal"),
}


def run(name: str, t_end: float, step: float):
    build, y0, how = CASES[name]
    system = build()
    if how == "direct":
        L = LambdifiedSystem(system)
        sol, _ = solve_direct(system, y0, t_end, tol=1e-11, backend="python", compiled=L)
        return system, sol.t, sol.y, L
    ci = ConformalIntegrator(system, y0, backend="python")
    sol = ci.solve(y0, t_end, step)
    return system, sol.t[:-1], sol.y[:-1], ci.compiled


def plot(name: str, out: Path, t_end: float = 20.0, step: float = 0.01) -> Path:
    system, t, y, comp = run(name, t_end, step)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(7.0, 2.6), dpi=80)
    for k in range(3):
        ax1.plot(t, y[:, k], lw=0.8, label=str(system.coords[k]))
    ax1.set_xlabel("t")
    ax1.set_title(f"{name}: trajectory", fontsize=8)
    ax1.legend(fontsize=6, loc="upper right")
    vals = {"H": comp.energy(y)}
    if comp.casimir_names:
        vals.update(zip(comp.casimir_names, comp.casimirs(y).T))
    if comp.integral_names:
        vals.update(zip(comp.integral_names, comp.integrals(y).T))
    for label, v in vals.items():
        ax2.semilogy(t[1:], np.abs(v[1:] - v[0]) + 1e-17, lw=0.7, label=label[:22])
    ax2.set_xlabel("t")
    ax2.set_title("|F(t) - F(0)| of the invariants", fontsize=8)
    ax2.legend(fontsize=5, loc="lower right")
    fig.tight_layout()
    out.mkdir(parents=True, exist_ok=True)
    path = out / f"nonholonomic_{name}.png"
    fig.savefig(path)
    plt.close(fig)
    return path


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="nonholonomic-img",
                    help="output folder (default ./nonholonomic-img; "
                         "use --out docs/img to regenerate the docs images)")
    ap.add_argument("--t-end", type=float, default=20.0)
    ap.add_argument("names", nargs="*")
    args = ap.parse_args()
    for name in args.names or list(CASES):
        path = plot(name, Path(args.out), args.t_end)
        print(f"{path}  ({path.stat().st_size // 1024} KB)")


if __name__ == "__main__":
    main()
