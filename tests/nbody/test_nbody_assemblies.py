"""N-body assemblies from networkx graphs: geometry, pairs, parameters, and conservation laws.

Truth is computed here from first principles (closed-form pair energies, r x p sums of the
initial data), never from the system under test.
"""

from __future__ import annotations

import itertools
import math

import networkx as nx
import numpy as np
import poissonkit_nbody as nb
import pytest

from poissonkit.errors import InputError, UnknownNameError
from poissonkit.plugin import assembly

MAG = {"mass": 7.658e-4, "alpha": 3.872e7, "moment": 0.15546875, "radius": 1.25e-3,
       "length": 0.02}
MU0 = 4e-7 * math.pi
G_N = 6.67430e-11


def positions(G):
    return np.array([G.nodes[n]["r"] for n in G.nodes])


def axes(G):
    return np.array([G.nodes[n]["nu"] for n in G.nodes])


# ----------------------------------------------------------------------------- builders


def test_chain_spacing_axes_and_edges():
    G = nb.chain(5, 0.03, MAG, direction=(0, 0, 2), axes="alternating", interactions="neighbours")
    P = positions(G)
    assert np.allclose(np.diff(P, axis=0), [0, 0, 0.03])
    assert np.allclose(axes(G), [[0, 0, (-1) ** k] for k in range(5)])
    assert sorted(G.edges) == [(0, 1), (1, 2), (2, 3), (3, 4)]
    full = nb.chain(5, 0.03, MAG)
    assert full.number_of_edges() == 10 and np.allclose(axes(full), [0, 0, 0] + np.eye(3)[0])
    assert [full.nodes[k]["name"] for k in full.nodes] == [f"b{k}" for k in range(5)]


def test_ring_is_a_regular_polygon_with_tangent_axes():
    n, R = 7, 0.05
    G = nb.ring(n, R, MAG, interactions="neighbours")
    P = positions(G)
    assert np.allclose(np.linalg.norm(P, axis=1), R)
    side = 2 * R * math.sin(math.pi / n)
    assert all(np.isclose(np.linalg.norm(P[u] - P[v]), side) for u, v in G.edges)
    assert G.number_of_edges() == n
    assert np.allclose(np.einsum("ij,ij->i", axes(G), P), 0)  # tangent: perpendicular to radius
    assert np.allclose(np.cross(P, axes(G))[:, 2], R)         # and counter-clockwise


@pytest.mark.parametrize("shape", [(3, 4), (2, 3, 2)])
def test_lattice_sites_and_nearest_neighbour_edges(shape):
    G = nb.lattice(shape, 0.04, MAG, axes="checkerboard", interactions="neighbours")
    P = positions(G)
    assert len(P) == math.prod(shape)
    d = np.linalg.norm(P[:, None] - P[None], axis=2)
    expected = {(i, j) for i, j in itertools.combinations(range(len(P)), 2)
                if np.isclose(d[i, j], 0.04)}
    assert {tuple(sorted(e)) for e in G.edges} == expected
    # checkerboard: nearest neighbours are antiparallel
    assert all(np.allclose(axes(G)[u], -axes(G)[v]) for u, v in G.edges)
    assert nb.lattice(shape, 0.04, MAG).number_of_edges() == len(P) * (len(P) - 1) // 2


def test_random_cluster_is_seeded_non_overlapping_and_inside_the_ball():
    a = nb.random_cluster(40, 0.12, MAG, seed=3)
    b = nb.random_cluster(40, 0.12, MAG, seed=3)
    c = nb.random_cluster(40, 0.12, MAG, seed=4)
    Pa = positions(a)
    assert np.array_equal(Pa, positions(b)) and np.array_equal(axes(a), axes(b))
    assert not np.allclose(Pa, positions(c))
    assert np.all(np.linalg.norm(Pa, axis=1) <= 0.12)
    d = np.linalg.norm(Pa[:, None] - Pa[None], axis=2) + np.eye(40)
    bounding = math.hypot(1.25e-3, 0.01)
    assert d.min() >= 2 * bounding  # bounding spheres disjoint, so the cylinders never overlap
    assert np.allclose(np.linalg.norm(axes(a), axis=1), 1)
    with pytest.raises(InputError, match="could not place body"):
        nb.random_cluster(50, 0.02, MAG, seed=0, max_tries=50)


def test_builders_reject_bad_input_naming_it():
    with pytest.raises(InputError, match="spacing must be finite and > 0"):
        nb.chain(3, -1.0, MAG)
    with pytest.raises(InputError, match="number of bodies"):
        nb.ring(1, 0.1, MAG)
    with pytest.raises(InputError, match="body 'b0': mass must be positive and finite"):
        nb.chain(2, 0.1, {**MAG, "mass": -1})
    with pytest.raises(InputError, match="lattice shape"):
        nb.lattice((3,), 0.1, MAG)
    with pytest.raises(InputError, match="needs its axis 'nu'"):
        nb.BodyModel.from_attrs({"mass": 1.0, "alpha": 1.0, "r": (0, 0, 0)}, "x")


def test_registered_assemblies_take_typed_params():
    entry = assembly("ring")
    params = entry.resolve_params({"n": 6, "ring_radius": 0.1, "mass": 1.0, "potential": "gravity"})
    G = entry.build(**params)
    assert G.number_of_nodes() == 6 and G.graph["potential"] == "gravity"
    assert "alpha" not in G.nodes[0]  # alpha = 0 means point mass
    with pytest.raises(UnknownNameError, match="available: .*ring_radius"):
        entry.resolve_params({"n": 6, "radius": 0.1, "mass": 1.0})
    lat = assembly("lattice")
    G3 = lat.build(**lat.resolve_params({"nx": 2, "ny": 2, "nz": 2, "spacing": 0.1, "mass": 1.0}))
    assert G3.number_of_nodes() == 8


# ----------------------------------------------------------------------------- pairs


def test_pair_parameters_come_from_node_attributes_and_edges_override():
    G = nx.Graph(potential="dumbbell")
    G.add_node("a", mass=1.0, alpha=1.0, r=(0, 0, 0), nu=(0, 0, 1), moment=0.1, half_length=0.01)
    G.add_node("b", mass=1.0, alpha=1.0, r=(0.1, 0, 0), nu=(0, 0, 1), moment=0.2, length=0.04)
    G.add_node("c", mass=2.0, r=(0, 0.1, 0))
    G.add_edge("a", "b")
    # explicit params given from c's side: "first" says which body is 1
    G.add_edge("c", "a", potential="gravity", params={"mass1": 5.0}, first="c")
    specs = {(p.i, p.j): p for p in nb.pairs_of(G)}
    ab = specs[(0, 1)]
    assert ab.potential == "dumbbell"
    assert (ab.params["moment1"], ab.params["moment2"]) == (0.1, 0.2)
    assert (ab.params["half_length1"], ab.params["half_length2"]) == (0.01, 0.02)
    ac = specs[(0, 2)]  # stored as (a, c): c's explicit mass moves to slot 2
    assert ac.potential == "gravity" and (ac.params["mass1"], ac.params["mass2"]) == (1.0, 5.0)
    H = nx.Graph(potential="nope")
    H.add_node("x", mass=1.0, r=(0, 0, 0))
    H.add_node("y", mass=1.0, r=(1, 0, 0))
    with pytest.raises(UnknownNameError, match="unknown potential 'nope'; available: .*gravity"):
        nb.pairs_of(H)


def test_default_is_the_complete_graph_and_energy_matches_newton():
    rng = np.random.default_rng(0)
    G = nx.Graph()
    for k in range(6):  # equal masses: one compiled kernel (each distinct pair costs a compile)
        G.add_node(k, mass=2.0, r=tuple(rng.uniform(-1, 1, 3)))
    system = nb.from_graph(G, default_potential="gravity")
    y = nb.initial_state(G, system)
    P = positions(G)
    m = [G.nodes[k]["mass"] for k in G.nodes]
    truth = -sum(G_N * m[i] * m[j] / np.linalg.norm(P[i] - P[j])
                 for i, j in itertools.combinations(range(6), 2))
    assert system.energy(y) * system.scales.energy == pytest.approx(truth, rel=1e-12)


@pytest.mark.slow  # compiles its own N-body kernels (registry entries are rebuilt per test)
def test_chain_of_dipoles_energy_matches_the_closed_form():
    G = nb.chain(4, 0.05, MAG, axes="transverse", potential="dipole")
    G.nodes[2]["nu"] = (0.6, 0.0, 0.8)
    system = nb.from_graph(G)
    y = nb.initial_state(G, system)
    P, N = positions(G), axes(G)
    N = N / np.linalg.norm(N, axis=1)[:, None]
    truth = 0.0
    for i, j in itertools.combinations(range(4), 2):
        d = P[j] - P[i]
        r = np.linalg.norm(d)
        e = d / r
        truth += MU0 * MAG["moment"] ** 2 / (4 * math.pi * r ** 3) * (
            N[i] @ N[j] - 3 * (e @ N[i]) * (e @ N[j]))
    assert system.energy(y) * system.scales.energy == pytest.approx(truth, rel=1e-12)


# ----------------------------------------------------------------------------- conservation


def _spin_and_push(G, seed):
    rng = np.random.default_rng(seed)
    for n in G.nodes:
        G.nodes[n]["p"] = tuple(1e-6 * rng.normal(size=3))
        if "alpha" in G.nodes[n]:
            G.nodes[n]["m"] = tuple(1e-9 * rng.normal(size=3))


def _momenta_from_attrs(G):
    """Total linear and angular momentum of the initial data, from the node attributes."""
    P = sum(np.array(G.nodes[n]["p"]) for n in G.nodes)
    L = sum(np.cross(G.nodes[n]["r"], G.nodes[n]["p"]) + np.array(G.nodes[n].get("m", (0, 0, 0)))
            for n in G.nodes)
    return P, L


def _tilted(G, seed, amount=0.2):
    """Tilt every axis a little (random), so the pairs exert torques."""
    rng = np.random.default_rng(seed)
    for n in G.nodes:
        nu = np.array(G.nodes[n]["nu"]) + amount * rng.normal(size=3)
        G.nodes[n]["nu"] = tuple(nu / np.linalg.norm(nu))
    return G


# mostly side-by-side parallel magnets repel: the bodies move and turn but never collide
@pytest.mark.parametrize("build", [
    pytest.param(lambda: _tilted(nb.ring(5, 0.04, MAG, axes="normal", potential="dumbbell"), 5),
                 marks=pytest.mark.slow),
    lambda: _tilted(nb.lattice((2, 3), 0.04, MAG, potential="dipole"), 6),
], ids=["ring-dumbbell", "lattice-dipole"])
def test_assemblies_conserve_total_linear_and_angular_momentum(build):
    from poissonkit.numerics.solver import solve

    G = build()
    _spin_and_push(G, 1)
    system = nb.from_graph(G)
    y0 = nb.initial_state(G, system)
    s = system.scales
    P_true, L_true = _momenta_from_attrs(G)
    # the packed state carries exactly the initial data's momenta
    assert np.allclose(system.linear_momentum(y0) * s.unit("momentum"), P_true, rtol=1e-12,
                       atol=1e-20)
    assert np.allclose(system.angular_momentum(y0) * s.unit("angular_momentum"), L_true,
                       rtol=1e-12, atol=1e-22)
    sol = solve(system, y0, 0.5, method="splitting4", step=0.01)
    y = np.asarray(sol.y)
    assert y.shape[0] > 40
    P = system.linear_momentum(y)
    L = system.angular_momentum(y)
    # round-off scale: the sizes of the terms that are summed (sum |p_i|, sum |r_i||p_i| + |m_i|)
    st = system.unpack(y)
    p_size = np.max(np.sum(np.linalg.norm(st["p"], axis=-1), axis=-1))
    l_size = np.max(np.sum(np.linalg.norm(st["r"], axis=-1) * np.linalg.norm(st["p"], axis=-1)
                           + np.linalg.norm(st["m"], axis=-1), axis=-1))
    assert np.max(np.abs(P - P[0])) <= 1e-13 * p_size * len(G)
    assert np.max(np.linalg.norm(L - L[0], axis=1)) <= 1e-13 * l_size * len(G)
    # the bodies really moved and turned (the test is not vacuous)
    start, end = system.unpack(y[0]), system.unpack(y[-1])
    assert np.max(np.linalg.norm(end["r"] - start["r"], axis=1)) > 1e-3
    assert np.max(np.linalg.norm(end["nu"] - start["nu"], axis=1)) > 1e-2
    E = system.energy(y)
    assert np.max(np.abs(E - E[0])) < 1e-4 * np.max(np.abs(E))


@pytest.mark.slow  # compiles its own N-body kernels
def test_fixed_body_contributes_a_field_not_degrees_of_freedom():
    G = nb.chain(3, 0.04, MAG, potential="dipole")
    G.nodes[0]["fixed"] = True
    system = nb.from_graph(G)
    assert system.n_moving == 2 and system.n_tops == 2
    y = nb.initial_state(G, system)
    F, T, _ = system.forces(y)
    free = nb.chain(3, 0.04, MAG, potential="dipole")
    free_system = nb.from_graph(free)
    F_free, T_free, _ = free_system.forces(nb.initial_state(free, free_system))
    # the moving bodies feel exactly what they feel when body 0 is free: its field is there
    assert np.linalg.norm(F_free[2]) > 0
    assert np.allclose(F[1:], F_free[1:], rtol=1e-13, atol=0)
    assert np.allclose(T[1:], T_free[1:], rtol=1e-13, atol=1e-30)
