"""Model families from any plugin: a third-party family planned like the built-in magnets.

The toy plugin is installed for real (a ``*.dist-info`` with an entry point in group
``poissonkit`` on ``sys.path``). Its two fidelities of an orientation-dependent potential,

    exact:  U = k (c3 − 3 c1 c2) / r³ · (1 + (a1² + a2²) / r²)
    point:  U = k (c3 − 3 c1 c2) / r³,

are checked against these closed forms, computed here by hand.
"""

from __future__ import annotations

import math
import textwrap
from pathlib import Path

import numpy as np
import pytest
from scene_texts import magnet_scene  # type: ignore[import-not-found]

from poissonkit.errors import UnknownNameError
from poissonkit.pairs import NoModelFamilyError, pair_interaction
from poissonkit.plugin import model_families, reset
from poissonkit.scene.assembly import EdgeSpec
from poissonkit.scene.bodies import BodyModel
from poissonkit.scene.planner import Planner, PlannerError, estimated_error, run_planned

TOY = '''
import sympy as sp
from poissonkit.plugin import ModelFamily, PairPotential, Param, hookimpl

r, c1, c2, c3 = (sp.Symbol(n, real=True) for n in ("r", "c1", "c2", "c3"))
K = Param("k", "float", "strength [J m^3]", default=1e-9)


def _radii(i):
    return Param(f"radius{i}", "float", f"radius of body {i} [m]", positive=True)


def applies(b1, b2):
    return all(b.get("radius", 0) > 0 and not b.get("moment") for b in (b1, b2))


def estimate(model, dist, b1, b2):
    if model == "toy_exact":
        return 0.0
    return 2.0 * (b1["radius"] ** 2 + b2["radius"] ** 2) / dist ** 2


@hookimpl
def poissonkit_potentials():
    return [
        PairPotential("toy_point", "Toy dipole-like pair, far-field form.", params=(K,),
                      expr=lambda p: p["k"] * (c3 - 3 * c1 * c2) / r ** 3),
        PairPotential("toy_exact", "Toy dipole-like pair with its size correction.",
                      params=(K, _radii(1), _radii(2)),
                      expr=lambda p: p["k"] * (c3 - 3 * c1 * c2) / r ** 3
                      * (1 + (p["radius1"] ** 2 + p["radius2"] ** 2) / r ** 2)),
    ]


@hookimpl
def poissonkit_model_families():
    return [ModelFamily("toy", "Toy pair at two fidelities.", models=("toy_point", "toy_exact"),
                        estimate=estimate, applies=applies, reads=("radius",))]
'''

A = 0.01
Z, X = np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])


def toy_energy(model, rvec, n1, n2, k=1e-9, a1=A, a2=A):
    r = float(np.linalg.norm(rvec))
    e = rvec / r
    base = k * (n1 @ n2 - 3 * (e @ n1) * (e @ n2)) / r ** 3
    return base * (1 + (a1 * a1 + a2 * a2) / r ** 2) if model == "toy_exact" else base


@pytest.fixture
def toy_plugin(tmp_path, monkeypatch):
    site = tmp_path / "site"
    info = site / "pk_toy-1.0.dist-info"
    info.mkdir(parents=True)
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: pk-toy\nVersion: 1.0\n")
    (info / "entry_points.txt").write_text("[poissonkit]\npk_toy = pk_toy_mod\n")
    (site / "pk_toy_mod.py").write_text(textwrap.dedent(TOY))
    monkeypatch.syspath_prepend(str(site))
    monkeypatch.delenv("POISSONKIT_DISABLE_PLUGIN_AUTOLOAD", raising=False)
    monkeypatch.delenv("POISSONKIT_BLOCK_PLUGINS", raising=False)
    reset()
    yield Path(site)
    monkeypatch.undo()
    reset()


@pytest.fixture
def no_magnets(monkeypatch):
    """The core without the magnets plugin (and without installed third-party plugins)."""
    monkeypatch.setenv("POISSONKIT_BLOCK_PLUGINS", "magnets")
    monkeypatch.setenv("POISSONKIT_DISABLE_PLUGIN_AUTOLOAD", "1")
    reset()
    yield
    monkeypatch.undo()
    reset()


def test_the_toy_family_is_registered_after_the_magnets(toy_plugin):
    # other installed plugins may add families; the built-in one comes before the toy's
    assert [f.name for f in model_families() if f.name in ("magnets", "toy")] == \
        ["magnets", "toy"]


def test_auto_picks_the_toy_fidelity_within_tol_and_matches_the_closed_forms(toy_plugin):
    rng = np.random.default_rng(5)
    n1, n2 = (v / np.linalg.norm(v) for v in rng.normal(size=(2, 3)))
    for dist, want in ((1.0, "toy_point"), (0.1, "toy_exact")):
        rvec = dist * np.array([0.6, 0.0, 0.8])
        out = pair_interaction("auto", rvec, n1, n2, radius=A, tol=1e-3)
        assert out.model == want
        assert out.energy == pytest.approx(toy_energy(want, rvec, n1, n2), rel=1e-12)
        exact = pair_interaction("toy_exact", rvec, n1, n2, radius=A)
        err = np.linalg.norm(out.force - exact.force) / np.linalg.norm(exact.force)
        assert err <= 1e-3 and out.estimated_error <= 1e-3
    # the point model far off is what the estimate says, and not better than it by much
    rvec = 0.3 * Z
    far = pair_interaction("toy_point", rvec, Z, Z, radius=A)
    exact = pair_interaction("toy_exact", rvec, Z, Z, radius=A)
    err = np.linalg.norm(far.force - exact.force) / np.linalg.norm(exact.force)
    assert 0.3 * far.estimated_error < err <= far.estimated_error


def test_the_planner_plans_toy_pairs_with_the_toy_family(toy_plugin):
    def body(name, r, nu):
        return BodyModel.from_attrs({"name": name, "mass": 1.0, "alpha": 10.0, "radius": A,
                                     "r": r, "nu": nu})

    bodies = [body("a", (0, 0, 0), Z), body("b", (0.05, 0, 0), X), body("c", (2.0, 0, 0), Z)]
    edges = [EdgeSpec(0, 1, None, {}), EdgeSpec(0, 2, None, {}), EdgeSpec(1, 2, None, {})]
    planner = Planner(tol=1e-3, models=("toy_point", "toy_exact"), replan_every=2)
    _, pairs, plan = planner.prepare(bodies, edges)
    assert {(p.i, p.j): p.model for p in plan.pairs} == {
        (0, 1): "toy_exact", (0, 2): "toy_point", (1, 2): "toy_point"}
    assert {p.potential for p in pairs} == {"toy_point", "toy_exact"}
    assert plan.pairs[0].estimated_error == 0.0
    assert estimated_error("toy_point", 2.0, {"radius": A}, {"radius": A}) == \
        pytest.approx(2 * 2 * A * A / 4.0)
    run = run_planned(bodies, edges, planner, duration=4e-3, step=1e-3, method="splitting2")
    assert run.steps == 4 and run.plans[-1].counts()["toy_exact"] == 1


def test_planner_models_must_belong_to_a_registered_family(toy_plugin):
    with pytest.raises(UnknownNameError, match="toy_point"):
        Planner(tol=1e-3, models=("gravity",))


@pytest.mark.usefixtures("no_magnets")
def test_without_the_magnets_plugin_the_core_still_plans_and_evaluates():
    assert model_families() == []
    out = pair_interaction("gravity", (0, 0, 2.0), Z, Z, mass1=3.0, mass2=5.0)
    assert out.energy == pytest.approx(-6.6743e-11 * 15.0 / 2.0, rel=1e-4)
    with pytest.raises(NoModelFamilyError, match="no model family"):
        pair_interaction("auto", (0, 0, 2.0), Z, Z, mass=1.0, tol=1e-3)
    planner = Planner(tol=1e-2)
    assert planner.models == ()
    bodies = [BodyModel.from_attrs({"name": n, "mass": 1.0, "r": (x, 0, 0)})
              for n, x in (("a", 0.0), ("b", 1.0))]
    _, pairs, plan = planner.prepare(bodies, [EdgeSpec(0, 1, "gravity", {})])
    assert [p.potential for p in pairs] == ["gravity"] and plan.unplanned == 1
    with pytest.raises(PlannerError):
        planner.choose(1.0, {}, {})
    assert math.isfinite(float(pairs[0].params["mass1"]))


SCENE = magnet_scene(
    "default_potential_and_planner",
    ("a", "[0.0, 0.0, 0.0]", "[0.0, 0.0, 1.0]"),
    ("b", "[0.05, 0.0, 0.0]", "[0.0, 0.0, 1.0]"),
    ("brass", "[0.0, 0.08, 0.0]", "[1.0, 0.0, 0.0]", "moment = 0.0\nmass = 0.05")) + """[interactions]
pairs = "all"
potential = "gravity"
[planner]
tol = 1e-2
[run]
duration = 1e-3
step = 1e-4
"""


def test_a_default_potential_does_not_keep_the_planner_from_planning_magnet_pairs():
    """docs/scenes.md: every pair of two magnets is planned; the default potential serves the
    other pairs (it used to replace the magnets' models, and a plugin potential that cannot
    describe magnets failed naming the magnet pair)."""
    from poissonkit.scene import build_run, loads_scene

    plan = build_run(loads_scene(SCENE)).metadata["plan"]
    # side by side at 5 cm, 2 cm long magnets: too close for the cheap models at 1 %
    assert [(p["bodies"], p["model"]) for p in plan["pairs"]] == [(["a", "b"], "cylinder")]
    assert plan["unplanned_pairs"] == 2  # brass-a, brass-b: gravity
