"""Built-in scenes are registry entries: the seed 000 orbit comes from the magnets plugin.

Truth used: the seed's circular orbit (period ``T_orb`` from the printed ``P_orb``, radius 10 mm);
a run by name and the default run must be the same problem, and a scene that a plugin returns as
a TOML scene goes through the same path as a scene file.
"""

from __future__ import annotations

import argparse
import json
import math
import re
import textwrap
from pathlib import Path

import numpy as np
import pytest

from poissonkit import cli
from poissonkit.commands import run
from poissonkit.errors import InputError, SceneError, UnknownNameError
from poissonkit.plugin import Param, default_scene, manager, plugin_reports, scene
from poissonkit.scene.registered import registered_run

ROOT = Path(__file__).resolve().parents[2]


def _args(*argv: str) -> argparse.Namespace:
    parser = argparse.ArgumentParser()
    run.add_arguments(parser)
    return parser.parse_args(list(argv))


def test_default_scene_is_the_seed_orbit_registered_by_the_magnets_plugin():
    entry = default_scene()
    assert entry.name == "seed000" and entry.default
    assert scene("seed000") is entry
    magnets = next(r for r in plugin_reports() if r.name == "magnets")
    assert magnets.contributions["scene"] == ["seed000", "levitron"]


def test_the_core_holds_no_scene_module_and_the_commands_name_no_scene():
    pkg = ROOT / "poissonkit"
    assert not [p.name for p in pkg.glob("*.py") if "seed" in p.name]
    for cmd in ("run.py", "bench.py", "sweep.py"):
        text = (pkg / "commands" / cmd).read_text()
        assert not re.search(r"(from|import) poissonkit_magnets", text), cmd
    # the sweep layer reaches the seed scene only through its registered entry
    for module in sorted((pkg / "sweeps").glob("*.py")):
        text = module.read_text()
        assert not re.search(r"(from|import) poissonkit_magnets", text), module.name


def test_run_without_scene_and_run_by_name_are_the_same_problem():
    from poissonkit_magnets import seed000

    default = run.build_spec(_args())
    named = run.build_spec(_args("seed000"))
    for spec in (default, named):
        assert spec.name == "seed000" and spec.method == "splitting6"
        assert spec.t_end == pytest.approx(2 * math.pi * 20)  # 20 periods, time unit 1/omega
        assert spec.step == pytest.approx(2 * math.pi / 200)  # T_orb/200
    assert np.array_equal(default.y0, named.y0)
    # the printed P_orb of the seed (Maple, 20 digits) travels in the run's metadata
    assert default.metadata["P_orb"] == pytest.approx(6.4910356642626862477e-4, rel=1e-14)
    T = float(seed000.circular_orbit().period)
    short = run.build_spec(_args("--duration", str(T / 2), "--step", str(T / 100)))
    assert short.t_end == pytest.approx(math.pi) and short.step == pytest.approx(2 * math.pi / 100)
    assert short.metadata["periods"] == pytest.approx(0.5)
    # an adaptive method chosen on the command line gets no fixed step of the default method
    adaptive = run.build_spec(_args("--method", "dop853", "--tilt", "0.02"))
    assert adaptive.method == "dop853" and adaptive.step is None
    assert adaptive.metadata["tilt"] == 0.02


def test_cli_runs_the_registered_scene_by_name(tmp_path):
    out = tmp_path / "o"
    code = cli.main(["run", "seed000", "--out", str(out), "--no-progress", "--no-plots",
                     "--periods", "1"])
    assert code == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["scene"] == "seed000" and s["steps"] == 200
    assert s["min_distance_m"] == pytest.approx(0.01, rel=1e-7)  # stays on the circle


def test_blocked_magnets_plugin_makes_the_default_run_a_clear_error(monkeypatch, capsys):
    monkeypatch.setenv(manager.ENV_BLOCK, "magnets")
    manager.reset()
    with pytest.raises(SceneError, match="default scene"):
        default_scene()
    assert cli.main(["run", "--no-progress"]) == 1
    assert "default scene" in capsys.readouterr().err


def test_unknown_scene_name_lists_the_registered_ones():
    with pytest.raises(UnknownNameError, match="seed000"):
        registered_run("no_such_scene")
    with pytest.raises(InputError, match="periods"):
        registered_run("seed000", {"periods": -2.0})


_TOML_SCENE_PLUGIN = '''
from pathlib import Path
from poissonkit.plugin import SceneEntry, hookimpl
from poissonkit.scene import load_scene

TOML = Path({toml!r})

@hookimpl
def poissonkit_scenes():
    return [SceneEntry("pk_test_two_magnets", "Two magnets from a TOML file.",
                       load=lambda: load_scene(TOML), default=True)]
'''


def test_a_plugin_scene_given_as_toml_runs_like_the_scene_file(tmp_path, monkeypatch):
    toml = ROOT / "poissonkit" / "scene" / "shipped" / "two_magnets.toml"
    (tmp_path / "pk_test_scenes.py").write_text(
        textwrap.dedent(_TOML_SCENE_PLUGIN.format(toml=str(toml))))
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setattr(manager, "BUILTIN_PLUGINS",
                        manager.BUILTIN_PLUGINS + (("test-scenes", "pk_test_scenes"),))
    manager.reset()
    assert default_scene().name == "seed000"  # a later plugin cannot take the default
    by_name = run.build_spec(_args("pk_test_two_magnets", "--method", "splitting2"))
    from_file = run.build_spec(_args(str(toml), "--method", "splitting2"))
    assert by_name.method == from_file.method == "splitting2"  # not consumed: applied after
    assert by_name.t_end == from_file.t_end and by_name.step == from_file.step
    assert np.array_equal(by_name.y0, from_file.y0)


def test_optional_param_may_be_left_out_but_required_one_may_not():
    from poissonkit.plugin import SceneEntry

    e = SceneEntry("x", "doc", params=(Param("a", optional=True), Param("b")))
    assert e.resolve_params({"b": 1}) == {"b": 1.0}
    with pytest.raises(InputError, match="'b'"):
        e.resolve_params({"a": 1})
