"""The pair potentials other than ``dipole`` on LAMMPS (docs/lammps.md, "Pair potentials").

LAMMPS is the independent truth: its ``coul/cut`` (gravity: charges ``q = m``, prefactor
``−G``), ``lj/cut``, ``lj/cut/coul/cut`` and ``lj/cut/dipole/cut`` (Lennard-Jones beside
magnetic or electric point dipoles) forces and torques against poissonkit's on the same
random state, and its velocity-Verlet runs against a converged poissonkit run. Lennard-Jones
and the electric dipoles are the example plugin's (``examples/external_plugin``): those tests
are skipped, saying so, where it is not installed; the LAMMPS ones where LAMMPS is absent.
The default suite keeps gravity and the refusals; the other mappings and the runs are marked
slow (each compiles poissonkit's kernels of a new potential combination first):
``pytest -m slow tests/engines/``.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from poissonkit.errors import MissingDependencyError
from poissonkit.numerics.nbody import NBodySystem
from poissonkit.numerics.nbody.bodies import AllPairs, Body, Interaction
from poissonkit.numerics.runspec import RunSpec

N = 6
RNG = np.random.default_rng(11)
POS = RNG.normal(size=(N, 3)) * 0.02  # m: a cluster a few centimetres across
VEL = RNG.normal(size=(N, 3))
AXES = RNG.normal(size=(N, 3))
AXES /= np.linalg.norm(AXES, axis=1)[:, None]
SPIN = RNG.normal(size=(N, 3)) * 1e-9
MOMENTS = [0.05 * (1 + 0.1 * k) for k in range(N)]  # A m²: a different moment per body
LJ = {"epsilon": 1e-3, "sigma": 0.015}  # J, m
#: A 2 x 3 lattice of spacing 2 cm, perturbed by 1 mm: no pair deep in a repulsive core
LATTICE = (np.array([[0.02 * (k % 2), 0.02 * (k // 2), 0.0] for k in range(N)])
           + RNG.normal(size=(N, 3)) * 1e-3)


def _lammps_or_skip() -> None:
    from poissonkit.engines.lammps_runtime import load_lammps

    try:
        load_lammps()
    except MissingDependencyError as exc:
        pytest.skip(f"LAMMPS is not installed here ({exc})")


def _example_plugin_or_skip() -> None:
    from poissonkit.plugin.manager import entries

    if "lennard_jones" not in entries("potential"):
        pytest.skip("the example plugin (examples/external_plugin: lennard_jones, point_dipole) "
                    "is not installed: pip install -e examples/external_plugin")


def _points(*terms: AllPairs) -> NBodySystem:
    return NBodySystem([Body(f"b{k}", mass=1.0 + k) for k in range(N)], terms)


def _tops(*terms: AllPairs | Interaction) -> NBodySystem:
    bodies = [Body(f"t{k}", mass=1e-3 * (1 + k), alpha=1e8 / (1 + k),
                   attributes={"charge": 1e-8 * (1 + k), "dipole_length": 1e-3 * (2 - 0.1 * k)})
              for k in range(N)]
    return NBodySystem(bodies, terms)


def _dipole_pairs() -> list[Interaction]:
    """Magnetic dipole pairs listed one by one: each body its own moment."""
    return [Interaction(i, j, "dipole", {"moment1": MOMENTS[i], "moment2": MOMENTS[j]})
            for i in range(N) for j in range(i + 1, N)]


def _assert_same_forces(system: NBodySystem, y: np.ndarray) -> None:
    from poissonkit.engines import lammps_forces

    f, t = lammps_forces(system, y)
    fp, tp, _ = system.forces(y)  # no scales: internal units are SI
    assert np.abs(fp).max() > 0
    assert np.abs(f - fp).max() <= 1e-12 * np.abs(fp).max()
    if np.abs(tp).max() == 0:  # point masses
        assert np.abs(t).max() == 0
    else:
        assert np.abs(t - tp).max() <= 1e-12 * np.abs(tp).max()


def test_gravity_forces_equal_poissonkits_and_newtons():
    _lammps_or_skip()
    from poissonkit.conventions import NEWTON_G
    from poissonkit.engines import lammps_forces

    system = _points(AllPairs("gravity"))
    y = system.pack(POS, VEL)
    _assert_same_forces(system, y)
    f, _ = lammps_forces(system, y)
    d = POS[None, :, :] - POS[:, None, :]  # Newton's law by hand, the sign included
    r = np.linalg.norm(d, axis=2) + np.eye(N)
    m = 1.0 + np.arange(N)
    newton = (NEWTON_G * m[:, None] * m[None, :] / r ** 3)[..., None] * d
    assert np.abs(f - newton.sum(axis=1)).max() <= 1e-12 * np.abs(f).max()


@pytest.mark.slow  # compiles poissonkit's kernels of new potentials: 30-75 s cold
def test_lennard_jones_of_point_masses_alone_and_beside_gravity():
    _lammps_or_skip()
    _example_plugin_or_skip()
    for terms in ([AllPairs("lennard_jones", LJ)],
                  [AllPairs("gravity"), AllPairs("lennard_jones", {"epsilon": 1e-12,
                                                                   "sigma": 0.015})]):
        system = _points(*terms)
        _assert_same_forces(system, system.pack(POS, VEL))


@pytest.mark.slow  # compiles poissonkit's kernels of new potentials: 30-75 s cold
def test_lennard_jones_beside_magnetic_dipoles_of_different_moments():
    _lammps_or_skip()
    _example_plugin_or_skip()
    for terms in (_dipole_pairs(), [*_dipole_pairs(), AllPairs("lennard_jones", LJ)]):
        system = _tops(*terms)
        _assert_same_forces(system, system.pack(POS, VEL * 1e-3, AXES, SPIN))


@pytest.mark.slow  # compiles poissonkit's kernels of new potentials: 30-75 s cold
def test_electric_point_dipoles_alone_and_beside_lennard_jones():
    _lammps_or_skip()
    _example_plugin_or_skip()
    for terms in ([AllPairs("point_dipole")],
                  [AllPairs("point_dipole"), AllPairs("lennard_jones", {"epsilon": 1e-6,
                                                                        "sigma": 0.015})]):
        system = _tops(*terms)
        _assert_same_forces(system, system.pack(POS, VEL * 1e-3, AXES, SPIN))


def _converges(spec: RunSpec) -> None:
    """LAMMPS's run converges at order 2 to a converged poissonkit run (splitting4 at h/8)."""
    from poissonkit.engines import run_lammps
    from poissonkit.numerics import solve

    s, h, t_end = spec.system, float(spec.step or 0), spec.t_end
    ref = solve(s, spec.y0, t_end, method="splitting4", step=h / 8).y[-1]
    ours = solve(s, spec.y0, t_end, method="splitting4", step=h).y[-1]
    a = run_lammps(spec, t_end, h).y[-1]
    b = run_lammps(spec, t_end, h / 2).y[-1]
    moved = np.abs(ref - spec.y0).max()
    err_a, err_b = np.abs(a - ref).max(), np.abs(b - ref).max()
    # splitting4 at h is 100 times better than LAMMPS at h, so its h/8 run (4096 times better
    # again) is the truth here
    assert np.abs(ours - ref).max() < 1e-2 * err_a
    assert 3.5 < err_a / err_b < 4.5  # velocity Verlet: order 2
    assert err_a <= 1.5 * (4 / 3) * np.abs(a - b).max() and err_a < 1e-3 * moved


@pytest.mark.slow  # compiles poissonkit's kernels of new potentials: 30-75 s cold
def test_a_gravitating_lennard_jones_cluster_runs_as_in_poissonkit():
    _lammps_or_skip()
    _example_plugin_or_skip()
    # masses of kilograms 2 cm apart: gravity (~1e-8 J) and the LJ well (1e-8 J) both count;
    # released at rest, the cluster oscillates with periods of about two minutes
    system = _points(AllPairs("gravity"), AllPairs("lennard_jones", {"epsilon": 1e-8,
                                                                    "sigma": 0.018}))
    y0 = system.pack(LATTICE, np.zeros((N, 3)))
    _converges(RunSpec("cluster", system, y0, t_end=100.0, method="splitting4", step=1.0))


@pytest.mark.slow  # compiles poissonkit's kernels of new potentials: 30-75 s cold
def test_dipoles_with_lennard_jones_run_as_in_poissonkit():
    _lammps_or_skip()
    _example_plugin_or_skip()
    system = _tops(*_dipole_pairs(), AllPairs("lennard_jones", {"epsilon": 1e-4,
                                                                "sigma": 0.015}))
    y0 = system.pack(LATTICE, np.zeros((N, 3)), AXES, np.zeros((N, 3)))
    _converges(RunSpec("lj_dipoles", system, y0, t_end=5e-3, method="splitting4", step=5e-5))


class _Built:
    """The one attribute :func:`can_express` reads of a built scene."""

    def __init__(self, system: NBodySystem) -> None:
        self.system = system


def test_a_potential_without_a_lammps_style_is_refused_with_the_reason():
    _example_plugin_or_skip()
    from poissonkit.engines import can_express

    ok, why = can_express(_Built(_tops(AllPairs("finite_dipole"))))
    assert not ok and "'finite_dipole' has no LAMMPS pair style" in why and "charges" in why
    ok, why = can_express(_Built(_tops(*_dipole_pairs(), AllPairs("point_dipole"))))
    assert not ok and "magnetic and electric point dipoles" in why


def test_pairs_joined_twice_or_not_at_all_by_a_potential_are_refused():
    from poissonkit.engines import can_express

    ok, why = can_express(_Built(_points(AllPairs("gravity"), AllPairs("gravity"))))
    assert not ok and "interact twice through 'gravity'" in why
    ok, why = can_express(_Built(_tops(*_dipole_pairs(), _dipole_pairs()[0])))
    assert not ok and "interact twice through 'dipole'" in why
    ok, why = can_express(_Built(_tops(*_dipole_pairs()[1:])))
    assert not ok and "do not interact through 'dipole'" in why


def test_gravity_beside_dipoles_and_tops_without_dipoles_are_refused():
    from poissonkit.engines import can_express

    ok, why = can_express(_Built(_tops(*_dipole_pairs(), AllPairs("gravity"))))
    assert not ok and "charge-dipole" in why
    ok, why = can_express(_Built(_tops(AllPairs("gravity"))))
    assert not ok and "without a dipole potential" in why


def test_a_potential_registered_under_a_mapped_name_with_another_energy_is_refused():
    from poissonkit.engines import can_express
    from poissonkit.plugin.contributions import PairPotential, Param

    r = sp.Symbol("r", real=True)
    softened = PairPotential(  # "gravity" softened by 1 cm: not LAMMPS's coul/cut
        name="gravity", doc="softened gravity",
        params=(Param("mass1", "float", "kg", positive=True),
                Param("mass2", "float", "kg", positive=True),
                Param("G", "float", "m^3/(kg s^2)", default=6.6743e-11, positive=True)),
        expr=lambda p: -p["G"] * p["mass1"] * p["mass2"] / sp.sqrt(r ** 2 + 1e-4),
        orientation="none", body_params=(("mass1", "mass", 1), ("mass2", "mass", 2)))
    ok, why = can_express(_Built(_points(AllPairs(softened))))
    assert not ok and "another energy than LAMMPS's coul/cut" in why


@pytest.mark.slow
def test_a_gravitating_cluster_on_two_ranks_equals_one_rank_to_round_off():
    _lammps_or_skip()
    from poissonkit.engines import run_lammps

    system = _points(AllPairs("gravity"))
    spec = RunSpec("cluster", system, system.pack(LATTICE, np.zeros((N, 3))), t_end=100.0,
                   method="splitting4", step=1.0)
    one = run_lammps(spec, spec.t_end, 1.0, ranks=1)
    two = run_lammps(spec, spec.t_end, 1.0, ranks=2)
    assert two.extra["ranks"] == 2 and two.method == "lammps nve"
    assert np.abs(one.y - two.y).max() <= 1e-12 * np.abs(one.y).max()
