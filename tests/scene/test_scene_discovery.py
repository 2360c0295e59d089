"""Finding scenes from the command line: ``poissonkit scenes``, runs by name, ``run --help``.

Truth used: the shipped scene files are the ``*.toml`` files of ``poissonkit/scene/shipped/`` with the
``description`` their TOML text states; the only registered scene of the built-in plugins is
``seed000`` (the default); a shipped scene run by name is the same problem as its file run by
path; pyproject's package data must install every shipped file.
"""

from __future__ import annotations

import argparse
import fnmatch
import json
import os
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

from poissonkit import cli
from poissonkit.commands import run
from poissonkit.errors import SceneError, UnknownNameError
from poissonkit.plugin.manager import BUILTIN_PLUGINS
from poissonkit.scene.loader import scene_description, shipped_scene, shipped_scenes
from poissonkit.scene.registered import resolve_scene, scene_catalog

ROOT = Path(__file__).resolve().parents[2]
FOLDER = ROOT / "poissonkit" / "scene" / "shipped"
SHIPPED = sorted(p.stem for p in FOLDER.glob("*.toml"))


def _args(*argv: str) -> argparse.Namespace:
    parser = argparse.ArgumentParser()
    run.add_arguments(parser)
    return parser.parse_args(list(argv))


def test_the_shipped_scenes_are_the_package_folders_toml_files():
    assert SHIPPED == ["circumbinary_planet", "dipolar_spheres", "hierarchical_triple",
                       "magnet_chain", "outer_solar_system", "planned_cluster", "two_magnets"]
    assert list(shipped_scenes()) == SHIPPED
    for name in SHIPPED:
        assert shipped_scene(name).read_bytes() == (FOLDER / f"{name}.toml").read_bytes()
    with pytest.raises(UnknownNameError, match="two_magnets"):
        shipped_scene("three_magnets")
    assert not (ROOT / "examples" / "scenes").exists()


def test_package_data_installs_every_shipped_scene():
    pyproject = tomllib.loads((ROOT / "pyproject.toml").read_text())
    patterns = pyproject["tool"]["setuptools"]["package-data"]["poissonkit"]
    for name in SHIPPED:
        assert any(fnmatch.fnmatch(f"scene/shipped/{name}.toml", p) for p in patterns), patterns


def test_scene_description_is_the_files_description_line(tmp_path):
    for name in SHIPPED:
        text = tomllib.loads((FOLDER / f"{name}.toml").read_text())["description"]
        assert scene_description(FOLDER / f"{name}.toml") == text
    bad = tmp_path / "bad.toml"
    bad.write_text("name = [unclosed")
    assert scene_description(bad) == ""  # listing never fails on a broken file


def test_poissonkit_scenes_lists_registered_and_shipped_with_descriptions(capsys):
    assert cli.main(["scenes"]) == 0
    out = capsys.readouterr().out
    registered, shipped = out.split("shipped scene files:")
    assert "seed000" in registered and "[default; from magnets]" in registered
    for name in SHIPPED:
        line = next(ln for ln in shipped.splitlines() if ln.split()[:1] == [name])
        assert scene_description(FOLDER / f"{name}.toml") in line
    assert cli.main(["scenes", "--json"]) == 0
    listed = json.loads(capsys.readouterr().out)
    # registered scenes first, then the shipped files; an installed third-party plugin may add
    # registered scenes of its own
    kinds = [r["kind"] for r in listed]
    assert kinds == sorted(kinds, key=["registered", "file"].index)
    ours = [r for r in listed if r["kind"] == "file" or r["source"] in dict(BUILTIN_PLUGINS)]
    assert [(r["name"], r["kind"]) for r in ours] == (
        [("levitron", "registered"), ("seed000", "registered")] + [(n, "file") for n in SHIPPED])
    assert [r["name"] for r in listed if r["default"]] == ["seed000"]
    assert listed == [r.__dict__ for r in scene_catalog()]


def test_run_help_names_every_scene(capsys):
    with pytest.raises(SystemExit) as exc:
        cli.main(["run", "--help"])
    assert exc.value.code == 0
    out = capsys.readouterr().out
    epilog = out.split("scenes by name")[1]
    for name in ["seed000", *SHIPPED]:
        assert f"\n  {name} " in epilog, name
    assert "--no-plot, --no-plots" in out


def test_a_shipped_scene_by_name_is_its_file(tmp_path, monkeypatch):
    path = FOLDER / "two_magnets.toml"
    assert resolve_scene("two_magnets") == path
    assert resolve_scene("two_magnets.toml") == path
    assert resolve_scene("seed000") == "seed000"
    # a file in the working directory wins over the shipped one of the same name
    monkeypatch.chdir(tmp_path)
    (tmp_path / "two_magnets.toml").write_text(path.read_text())
    assert resolve_scene("two_magnets.toml") == Path("two_magnets.toml")
    monkeypatch.chdir(ROOT)
    by_name = run.build_spec(_args("two_magnets"))
    by_path = run.build_spec(_args(str(path)))
    assert by_name.method == by_path.method and by_name.t_end == by_path.t_end
    assert np.array_equal(by_name.y0, by_path.y0)


def test_run_two_magnets_by_name_through_the_cli(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)  # found in the package, not relative to the working directory
    out = tmp_path / "out"
    code = cli.main(["run", "two_magnets", "--duration", "0.002", "--out", str(out),
                     "--no-progress", "--no-plot"])
    assert code == 0, capsys.readouterr().err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["scene"] == "two_magnets"
    assert summary["t_reached_s"] == pytest.approx(0.002)
    assert not list(out.glob("*.png"))  # --no-plot is honoured


def test_a_name_that_is_neither_fails_listing_both_kinds(capsys):
    with pytest.raises(SceneError) as exc:
        resolve_scene("two_magnet")
    msg = str(exc.value)
    registered = msg.split("registered scenes: ")[1].split(";")[0].split(", ")
    assert "seed000" in registered  # (with any third-party plugin's scenes)
    assert "shipped scene files: " + ", ".join(SHIPPED) in msg
    assert cli.main(["run", "two_magnet", "--no-progress"]) == 1
    err = capsys.readouterr().err
    assert "seed000" in err and "two_magnets" in err and "Traceback" not in err


def test_the_installed_command_lists_the_scenes_from_any_folder(tmp_path):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [str(ROOT), str(ROOT / "plugins"), os.environ.get("PYTHONPATH", "")]))
    done = subprocess.run([sys.executable, "-m", "poissonkit", "scenes"], cwd=tmp_path,
                          env=env, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    for name in ["seed000", *SHIPPED]:
        assert f"  {name} " in done.stdout
