"""Integrator options from a scene's ``[run.options]``, ``poissonkit run --option NAME=VALUE`` and
``solve(options=...)``: checked against the registry entry, refused with the valid ones.

The end-to-end check runs a Sun-Jupiter-Saturn scene (point masses, SI) with Wisdom-Holman and
the Blanes et al. ``10_6_4`` table, given in the scene and on the command line, and compares it
with REBOUND's IAS15 on the same initial state: the table must reach the integrator (it is far
more accurate than the classical map at the same step), and both routes give the same numbers.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from poissonkit.errors import InputError, SceneError, UnknownNameError
from poissonkit.scene import loads_scene

BODIES = """
name = "sun_jupiter_saturn"
description = "Sun, Jupiter and Saturn as point masses (SI)"

[[bodies]]
name = "sun"
mass = 1.98847e30
r = [0.0, 0.0, 0.0]
p = [0.0, 0.0, 0.0]

[[bodies]]
name = "jupiter"
mass = 1.89813e27
r = [7.7857e11, 0.0, 0.0]
p = [0.0, 2.4811e31, 0.0]

[[bodies]]
name = "saturn"
mass = 5.6832e26
r = [0.0, 1.43353e12, 0.0]
p = [-5.5012e30, 0.0, 1.0e29]

[interactions]
potential = "gravity"
pairs = "all"
"""
#: 100 years in steps of 100 days
RUN = """
[run]
method = "wisdom_holman"
step = 8.64e6
duration = 3.15576e9
"""


def _scene(options: str = "", method: str = "wisdom_holman") -> str:
    return BODIES + RUN.replace("wisdom_holman", method) + options


def test_scene_options_are_read_and_checked():
    scene = loads_scene(_scene('[run.options]\ntable = "10_6_4"\ncorrectors = 0\n'))
    assert dict(scene.run.options) == {"table": "10_6_4", "correctors": 0}
    assert dict(loads_scene(_scene()).run.options) == {}


@pytest.mark.parametrize("options, message", [
    ('[run.options]\ntabel = "10_6_4"\n', r"(?s)run\.options: .*unknown option 'tabel'.*table \("),
    ('[run.options]\ntable = "10_6_5"\n', r"(?s)run\.options: .*'10_6_4'"),
    ('[run.options]\nstages = "two"\n', r"run\.options: .*'stages' must be int"),
    # TOML reads an unquoted 10_6_4 as the integer 1064
    ("[run.options]\ntable = 10_6_4\n", r"run\.options\.table: .*quote it"),
    ('[run]\noptions = "table=10_6_4"\n', r"run\.options: must be a table"),
])
def test_a_wrong_scene_option_is_refused_with_the_valid_ones(options, message):
    text = _scene(options) if options.startswith("[run.options]") else \
        BODIES + RUN + options.replace("[run]\n", "")
    with pytest.raises(SceneError, match=message) as err:
        loads_scene(text)
    if "unknown" in message:  # the list names every declared option with its type
        for name in ("stages (int", "table (str", "correctors (int"):
            assert name in str(err.value)


def test_solve_refuses_an_unknown_option_as_input_error():
    """An unknown option is an InputError (bad input) and still an UnknownNameError (as
    before); the message lists the valid options."""
    from poissonkit.numerics import solve

    with pytest.raises(InputError, match="valid options") as err:
        solve(object(), np.zeros(3), 1.0, "midpoint", step=0.1, options={"maxiter": 3})
    assert isinstance(err.value, UnknownNameError)
    assert "max_iterations (int; default 50)" in str(err.value)


def test_option_text_takes_the_declared_type():
    from poissonkit.numerics.solve_options import parse_option_items
    from poissonkit.plugin import integrator

    split = integrator("splitting4")
    assert parse_option_items(split, ["adaptive=true", "iterations=3",
                                      "reference_distance=0.5"]) == {
        "adaptive": True, "iterations": 3, "reference_distance": 0.5}
    assert parse_option_items(integrator("wisdom_holman"), ["table=10_6_4"]) == {
        "table": "10_6_4"}
    with pytest.raises(InputError, match="is bool"):
        parse_option_items(split, ["adaptive=maybe"])
    with pytest.raises(InputError, match="NAME=VALUE"):
        parse_option_items(split, ["adaptive"])


def test_the_option_table_lists_every_integrator_option():
    from poissonkit.numerics.solve_options import option_table, options_text
    from poissonkit.plugin import integrators

    rows = option_table()
    assert ("wisdom_holman", "table") in {(n, o.name) for n, o in rows}
    assert len(rows) == sum(len(e.options()) for e in integrators().values())
    text = options_text()
    assert "wisdom_holman:" in text and "'10_6_4'" in text and "--option NAME=VALUE" in text


def _cli(*argv: str) -> int:
    from poissonkit.cli import main

    return main([*argv, "--no-plot", "--no-progress", "--overwrite"])


def _ias15_final(scene_text: str, t_end: float) -> np.ndarray:
    """Jupiter and Saturn relative to the Sun at ``t_end`` [m], by REBOUND's IAS15."""
    rebound = pytest.importorskip("rebound")
    from poissonkit.conventions import NEWTON_G

    scene = loads_scene(scene_text)
    sim = rebound.Simulation()
    sim.G = NEWTON_G
    sim.integrator = "ias15"
    for b in scene.bodies:
        m = float(b["mass"])
        sim.add(m=m, x=b["r"][0], y=b["r"][1], z=b["r"][2],
                vx=b["p"][0] / m, vy=b["p"][1] / m, vz=b["p"][2] / m)
    sim.integrate(t_end, exact_finish_time=1)
    xyz = np.array([p.xyz for p in sim.particles])
    return xyz[1:] - xyz[0]


def _final_relative(out: Path) -> tuple[np.ndarray, float, str]:
    xr = pytest.importorskip("xarray")
    with xr.open_dataset(out / "trajectory.nc") as ds:
        pos = ds["position"].values[-1]
        return pos[1:] - pos[0], float(ds["time"].values[-1]), str(ds.attrs["method"])


def test_run_takes_the_table_from_the_scene_and_the_command_line(tmp_path):
    """``[run.options] table = "10_6_4"`` and ``--option table=10_6_4`` run the same method
    bit for bit; against IAS15 it beats the classical map at the same step (so the option
    reached the integrator); a wrong option is refused with the valid ones."""
    with_options = tmp_path / "sjs.toml"
    with_options.write_text(_scene('[run.options]\ntable = "10_6_4"\n'))
    plain = tmp_path / "plain.toml"
    plain.write_text(_scene())
    assert _cli("run", str(with_options), "--out", str(tmp_path / "scene")) == 0
    assert _cli("run", str(plain), "--option", "table=10_6_4", "--out", str(tmp_path / "cli")) == 0
    assert _cli("run", str(plain), "--out", str(tmp_path / "classic")) == 0
    a = np.load(tmp_path / "scene" / "trajectory.npz")["y"]
    b = np.load(tmp_path / "cli" / "trajectory.npz")["y"]
    assert np.array_equal(a, b)
    table, t_end, method = _final_relative(tmp_path / "scene")
    classic, _, classic_method = _final_relative(tmp_path / "classic")
    assert method == "wisdom_holman_10_6_4" and classic_method == "wisdom_holman"
    truth = _ias15_final(_scene(), t_end)
    err_table = np.max(np.abs(table - truth)) / 7.7857e11
    err_classic = np.max(np.abs(classic - truth)) / 7.7857e11
    assert err_table < 1e-6, err_table
    assert err_table < 0.1 * err_classic, (err_table, err_classic)


def test_run_refuses_a_wrong_option_with_the_valid_ones(tmp_path, capsys):
    plain = tmp_path / "plain.toml"
    plain.write_text(_scene())
    out = str(tmp_path / "o")
    assert _cli("run", str(plain), "--option", "tabel=10_6_4", "--out", out) == 1
    err = capsys.readouterr().err
    assert "unknown option 'tabel'" in err and "table (str" in err and "correctors (int" in err
    assert _cli("run", str(plain), "--option", "table=10_6_5", "--out", out) == 1
    assert "'h10_6_4'" in capsys.readouterr().err
    # --method picks another integrator: the scene's options (for wisdom_holman) are dropped,
    # the command line's are checked against the new one
    with_options = tmp_path / "sjs.toml"
    with_options.write_text(_scene('[run.options]\ntable = "10_6_4"\n'))
    assert _cli("run", str(with_options), "--method", "splitting2", "--option", "table=x",
                "--out", out) == 1
    assert "adaptive (bool" in capsys.readouterr().err


def test_run_help_lists_the_options(capsys):
    from poissonkit.cli import main

    with pytest.raises(SystemExit):
        main(["run", "--help"])
    out = capsys.readouterr().out
    assert "--option NAME=VALUE" in out and "wisdom_holman:" in out and "'10_6_4'" in out


def test_the_docs_table_is_the_registry_s():
    """docs/numerics.md lists the options of poissonkit's own integrators as the registry
    declares them (regenerate with ``python -m poissonkit.numerics.solve_options``)."""
    from poissonkit.numerics.hooks import poissonkit_integrators
    from poissonkit.numerics.solve_options import DOCS_MARKERS, options_markdown

    text = (Path(__file__).resolve().parents[2] / "docs" / "numerics.md").read_text("utf-8")
    start, end = (text.index(m) for m in DOCS_MARKERS)
    shown = text[start + len(DOCS_MARKERS[0]):end].strip()
    assert shown == options_markdown(poissonkit_integrators()), \
        "docs/numerics.md: regenerate the table with python -m poissonkit.numerics.solve_options"


def test_a_sweep_of_the_scene_passes_its_options_to_solve(monkeypatch):
    """``poissonkit sweep FILE`` integrates every point with the scene's ``[run.options]``
    (the compile-ahead run of ``prepare`` too): the options reach ``solve``."""
    from poissonkit.numerics import solver
    from poissonkit.sweeps.targets import TomlScene

    seen: list[dict] = []

    class Stop(Exception):
        pass

    def fake_solve(*args, **kwargs):
        seen.append(dict(kwargs.get("options") or {}))
        if len(seen) > 1:
            raise Stop

    monkeypatch.setattr(solver, "solve", fake_solve)
    target = TomlScene(_scene('[run.options]\ntable = "10_6_4"\n'))
    prep = target.prepare()
    with pytest.raises(Stop):
        target.run(prep, {})
    assert seen == [{"table": "10_6_4"}, {"table": "10_6_4"}]
