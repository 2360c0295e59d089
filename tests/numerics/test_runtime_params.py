"""Parameters as data: a potential's float parameters are run-time values of its kernels.

Systems that differ only in parameter values share every compiled kernel (counted with numba's
compile events), and their numbers equal those of kernels with the parameters compiled in:
bit for bit for a plugin's ready-made kernel (the same machine operations on the same values),
to round-off for an expression (sympy folds constants differently).
"""

from __future__ import annotations

import dataclasses
import math

import numba
import numpy as np
import pytest
import sympy as sp

from poissonkit.numerics.nbody import AllPairs, Body, Interaction, NBodySystem
from poissonkit.numerics.potentials import runtime_potential
from poissonkit.plugin import PairPotential, Param, entries
from poissonkit.sweeps.compiles import compilations, count_compilations

R = sp.Symbol("r", real=True)


def _yukawa(p):
    return -p["k"] * sp.exp(-R / p["lam"]) / R


#: a third-party expression potential (as a plugin would register it)
YUKAWA = PairPotential(
    name="test_yukawa_rt", doc="U = -k exp(-r/lam)/r.",
    params=(Param("k", doc="strength [J m]", default=1.0, positive=True),
            Param("lam", doc="range [m]", default=1.0, positive=True)),
    expr=_yukawa, orientation="none")


@numba.njit(cache=False)
def _spring_kernel(r, c1, c2, c3, P):
    """U = k (r - r0)^2 / 2 with k = P[0], r0 = P[1]."""
    d = r - P[1]
    return 0.5 * P[0] * d * d, P[0] * d, 0.0, 0.0, 0.0


#: a third-party potential with a ready-made kernel reading a parameter array
SPRING = PairPotential(
    name="test_spring_rt", doc="U = k (r - r0)^2 / 2.",
    params=(Param("k", doc="stiffness [N/m]", default=1.0), Param("r0", doc="rest length [m]",
                                                                  default=1.0)),
    param_kernel=lambda p: _spring_kernel, param_values=lambda p: (p["k"], p["r0"]),
    orientation="none")


def _points(entry, params, n=4, fast=True):
    bodies = [Body(f"b{k}", 1.0 + 0.25 * k) for k in range(n)]
    return NBodySystem(bodies, [AllPairs(entry, params)], fast_path=fast)


def _state(sys, n=4):
    rng = np.random.default_rng(3)
    return sys.pack(rng.normal(size=(n, 3)) * 2.0, rng.normal(size=(n, 3)))


def _compiles_of(build):
    count_compilations()
    before = compilations()
    out = build()
    return out, compilations() - before


@pytest.mark.parametrize("fast", [True, False])
def test_expression_potential_sweep_compiles_once(fast):
    first = _points(YUKAWA, {"k": 1.0, "lam": 0.5}, fast=fast)
    first.forces(_state(first))  # compiles (or loads) everything once
    for lam in (0.7, 1.1, 2.3):
        sys = _points(YUKAWA, {"k": 1.5, "lam": lam}, fast=fast)

        def run(sys=sys):
            return sys.forces(_state(sys))

        (F, _, U), n = _compiles_of(run)
        assert n == 0, f"lam={lam}: {n} numba compilations"
        # independent truth: the pair forces of U = -k exp(-r/lam)/r by hand
        y = _state(sys)
        pos = sys.unpack(y)["r"]
        F_ref = np.zeros_like(pos)
        U_ref = 0.0
        for i in range(4):
            for j in range(i + 1, 4):
                d = pos[j] - pos[i]
                r = math.sqrt(d @ d)
                U_ref += -1.5 * math.exp(-r / lam) / r
                dU = 1.5 * math.exp(-r / lam) * (1 / (r * r) + 1 / (lam * r))
                F_ref[j] -= dU * d / r
                F_ref[i] += dU * d / r
        np.testing.assert_allclose(F, F_ref, rtol=1e-13, atol=1e-15)
        assert U == pytest.approx(U_ref, rel=1e-13)


def test_expression_runtime_equals_constants_to_round_off():
    const = dataclasses.replace(YUKAWA, constant_params=("k", "lam"))
    for lam in (0.6,):  # each constant value compiles the force loops again: one is enough
        a = _points(YUKAWA, {"k": 2.0, "lam": lam})
        b = _points(const, {"k": 2.0, "lam": lam})
        y = _state(a)
        Fa, _, Ua = a.forces(y)
        Fb, _, Ub = b.forces(y)
        np.testing.assert_allclose(Fa, Fb, rtol=4e-16 * 8, atol=0)
        assert Ua == pytest.approx(Ub, rel=4e-16 * 8)
    assert runtime_potential(YUKAWA, {"lam": 0.6}).kernel is \
        runtime_potential(YUKAWA, {"lam": 1.3}).kernel
    assert runtime_potential(const, {"lam": 0.6}).values == ()


def test_ready_made_kernel_with_parameter_array():
    first = _points(SPRING, {"k": 1.0, "r0": 1.0})
    first.forces(_state(first))
    for k, r0 in ((2.0, 0.5), (3.5, 1.5)):
        sys = _points(SPRING, {"k": k, "r0": r0})
        (F, _, U), n = _compiles_of(lambda sys=sys: sys.forces(_state(sys)))
        assert n == 0
        pos = sys.unpack(_state(sys))["r"]
        U_ref = sum(0.5 * k * (np.linalg.norm(pos[j] - pos[i]) - r0) ** 2
                    for i in range(4) for j in range(i + 1, 4))
        assert U == pytest.approx(U_ref, rel=1e-14)


def _magnets():
    pots = entries("potential")
    if "dipole" not in pots or pots["dipole"].param_kernel is None:
        pytest.skip("the magnets plugin is not installed")
    return pots["dipole"]


def _two_dipoles(entry, m1):
    bodies = [Body("a", 1e-3, alpha=1e7), Body("b", 1e-3, alpha=1e7)]
    return NBodySystem(bodies, [Interaction(0, 1, entry, {"moment1": m1, "moment2": 0.1})])


def _dipole_state(sys):
    nu = np.array([[0.0, 0.6, 0.8], [0.28, 0.0, 0.96]])
    return sys.pack([[0, 0, 0], [0.05, 0.01, -0.02]], [[0, 0, 0], [0, 0, 0]], nu,
                    [[0, 0, 0], [0, 0, 0]])


def test_plugin_kernel_sweep_compiles_once_and_is_bit_identical():
    dipole = _magnets()
    constant = dataclasses.replace(dipole, param_kernel=None, param_values=None)
    first = _two_dipoles(dipole, 0.1)
    first.forces(_dipole_state(first))
    for m1 in (0.13, 0.29):
        sys = _two_dipoles(dipole, m1)
        (F, T, U), n = _compiles_of(lambda sys=sys: sys.forces(_dipole_state(sys)))
        assert n == 0
    ref = _two_dipoles(constant, m1)  # parameters compiled in, as before
    Fc, Tc, Uc = ref.forces(_dipole_state(ref))
    assert np.array_equal(F, Fc) and np.array_equal(T, Tc) and U == Uc
    # independent truth: U = mu0 m1 m2 (c3 - 3 c1 c2) / (4 pi r^3)
    nu = _dipole_state(sys)[12:].reshape(2, 2, 3)[:, 0]
    d = np.array([0.05, 0.01, -0.02])
    r = np.linalg.norm(d)
    e = d / r
    U_ref = 4e-7 * math.pi * 0.29 * 0.1 * (nu[0] @ nu[1] - 3 * (e @ nu[0]) * (e @ nu[1])) / (
        4 * math.pi * r ** 3)
    assert U == pytest.approx(U_ref, rel=1e-9)


def test_equal_values_share_a_kernel_and_other_values_get_their_own():
    bodies = [Body(f"b{k}", 1.0) for k in range(3)]
    same = NBodySystem(bodies, [Interaction(0, 1, YUKAWA, {"lam": 0.5}),
                                Interaction(1, 2, YUKAWA, {"lam": 0.5})], fast_path=False)
    other = NBodySystem(bodies, [Interaction(0, 1, YUKAWA, {"lam": 0.5}),
                                 Interaction(1, 2, YUKAWA, {"lam": 0.8})], fast_path=False)
    assert len(same._kerns) == 1 and len(other._kerns) == 2
    table = other.data.table
    assert table.shape[0] == len(bodies) + 1  # the bodies, then the parameter row
    assert table[-1].tolist() == [1.0, 0.5, 1.0, 0.8]  # (k, lam) of each kernel
    assert same.data.table[-1].tolist() == [1.0, 0.5]


def test_expression_that_needs_numbers_falls_back_to_constants():
    needs_numbers = PairPotential(
        name="test_sqrt_rt", doc="U = sqrt(k) / r (written with math.sqrt).",
        params=(Param("k", doc="strength", default=4.0, positive=True),),
        expr=lambda p: math.sqrt(p["k"]) / R, orientation="none")
    rk = runtime_potential(needs_numbers, {"k": 9.0})
    assert rk.values == ()
    assert rk.kernel(2.0, 0.0, 0.0, 0.0)[0] == pytest.approx(1.5)


_SECOND_PROCESS = """
import math, sys
import sympy as sp
from poissonkit.numerics.nbody import AllPairs, Body, NBodySystem
from poissonkit.plugin import PairPotential, Param
from poissonkit.sweeps.compiles import compilations, count_compilations
R = sp.Symbol("r", real=True)
Y = PairPotential(name="yk2", doc="U = -k exp(-r/lam)/r.",
                  params=(Param("k", default=1.0, positive=True),
                          Param("lam", default=1.0, positive=True)),
                  expr=lambda p: -p["k"] * sp.exp(-R / p["lam"]) / R, orientation="none")
count_compilations()
s = NBodySystem([Body("a", 1.0), Body("b", 1.0)], [AllPairs(Y, {"lam": float(sys.argv[1])})],
                parallel=False)
F, T, U = s.forces(s.pack([[0, 0, 0], [2.0, 0, 0]], [[0, 0, 0], [0, 0, 0]]))
print(compilations(), repr(U))
"""


@pytest.mark.slow
def test_second_process_compiles_nothing_for_other_values(tmp_path):
    import os
    import subprocess
    import sys

    env = {**os.environ, "POISSONKIT_CACHE_DIR": str(tmp_path / "cache")}

    def run(lam):
        out = subprocess.run([sys.executable, "-c", _SECOND_PROCESS, str(lam)], env=env,
                             capture_output=True, text=True, check=True)
        n, u = out.stdout.split()
        return int(n), float(u)

    n1, u1 = run(0.5)
    n2, u2 = run(0.9)  # a new value in a new process: everything from the disk cache
    assert n1 > 0 and n2 == 0
    assert u1 == pytest.approx(-math.exp(-4.0) / 2.0, rel=1e-15)
    assert u2 == pytest.approx(-math.exp(-2.0 / 0.9) / 2.0, rel=1e-15)


@pytest.mark.slow  # compiles the unit-carrying kernels (~8 s cold)
def test_other_units_compile_nothing():
    from poissonkit.numerics.units import Scales

    def system(length):
        scales = Scales.from_energy(length, 2.0, 1.3 / length)
        return NBodySystem([Body(f"b{k}", 1.0 + k) for k in range(3)],
                           [AllPairs(YUKAWA, {"lam": 0.7})], scales=scales)

    pos = np.array([[0.0, 0.0, 0.0], [1.0, 0.2, 0.0], [0.3, 1.1, -0.4]])
    zero = np.zeros((3, 3))
    a = system(1.0)
    Fa = a.forces(a.pack(pos, zero, si=True))[0] * a.scales.unit("force")
    b = system(2.5)
    (Fb, _, _), n = _compiles_of(lambda: b.forces(b.pack(pos, zero, si=True)))
    assert n == 0  # the units are run-time data as well
    np.testing.assert_allclose(Fb * b.scales.unit("force"), Fa, rtol=1e-14)
