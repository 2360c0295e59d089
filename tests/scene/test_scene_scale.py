"""Large scenes: every pair alike is built as one cell-listed all-pairs interaction in O(N).

Truth: the dipole-dipole energy and forces summed over every pair within the cutoff directly in
numpy (O(N²)), and the system built from the full pair list (the path every scene took before),
compared to the last bit. The O(N) set-up is checked by structure (no pair list is ever made)
and by traced memory at N and 4N, not by timing.
"""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

from poissonkit.numerics.nbody import AllPairs
from poissonkit.scene import build_scene, loads_scene
from poissonkit.scene.limits import held_pairs

MU0 = 1.2566370614359173e-06
MOMENT = 0.15546875
SPACING = 0.03


def _lattice_text(nx: int, ny: int, nz: int, cutoff: float | None = 0.05,
                  axes: str = "checkerboard", interactions: str = "complete") -> str:
    cut = f"cutoff = {cutoff}" if cutoff is not None else ""
    return f"""
name = "lattice"
[assembly]
name = "lattice"
params = {{ nx = {nx}, ny = {ny}, nz = {nz}, spacing = {SPACING}, mass = 7.658e-4, \
alpha = 3.872e7, moment = {MOMENT}, axes = "{axes}", interactions = "{interactions}" }}
[interactions]
potential = "dipole"
{cut}
[run]
method = "splitting4"
step = 1e-4
duration = 1e-3
"""


def _bodies_text(pos: np.ndarray, axes: np.ndarray, cutoff: float = 0.05) -> str:
    lines = ['name = "dipoles"', "[defaults]", "mass = 7.658e-4", "alpha = 3.872e7",
             f"moment = {MOMENT}", "[interactions]", 'potential = "dipole"',
             f"cutoff = {cutoff}", "[run]", "step = 1e-4", "duration = 1e-3"]
    for r, a in zip(pos, axes):
        lines += ["[[bodies]]", "r = [{!r}, {!r}, {!r}]".format(*map(float, r)),
                  "nu = [{!r}, {!r}, {!r}]".format(*map(float, a))]
    return "\n".join(lines)


def _direct_dipoles(pos: np.ndarray, axes: np.ndarray, cutoff: float
                    ) -> tuple[float, np.ndarray]:
    """Energy [J] and forces [N] of point dipoles ``MOMENT * axes`` over every pair closer
    than ``cutoff``, summed directly (O(N²))."""
    m = MOMENT * axes
    d = pos[None, :, :] - pos[:, None, :]  # d[i, j] = r_j - r_i
    r = np.linalg.norm(d, axis=2)
    n = len(pos)
    inside = (r < cutoff) & ~np.eye(n, dtype=bool)
    r_safe = np.where(inside, r, 1.0)
    e = d / r_safe[:, :, None]
    mi_e = np.einsum("ijk,ik->ij", e, m)
    mj_e = np.einsum("ijk,jk->ij", e, m)
    mi_mj = m @ m.T
    c = MU0 / (4 * np.pi)
    u = np.where(inside, c / r_safe ** 3 * (mi_mj - 3 * mi_e * mj_e), 0.0)
    # force on j from i: 3c/r^4 [(mi.e) mj + (mj.e) mi + (mi.mj) e - 5 (mi.e)(mj.e) e]
    f_on_j = (3 * c / r_safe ** 4)[:, :, None] * (
        mi_e[:, :, None] * m[None, :, :] + mj_e[:, :, None] * m[:, None, :]
        + (mi_mj - 5 * mi_e * mj_e)[:, :, None] * e)
    f_on_j = np.where(inside[:, :, None], f_on_j, 0.0)
    return float(u.sum() / 2), f_on_j.sum(axis=0)


@pytest.fixture
def no_pair_lists(monkeypatch):
    """Fail if a scene build lists its pairs or joins every pair of a graph."""
    import poissonkit.scene.assembly as assembly

    def refuse(*_args, **_kwargs):
        raise AssertionError("the all-pairs scene listed its pairs")

    monkeypatch.setattr(assembly, "pairs_of", refuse)
    monkeypatch.setattr(assembly, "edges_of", refuse)
    monkeypatch.setattr(assembly, "complete", refuse)


def _positions(built) -> tuple[np.ndarray, np.ndarray]:
    u = built.system.unpack(built.y0, si=True)
    return u["r"], u["nu"]


def _check_against_direct(built, cutoff: float) -> None:
    system = built.system
    (inter,) = system.interactions
    assert isinstance(inter, AllPairs) and system.cutoff == cutoff
    F, _T, U = system.forces(built.y0)
    s = system.scales
    pos, axes = _positions(built)
    u_ref, f_ref = _direct_dipoles(pos, axes, cutoff)
    assert U * s.energy == pytest.approx(u_ref, rel=1e-10)
    np.testing.assert_allclose(F * s.unit("force"), f_ref, rtol=1e-9,
                               atol=1e-10 * np.abs(f_ref).max())


def test_assembly_lattice_with_a_cutoff_is_one_cell_listed_all_pairs(no_pair_lists):
    built = build_scene(loads_scene(_lattice_text(3, 3, 2)))
    assert len(built.bodies) == 18
    _check_against_direct(built, 0.05)


def test_listed_bodies_with_a_cutoff_are_one_cell_listed_all_pairs(no_pair_lists):
    rng = np.random.default_rng(7)
    pos = np.array([(x, y, z) for x in range(3) for y in range(3) for z in range(2)],
                   float) * SPACING + rng.uniform(-3e-3, 3e-3, (18, 3))
    axes = rng.normal(size=(18, 3))
    axes /= np.linalg.norm(axes, axis=1)[:, None]
    built = build_scene(loads_scene(_bodies_text(pos, axes)))
    _check_against_direct(built, 0.05)


@pytest.mark.parametrize("text", [_lattice_text(3, 3, 2), _lattice_text(4, 3, 2, cutoff=None)])
def test_direct_build_equals_the_pair_list_build(text):
    """The system is the one built from every pair listed (the former path), to the bit."""
    from poissonkit.scene.assembly import bodies_of, pairs_of, state_of, system_of
    from poissonkit.scene.build import scene_graph

    scene = loads_scene(text)
    built = build_scene(scene)
    G = scene_graph(scene)
    assert G.number_of_edges() == len(built.bodies) * (len(built.bodies) - 1) // 2
    bodies = bodies_of(G)
    ref = system_of(bodies, pairs_of(G, bodies), cutoff=scene.cutoff)
    assert built.system.scales == ref.scales
    assert repr(built.system.interactions) == repr(ref.interactions)
    def same(a, b):  # slot by slot to the bit, nested named tuples (the fields) included
        if isinstance(a, tuple):
            assert type(a) is type(b) and len(a) == len(b)
            for u, v in zip(a, b):
                same(u, v)
        elif isinstance(a, np.ndarray):
            assert a.dtype == b.dtype and np.array_equal(a, b)
        else:
            assert a == b

    same(built.system.data, ref.data)
    assert np.array_equal(built.y0, state_of(bodies, ref))


def test_neighbour_assemblies_keep_their_pair_list():
    text = _lattice_text(3, 3, 2, interactions="neighbours")
    built = build_scene(loads_scene(text))
    assert not any(isinstance(i, AllPairs) for i in built.system.interactions)
    assert len(built.system.interactions) == 2 * 3 * 2 + 3 * 2 * 2 + 3 * 3  # structural edges


def test_held_pairs_counts_what_the_build_holds():
    import tomllib

    alike = tomllib.loads(_lattice_text(50, 50, 40))
    assert held_pairs(10**5, alike, assembly={"interactions": "complete",
                                              "potential": "dipole"}) == 0
    assert held_pairs(10**5, alike, assembly={"interactions": "neighbours"}) == 3 * 10**5
    assert held_pairs(10**5, alike, assembly={"interactions": "other"}) == 10**5 * (10**5 - 1) // 2
    # bodies whose moments differ: every pair has its own parameters, all of them are held
    tables = [{"moment": 1.0}, {"moment": 1.0}, {"moment": 2.0}]
    data = {"interactions": {"potential": "dipole"}}
    assert held_pairs(3, data, tables[:2] * 2) == 0
    assert held_pairs(3, data, tables) == 3
    assert held_pairs(3, data, [{"moment": 1.0, "fixed": True}] * 3) == 3


def test_a_hundred_thousand_body_lattice_passes_the_memory_limit():
    """The former cap counted every pair of an assembly (5e9 here) and refused it."""
    import tomllib
    from unittest import mock

    from poissonkit.scene.limits import estimate_bytes
    from poissonkit.scene.schema import scene_from_mapping

    data = tomllib.loads(_lattice_text(50, 50, 40))
    need = estimate_bytes(10**5, 0)
    # validation goes on to build the bodies (O(N)); stop it there: only the limit is tested
    with mock.patch("poissonkit.scene.build.scene_graph", side_effect=StopIteration), \
            mock.patch("poissonkit.scene.limits.available_memory", return_value=4 * need), \
            pytest.raises(StopIteration):
        scene_from_mapping(data)


def _build_peak(nx: int, ny: int, nz: int) -> int:
    scene = loads_scene(_lattice_text(nx, ny, nz))
    tracemalloc.start()
    try:
        build_scene(scene)
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def test_set_up_memory_grows_linearly():
    """Traced peak of building N = 1024 and 4N = 4096 bodies: about 4x (N²: 16x). Both are
    above the 512 bodies up to which the length unit is found from the dense distance matrix."""
    build_scene(loads_scene(_lattice_text(3, 3, 3)))  # imports and registries out of the way
    small = _build_peak(16, 8, 8)
    large = _build_peak(16, 16, 16)
    assert large / small < 6.0, (small, large)


@pytest.mark.slow
def test_ten_thousand_body_lattice_stays_within_the_memory_estimate():
    """The limit's own estimate (no pair held) bounds the traced peak of the build."""
    from poissonkit.scene.limits import estimate_bytes

    build_scene(loads_scene(_lattice_text(3, 3, 3)))
    peak = _build_peak(25, 20, 20)
    assert peak < estimate_bytes(10**4, 0), peak
