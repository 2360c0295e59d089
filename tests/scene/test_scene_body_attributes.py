"""Bodies carry what their potentials need: a third-party potential whose charges are a body
attribute (``body_params``), used from a scene file, an assembly and its overrides.

Truth: the screened Coulomb energy and forces summed over every pair directly in numpy.
"""

from __future__ import annotations

import numpy as np
import pytest

from poissonkit.errors import SceneError
from poissonkit.numerics.nbody import AllPairs, Interaction
from poissonkit.scene import build_run, loads_scene
from poissonkit.scene.bodies import BodyModel
from scene_yukawa_plugin import K, LAM

POS = np.array([[0.0, 0.0, 0.0], [0.03, 0.01, 0.0], [-0.02, 0.025, 0.01],
                [0.01, -0.03, 0.02], [0.04, 0.04, -0.01]])
CHARGE = np.array([2e-8, -1e-8, 3e-8, -2.5e-8, 1e-8])
MASS = np.array([1e-3, 2e-3, 1.5e-3, 1e-3, 3e-3])


def _scene_text(charges=CHARGE, potential="test_yukawa", extra="") -> str:
    lines = ['name = "charged"', "[interactions]", f'potential = "{potential}"', "[run]",
             "duration = 0.01", "step = 0.001"]
    for k, (r, q, m) in enumerate(zip(POS, charges, MASS)):
        lines += ["[[bodies]]", f'name = "q{k}"', f"mass = {float(m)!r}",
                  f"r = [{float(r[0])!r}, {float(r[1])!r}, {float(r[2])!r}]",
                  f"charge = {float(q)!r}", extra]
    return "\n".join(lines)


def _direct(pos: np.ndarray, q: np.ndarray) -> tuple[float, np.ndarray]:
    """Energy [J] and forces [N] of every pair, summed directly (O(N^2))."""
    d = pos[None, :, :] - pos[:, None, :]  # d[i, j] = r_j - r_i
    r = np.linalg.norm(d, axis=2)
    iu = np.triu_indices(len(pos), 1)
    qq = q[:, None] * q[None, :]
    with np.errstate(divide="ignore", invalid="ignore"):
        u = K * qq * np.exp(-r / LAM) / r
        du = -u * (1 / r + 1 / LAM)  # dU/dr
        f_on_i = (du / r)[:, :, None] * d  # -dU/dr_i = dU/dr * (r_j - r_i)/r
    np.fill_diagonal(u, 0.0)
    f_on_i[np.arange(len(pos)), np.arange(len(pos))] = 0.0
    return float(u[iu].sum()), f_on_i.sum(axis=1)


def test_an_undeclared_attribute_is_named_with_the_declared_ones(monkeypatch):
    # built-ins only: an installed third-party plugin may declare a "charge"
    monkeypatch.setenv("POISSONKIT_DISABLE_PLUGIN_AUTOLOAD", "1")
    with pytest.raises(SceneError, match=r"bodies\[0\]\.charge: unknown key; .*body_params"):
        loads_scene(_scene_text(potential="gravity"))


def test_declared_attribute_reaches_the_all_pairs_cell_path(yukawa_plugin):
    run = build_run(loads_scene(_scene_text()))
    system = run.system
    assert len(system.interactions) == 1 and isinstance(system.interactions[0], AllPairs)
    assert not any(isinstance(i, Interaction) for i in system.interactions)
    F, _T, U = system.forces(run.y0)
    s = system.scales
    u_ref, f_ref = _direct(POS, CHARGE)
    assert U * s.energy == pytest.approx(u_ref, rel=1e-12)
    np.testing.assert_allclose(F * s.unit("force"), f_ref, rtol=1e-10,
                               atol=1e-12 * np.abs(f_ref).max())
    assert float(system.energy(run.y0)) * s.energy == pytest.approx(u_ref, rel=1e-12)


def test_energy_unit_comes_from_the_interaction_present(yukawa_plugin):
    run = build_run(loads_scene(_scene_text()))
    s = run.system.scales
    d = np.linalg.norm(POS[:, None] - POS[None], axis=2)
    length = d[np.triu_indices(len(POS), 1)].min()
    assert s.length == length
    qmax = np.abs(CHARGE).max()  # the strongest charge on both ends, at the length unit
    assert s.energy == pytest.approx(K * qmax * qmax * np.exp(-length / LAM) / length, rel=1e-12)


def test_vector_attributes_and_assembly_overrides_are_kept(yukawa_plugin):
    body = BodyModel.from_attrs({"mass": 1.0, "r": (0, 0, 0), "charge": 2.0})
    assert body.attr("charge") == 2.0 and body.extra == {"charge": 2.0}
    text = """
name = "charged chain"
[assembly]
name = "chain"
params = { n = 4, spacing = 0.02, mass = 0.001 }
overrides = { charge = 1e-8 }
[interactions]
potential = "test_yukawa"
[run]
duration = 0.01
step = 0.001
"""
    run = build_run(loads_scene(text))
    F, _T, U = run.system.forces(run.y0)
    pos = np.array([[0.02 * k, 0.0, 0.0] for k in range(4)])
    u_ref, f_ref = _direct(pos, np.full(4, 1e-8))
    assert U * run.system.scales.energy == pytest.approx(u_ref, rel=1e-12)


def test_attribute_with_a_wrong_type_is_named(yukawa_plugin):
    with pytest.raises(SceneError, match=r"bodies\[0\]\.charge"):
        loads_scene(_scene_text().replace("charge = 2e-08", 'charge = "big"', 1))


def test_bench_runs_on_a_plugin_potential_scene(yukawa_plugin, tmp_path, capsys):
    from poissonkit import cli

    path = tmp_path / "charged.toml"
    path.write_text(_scene_text(), encoding="utf-8")
    code = cli.main(["bench", str(path), "--quick", "--methods", "splitting4",
                     "--out", str(tmp_path / "bench"), "--budget", "5"])
    assert code == 0
    rows = (tmp_path / "bench" / "workprecision.csv").read_text().splitlines()
    assert len(rows) > 1 and "splitting4" in rows[1]


@pytest.mark.parametrize("potential", ["test_yukawa", "gravity"])
def test_direct_all_pairs_build_equals_the_pair_list_build(yukawa_plugin, potential):
    """A scene whose pairs all read their parameters from the bodies is built without listing
    its pairs; the system is the one built from the full pair list, to the last bit."""
    from poissonkit.scene.assembly import bodies_of, pairs_of, state_of, system_of
    from poissonkit.scene.build import build_scene, scene_graph

    text = _scene_text(potential=potential)
    if potential == "gravity":
        text = text.replace("\ncharge = ", "\n# charge = ")  # gravity declares no charge
    scene = loads_scene(text)
    direct = build_scene(scene)
    G = scene_graph(scene)
    bodies = bodies_of(G)
    listed = system_of(bodies, pairs_of(G, bodies), cutoff=scene.cutoff)
    assert direct.system.scales == listed.scales
    assert [type(i) for i in direct.system.interactions] == [AllPairs]
    assert direct.system.interactions == listed.interactions
    y0 = state_of(bodies, listed)
    np.testing.assert_array_equal(direct.y0, y0)
    assert float(direct.system.energy(y0)) == float(listed.energy(y0))


def test_graph_nodes_carry_declared_attributes(yukawa_plugin):
    import networkx as nx

    from poissonkit.scene.assembly import from_graph, initial_state

    G = nx.Graph(potential="test_yukawa")
    for k, (r, q, m) in enumerate(zip(POS, CHARGE, MASS)):
        G.add_node(f"q{k}", mass=float(m), r=tuple(r), charge=float(q))
    system = from_graph(G)
    assert [type(i) for i in system.interactions] == [AllPairs]
    _F, _T, U = system.forces(initial_state(G, system))
    assert U * system.scales.energy == pytest.approx(_direct(POS, CHARGE)[0], rel=1e-12)
    G.nodes["q0"]["colour"] = 3.0
    with pytest.raises(Exception, match=r"unknown body attribute 'colour'.*charge"):
        from_graph(G)
