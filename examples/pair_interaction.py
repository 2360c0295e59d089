"""What does a pair of magnets feel? Energy, force and torques of two cylinder magnets.

Runs every model at a few separations and shows what ``model="auto"`` picks for a 1 % force
tolerance. Usage: ``python examples/pair_interaction.py``.
"""

from __future__ import annotations

import numpy as np

from poissonkit.pairs import pair_interaction

# the seed 000 magnets: diameter 2.5 mm, height 20 mm, magnetisation 1.58359e6 A/m
MAGNET = dict(magnetization=1.58359e6, radius=1.25e-3, length=20e-3)


def main() -> None:
    nu1 = np.array([0.0, 0.0, 1.0])
    nu2 = np.array([0.6, 0.0, 0.8])
    direction = np.array([0.3, 0.2, 1.0]) / np.linalg.norm([0.3, 0.2, 1.0])
    for dist in (0.025, 0.05, 0.2):
        r = dist * direction
        print(f"separation {dist * 1e3:.0f} mm")
        for model in ("dipole", "dumbbell", "dumbbell_octupole", "cylinder"):
            out = pair_interaction(model, r, nu1, nu2, **MAGNET)
            print(f"  {model:18s} U = {out.energy: .6e} J   |F| = {np.linalg.norm(out.force):.6e} N"
                  f"   |T2| = {np.linalg.norm(out.torque2):.3e} N m"
                  f"   est. force error {out.estimated_error:.1e}")
        auto = pair_interaction("auto", r, nu1, nu2, tol=1e-2, **MAGNET)
        print(f"  auto (tol 1%) chose {auto.model!r}")
        # angular momentum balance: T1 + T2 + r x F = 0
        print(f"  |T1 + T2 + r x F| = "
              f"{np.linalg.norm(auto.torque1 + auto.torque2 + np.cross(r, auto.force)):.1e} N m")


if __name__ == "__main__":
    main()
