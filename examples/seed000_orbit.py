"""Seed 000: the parameter table, the circular orbit, and a run with its figures.

Prints the seed's Maple table derived from the magnet geometry (full precision), the orbit radius
recovered from the printed P_orb, then integrates 20 periods with the order-6 splitting method
and writes summary.json, trajectory.npz and the seed-style plots to ./seed000-orbit/.

    python examples/seed000_orbit.py
"""

from __future__ import annotations

import mpmath

from poissonkit import cli
from poissonkit_magnets import seed000


def main() -> None:
    table = seed000.parameter_table(dps=30)
    print("\n".join(table.lines()))
    radius = seed000.find_orbit_radius(seed000.SEED_PRINTED["P_orb"], table=table)
    orbit = seed000.circular_orbit(table=table)
    print(f"R_orb recovered from the printed P_orb: {mpmath.nstr(radius, 20)} m")
    print(f"P_orb = {mpmath.nstr(orbit.momentum, 20)} N*s (seed: {seed000.SEED_PRINTED['P_orb']})")
    print(f"T_orb = {mpmath.nstr(orbit.period, 20)} s")
    # the same as `poissonkit run --out seed000-orbit`
    cli.main(["run", "--out", "seed000-orbit", "--periods", "20"])


if __name__ == "__main__":
    main()
