"""Seed 000's claim: the orbit is stable "with certain relations between the parameters".

The circular orbit of the seed (two antiparallel magnets side by side, 10 mm apart) is a
relative equilibrium for any spin about the axes, but without spin it is unstable: the
magnets turn towards the line of centres (head-to-tail is lower in energy) and hit each other.
A fast enough spin stabilises it gyroscopically. This script integrates the orbit with both
axes tilted by 0.02 rad for spin ratios alpha|m|/omega_orb = 0 (unstable) and 20 (stable),
prints the fate of each run and plots the centre distance against time
(seed000-stability.png).

    python examples/seed000_stability.py
"""

from __future__ import annotations

import math

import numpy as np

from poissonkit_magnets import seed000
from poissonkit.numerics.solver import solve


def distance_history(spin_ratio: float, tilt: float, periods: float):
    spec = seed000.default_run(periods=periods, spin_ratio=spin_ratio, tilt=tilt,
                               method="splitting8", step=2 * math.pi / 400)
    sol = solve(spec.system, spec.y0, spec.t_end, method="splitting8", step=spec.step)
    r = np.linalg.norm(sol.y[:, :3], axis=1)
    axis_gap = seed000.axis_distance(sol.y, seed000.nondimensional_parameters()["half_length1"])
    return sol.t / (2 * math.pi), r, axis_gap


def main() -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    tilt, periods = 0.02, 10.0
    table = seed000.parameter_table()
    contact = float(2 * table.a / seed000.circular_orbit(table=table).radius)
    fig, ax = plt.subplots(figsize=(6.4, 4.0), dpi=100)
    for spin, color in ((0.0, "tab:red"), (20.0, "tab:blue")):
        fate = seed000.orbit_fate(spin_ratio=spin, tilt=tilt, periods=periods)
        print(f"spin ratio {spin:5.1f}: {fate.kind:9s} after {fate.t_end:.3f} periods, "
              f"r in [{fate.r_min:.4f}, {fate.r_max:.4f}] R_orb, max |dH|/H = "
              f"{fate.max_energy_error:.1e}")
        t, r, gap = distance_history(spin, tilt, min(periods, fate.t_end))
        ax.plot(t, r, color=color, label=f"alpha|m|/omega = {spin:g}: {fate.kind}")
        ax.plot(t, gap, color=color, linestyle=":", linewidth=0.8)
    ax.axhline(contact, color="0.5", linewidth=0.8, linestyle="--", label="contact (2a)")
    ax.set_xlabel("t [orbital periods]")
    ax.set_ylabel("centre distance (solid), axis gap (dotted) [R_orb]")
    ax.set_title("Seed 000 orbit, axes tilted by 0.02 rad")
    ax.grid(True, color="0.85")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig("seed000-stability.png")
    print("wrote seed000-stability.png")


if __name__ == "__main__":
    main()
