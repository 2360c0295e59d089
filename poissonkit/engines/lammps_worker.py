"""``python -m poissonkit.engines.lammps_worker SCRIPT``: run a LAMMPS input on every rank.

Started once (one rank) or by ``mpirun -np N`` (MPI domain decomposition; LAMMPS's library
initialises MPI itself). Sets the dipole prefactor to ``μ0/4π`` through ``dielectric`` (the
dipole styles use the Coulomb constant ``qqr2e`` of ``units si``), then runs the script.
"""

from __future__ import annotations

import sys


def main(argv: list[str]) -> int:
    """Run the LAMMPS input ``argv[0]`` (log to ``argv[1]`` if given)."""
    from poissonkit.conventions import MU0
    from poissonkit.engines.lammps_runtime import load_lammps

    lammps = load_lammps()
    log = argv[1] if len(argv) > 1 else "none"
    lmp = lammps(cmdargs=["-log", log, "-screen", "none", "-nocite"])
    try:
        lmp.command("units si")
        qqr2e = float(lmp.extract_global("qqr2e"))
        lmp.command(f"dielectric {qqr2e / (MU0 / (4.0 * 3.141592653589793))!r}")
        lmp.file(argv[0])
    finally:
        lmp.close()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
