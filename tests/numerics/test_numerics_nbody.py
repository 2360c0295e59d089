"""Compiled N-body right-hand side against x-dot = P grad H of the symbolic core."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from numerics_helpers import BOUND, C1, C2, C3, R, unit  # type: ignore[import-not-found]

from poissonkit.errors import InputError, UnknownNameError
from poissonkit.numerics import AllPairs, Body, Interaction, NBodySystem

#: depends on the first body's axis only (orientation "first"), for top-point pairs
FIRST_ONLY = C1 / R**2 + 1 / (2 * R)
CENTRAL = -1 / R
#: dipole pair with a short-range repulsion (shares compiled kernels with the other test files)
DIPOLE = BOUND


def _symbolic_field(system, pair_terms):
    """P grad H with P = system.to_structure() and H built here from the expressions."""
    P = system.to_structure()
    x = P.coords
    moving = [k for k, b in enumerate(system.bodies) if not b.fixed]
    tops = [k for k in moving if system.bodies[k].is_top]
    pos, axis = {}, {}
    H = 0
    for s, k in enumerate(moving):
        b = system.bodies[k]
        pos[k] = sp.Matrix(x[6 * s:6 * s + 3])
        p = sp.Matrix(x[6 * s + 3:6 * s + 6])
        H += p.dot(p) / (2 * sp.nsimplify(b.mass))
    base = 6 * len(moving)
    for t, k in enumerate(tops):
        axis[k] = sp.Matrix(x[base + 6 * t:base + 6 * t + 3])
        m = sp.Matrix(x[base + 6 * t + 3:base + 6 * t + 6])
        H += sp.nsimplify(system.bodies[k].alpha) * m.dot(m) / 2
    for k, b in enumerate(system.bodies):
        if b.fixed:
            pos[k] = sp.Matrix([sp.nsimplify(v) for v in b.position])
            if b.is_top:
                axis[k] = sp.Matrix([sp.nsimplify(v) for v in unit(b.axis)])
    for i, j, U in pair_terms:
        d = pos[j] - pos[i]
        rn = sp.sqrt(d.dot(d))
        e = d / rn
        zero = sp.zeros(3, 1)
        ni, nj = axis.get(i, zero), axis.get(j, zero)
        H += U.subs({R: rn, C1: e.dot(ni), C2: e.dot(nj), C3: ni.dot(nj)}, simultaneous=True)
    # P grad H from the core's matrix and gradient (hamiltonian_vector_field also expands,
    # which is slow for these radicals and changes nothing numerically)
    return sp.lambdify([x], P.matrix * P.gradient(H), "numpy")


def _random_state(system, rng, spread=3.0):
    n = len(system.bodies)
    pos = rng.normal(size=(n, 3)) * spread
    nu = np.array([unit(v) for v in rng.normal(size=(n, 3))])
    return system.pack(pos, rng.normal(size=(n, 3)), nu, rng.normal(size=(n, 3)))


def test_two_tops_rhs_equals_poisson_field():
    system = NBodySystem([Body("a", 1.5, 2.0), Body("b", 0.7, 3.0)],
                         [Interaction("a", "b", DIPOLE)])
    f = _symbolic_field(system, [(0, 1, DIPOLE)])
    rng = np.random.default_rng(1)
    for _ in range(3):
        y = _random_state(system, rng)
        ref = np.asarray(f(y), dtype=float).ravel()
        assert np.allclose(system.rhs(0, y), ref, rtol=1e-12, atol=1e-13)


def test_three_bodies_with_point_mass_equal_poisson_field():
    # two tops (dipole pair) and a point mass seen by top "a" through a c1-only potential
    bodies = [Body("a", 1.0, 2.0), Body("b", 2.0, 0.5), Body("c", 3.0)]
    inter = [Interaction(0, 1, DIPOLE), Interaction(0, 2, FIRST_ONLY), Interaction(1, 2, CENTRAL)]
    system = NBodySystem(bodies, inter)
    assert system.dim == 3 * 6 + 2 * 6
    f = _symbolic_field(system, [(0, 1, DIPOLE), (0, 2, FIRST_ONLY), (1, 2, CENTRAL)])
    rng = np.random.default_rng(2)
    for _ in range(3):
        y = _random_state(system, rng)
        ref = np.asarray(f(y), dtype=float).ravel()
        assert np.allclose(system.rhs(0, y), ref, rtol=1e-12, atol=1e-13)


def test_fixed_body_acts_without_degrees_of_freedom():
    bodies = [Body("a", 1.0, 2.0), Body("b", 2.0, 0.5),
              Body("f", 1.0, 1.0, fixed=True, position=(0.5, -1.0, 2.0), axis=(0, 1, 1))]
    system = NBodySystem(bodies, [AllPairs(DIPOLE)])
    assert system.dim == 2 * 6 + 2 * 6
    f = _symbolic_field(system, [(0, 1, DIPOLE), (0, 2, DIPOLE), (1, 2, DIPOLE)])
    rng = np.random.default_rng(4)
    y = _random_state(system, rng)
    assert np.allclose(system.rhs(0, y), np.asarray(f(y), dtype=float).ravel(),
                       rtol=1e-12, atol=1e-13)


def test_all_pairs_equals_explicit_pair_list_and_conserves_momenta():
    n = 6
    bodies = [Body(f"b{k}", 1.0 + 0.1 * k, 1.0 + 0.2 * k) for k in range(n)]
    explicit = [Interaction(i, j, DIPOLE) for i in range(n) for j in range(i + 1, n)]
    s1 = NBodySystem(bodies, [AllPairs(DIPOLE)])
    s2 = NBodySystem(bodies, explicit)
    y = _random_state(s1, np.random.default_rng(5))
    f1, f2 = s1.rhs(0, y), s2.rhs(0, y)
    assert np.allclose(f1, f2, rtol=1e-13, atol=1e-14)
    # Newton's third law and the torque balance: total momentum and j are constant
    rp = f1[:6 * n].reshape(n, 2, 3)
    assert np.max(np.abs(rp[:, 1].sum(axis=0))) < 1e-12
    st = s1.unpack(y)
    dst = s1.unpack(f1)
    jdot = (np.cross(dst["r"], st["p"]) + np.cross(st["r"], dst["p"])).sum(0) + dst["m"].sum(0)
    assert np.max(np.abs(jdot)) < 1e-12


def test_cell_list_with_cutoff_equals_direct_sum_of_close_pairs():
    rng = np.random.default_rng(6)
    n, box, cutoff = 300, 8.0, 1.5
    pos = rng.uniform(0, box, size=(n, 3))
    bodies = [Body(f"b{k}", 1.0, 1.0) for k in range(n)]
    close = [(i, j) for i in range(n) for j in range(i + 1, n)
             if np.linalg.norm(pos[j] - pos[i]) < cutoff]
    assert len(close) > n  # the test exercises many neighbour cells
    cell = NBodySystem(bodies, [AllPairs(DIPOLE)], cutoff=cutoff)
    direct = NBodySystem(bodies, [Interaction(i, j, DIPOLE) for i, j in close])
    nu = np.array([unit(v) for v in rng.normal(size=(n, 3))])
    y = cell.pack(pos, rng.normal(size=(n, 3)), nu, rng.normal(size=(n, 3)))
    assert np.allclose(cell.rhs(0, y), direct.rhs(0, y), rtol=1e-12, atol=1e-12)
    assert cell.energy(y) == pytest.approx(direct.energy(y), rel=1e-12)


def test_layout_pack_unpack_and_errors():
    system = NBodySystem([Body("a", 1.0, 2.0), Body("c", 3.0)], [Interaction("a", "c", FIRST_ONLY)])
    assert system.layout[:3] == ("a.r_x", "a.r_y", "a.r_z")
    assert system.layout[12:15] == ("a.nu_x", "a.nu_y", "a.nu_z")
    assert system.to_structure().dim == system.dim
    y = system.pack([[0, 0, 0], [1, 0, 0]], [[1, 2, 3], [4, 5, 6]], [[0, 0, 1]], [[0, 1, 0]])
    parts = system.unpack(y)
    assert np.array_equal(parts["p"][1], [4, 5, 6]) and np.array_equal(parts["nu"][0], [0, 0, 1])
    with pytest.raises(InputError):  # a dipole needs both axes, "c" is a point mass
        NBodySystem([Body("a", 1.0, 2.0), Body("c", 3.0)], [Interaction(0, 1, DIPOLE)])
    with pytest.raises(UnknownNameError):
        NBodySystem([Body("a", 1.0, 2.0)], [Interaction("a", "zz", DIPOLE)])
    with pytest.raises(InputError):
        Body("x", -1.0)
