"""The LAMMPS data file and input script of a run (``units si``), and the dump reader.

The data file carries every number LAMMPS needs per atom, written with ``repr`` so that it
reads back bit for bit: position, diameter and density (LAMMPS's sphere inertia is
``0.4 m r²``: the diameter is chosen so that it equals the top's ``1/α``), the dipole moment
[A m² or C m] or charge (a gravity scene's masses), velocity and angular velocity. The
pair prefactor (``μ0/4π``, ``k`` or ``−G``) is set by the worker
(:mod:`poissonkit.engines.lammps_worker`) through ``dielectric``, as LAMMPS's dipole and
Coulomb styles use the Coulomb constant of its unit system.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from poissonkit.engines.lammps_express import LammpsBodies

#: Columns of every dump of dipolar spheres (and of :func:`read_dump`'s arrays), after ``id``.
DUMP_COLUMNS = ("x", "y", "z", "vx", "vy", "vz", "mux", "muy", "muz", "omegax", "omegay",
                "omegaz", "fx", "fy", "fz", "tqx", "tqy", "tqz", "mass", "radius")
#: The columns of a dump of point masses.
POINT_COLUMNS = ("x", "y", "z", "vx", "vy", "vz", "fx", "fy", "fz", "mass")


def dump_columns(bodies: LammpsBodies) -> tuple[str, ...]:
    """The dump columns of a run of ``bodies``."""
    return DUMP_COLUMNS if bodies.dipolar else POINT_COLUMNS


def _f(x: float) -> str:
    return repr(float(x))


def write_data(path: Path, bodies: LammpsBodies, r: np.ndarray, v: np.ndarray,
               mu: np.ndarray | None, omega: np.ndarray | None) -> float:
    """Write the LAMMPS data file of the state (SI arrays ``(n, 3)``); return the pair
    cutoff [m]: the scene's, or far beyond the bodies' extent (the full pair sum)."""
    n = len(bodies.mass)
    lo, hi = r.min(axis=0), r.max(axis=0)
    extent = float(np.max(hi - lo))
    scale = extent if extent > 0 else 1.0
    lo, hi = lo - scale, hi + scale  # the box is shrink-wrapped as the bodies move
    cutoff = bodies.cutoff if bodies.cutoff is not None else 1e3 * scale
    # point masses: spheres of any size moved by fix nve (which never reads the diameter)
    radius = np.sqrt(2.5 * bodies.inertia / bodies.mass) if bodies.inertia is not None \
        else np.full(n, 0.5 * scale)
    density = bodies.mass / (4.0 / 3.0 * math.pi * radius ** 3)
    charge = bodies.charge if bodies.charge is not None else np.zeros(n)
    style = "hybrid sphere dipole" if bodies.dipolar else "hybrid sphere charge"
    lines = ["poissonkit scene (units si)", "", f"{n} atoms", "1 atom types", ""]
    lines += [f"{_f(lo[d])} {_f(hi[d])} {a}lo {a}hi" for d, a in enumerate("xyz")]
    lines += ["", f"Atoms # {style}", ""]
    # sphere dipole: id type x y z diameter density q mux muy muz; sphere charge: ... q
    lines += [f"{k + 1} 1 {_f(r[k, 0])} {_f(r[k, 1])} {_f(r[k, 2])} {_f(2 * radius[k])} "
              f"{_f(density[k])} {_f(charge[k])}"
              + ("" if mu is None else f" {_f(mu[k, 0])} {_f(mu[k, 1])} {_f(mu[k, 2])}")
              for k in range(n)]
    lines += ["", "Velocities", ""]
    w = omega if omega is not None else np.zeros((n, 3))
    lines += [f"{k + 1} " + " ".join(_f(x) for x in (*v[k], *w[k])) for k in range(n)]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return cutoff


def field_fixes(bodies: LammpsBodies) -> list[str]:
    """``fix gravity`` (force ``M g``) and ``fix efield`` (torque ``μ × B`` on each dipole:
    ``units si`` has ``qe2f = 1`` and the atoms carry no charge) of the uniform fields."""
    out = []
    if bodies.gravity is not None:
        g = math.sqrt(sum(x * x for x in bodies.gravity))
        if g > 0:
            out.append(f"fix grav all gravity {_f(g)} vector "
                       + " ".join(_f(x / g) for x in bodies.gravity))
    if bodies.field is not None:
        out.append("fix field all efield " + " ".join(_f(x) for x in bodies.field))
    return out


def pair_commands(bodies: LammpsBodies, cutoff: float) -> list[str]:
    """``pair_style`` and ``pair_coeff`` of the scene's potentials (docs/lammps.md): the
    dipole–dipole term of ``lj/cut/dipole/cut`` (with ``epsilon = 0`` unless Lennard-Jones is
    there too), or ``coul/cut`` (gravity: charges ``q = m``), ``lj/cut`` or both in
    ``lj/cut/coul/cut`` for point masses."""
    eps, sigma = bodies.lj if bodies.lj is not None else (0.0, 1.0)
    lj = f"pair_coeff * * {_f(eps)} {_f(sigma)}"
    if bodies.dipolar:
        return [f"pair_style lj/cut/dipole/cut {_f(cutoff)}", lj]
    if bodies.charge is None:
        return [f"pair_style lj/cut {_f(cutoff)}", lj]
    if bodies.lj is None:
        return [f"pair_style coul/cut {_f(cutoff)}", "pair_coeff * *"]
    return [f"pair_style lj/cut/coul/cut {_f(cutoff)}", lj]


def write_input(path: Path, data: Path, dump: Path, bodies: LammpsBodies, *, step: float,
                steps: int, every: int, cutoff: float) -> None:
    """The input script: read the data, the pair style (:func:`pair_commands`), NVE of spheres
    rotating their dipoles (``update dipole/dlm``: the symplectic rotation of Dullweber,
    Leimkuhler and McLachlan) or of point masses (``fix nve``), the uniform fields, a dump every
    ``every`` steps and at the end. Without a scene cutoff the cutoff lies beyond every pair
    (neighbour lists of all pairs: the full pair sum)."""
    cols = " ".join(dump_columns(bodies))
    fmt = "sort id format float %.17g"
    style = "hybrid sphere dipole" if bodies.dipolar else "hybrid sphere charge"
    nve = "nve/sphere update dipole/dlm" if bodies.dipolar else "nve"
    cmds = [f"atom_style {style}", "atom_modify map array", "boundary s s s",
            f"read_data {data}", *pair_commands(bodies, cutoff),
            # the full pair sum: one cell would hold everything, so all pairs (nsq)
            f"neighbor {_f(0.05 * cutoff)} {'nsq' if bodies.cutoff is None else 'bin'}",
            "neigh_modify every 1 delay 0 check yes",
            f"fix nve all {nve}", *field_fixes(bodies),
            f"timestep {_f(step)}",
            "thermo_style custom step pe", f"thermo {max(steps, 1)}",
            f"dump traj all custom {every} {dump} id {cols}",
            f"dump_modify traj {fmt}",
            f"run {steps}"]
    if steps % every:
        cmds += ["undump traj", f"write_dump all custom {dump}.last id {cols} modify {fmt}"]
    path.write_text("\n".join(cmds) + "\n", encoding="utf-8")


def read_dump(path: Path, columns: tuple[str, ...] = DUMP_COLUMNS
              ) -> tuple[np.ndarray, np.ndarray]:
    """``(timesteps (k,), atoms (k, n, len(columns)))`` of a text dump sorted by id."""
    steps: list[int] = []
    frames: list[np.ndarray] = []
    lines = path.read_text(encoding="utf-8").splitlines()
    i = 0
    while i < len(lines):
        if lines[i].startswith("ITEM: TIMESTEP"):
            steps.append(int(lines[i + 1]))
            n = int(lines[i + 3])
            head = lines[i + 8].split()[2:]
            rows = np.array([ln.split() for ln in lines[i + 9:i + 9 + n]], dtype=float)
            order = [head.index(c) for c in columns]
            frames.append(rows[np.argsort(rows[:, head.index("id")])][:, order])
            i += 9 + n
        else:
            i += 1
    return np.array(steps, dtype=np.int64), np.array(frames)
