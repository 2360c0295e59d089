"""``poissonkit new-plugin NAME`` writes a plugin package that installs and passes its tests as
generated: here its files and, registered in-process, the kit's fast checks of what it
contributes; the slow test installs it into a fresh virtual environment and runs its tests."""

from __future__ import annotations

import ast
import os
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
from test_plugins_host import install_fake

from poissonkit.cli import main as cli_main
from poissonkit.errors import InputError
from poissonkit.plugin import reset
from poissonkit.plugin.hookspecs import PLUGIN_API_VERSION
from poissonkit.testing.scaffold import new_plugin

ROOT = Path(__file__).resolve().parents[2]


def test_the_command_writes_a_complete_package(tmp_path, capsys):
    assert cli_main(["new-plugin", "demo", "--dir", str(tmp_path)]) == 0
    pkg = tmp_path / "poissonkit-demo"
    assert str(pkg) in capsys.readouterr().out
    files = sorted(str(p.relative_to(pkg)) for p in pkg.rglob("*") if p.is_file())
    assert files == ["README.md", "pyproject.toml", "src/poissonkit_demo/__init__.py",
                     "src/poissonkit_demo/hooks.py", "src/poissonkit_demo/scenes/orbit.toml",
                     "tests/test_kit.py", "tests/test_truth.py"]
    for path in pkg.rglob("*"):
        if path.is_file():
            text = path.read_text(encoding="utf-8")
            assert "{{" not in text and "__package__" not in text, path
            if path.suffix == ".py":
                ast.parse(text)
    project = tomllib.loads((pkg / "pyproject.toml").read_text())
    assert project["project"]["entry-points"]["poissonkit"] == {"demo": "poissonkit_demo.hooks"}
    assert f'POISSONKIT_API = "{PLUGIN_API_VERSION}"' in (
        pkg / "src" / "poissonkit_demo" / "hooks.py").read_text()
    tomllib.loads((pkg / "src" / "poissonkit_demo" / "scenes" / "orbit.toml").read_text())


@pytest.mark.parametrize("name", ["Demo", "1demo", "de-mo", "", "x" * 41])
def test_a_malformed_name_is_refused(tmp_path, name):
    with pytest.raises(InputError, match="plugin name"):
        new_plugin(name, tmp_path)


def test_an_existing_folder_is_not_overwritten(tmp_path):
    new_plugin("demo", tmp_path)
    with pytest.raises(InputError, match="exists already"):
        new_plugin("demo", tmp_path)
    assert cli_main(["new-plugin", "demo", "--dir", str(tmp_path)]) != 0


def test_the_generated_plugin_passes_the_fast_checks_of_the_kit(tmp_path, site):
    pkg = new_plugin("demo", tmp_path)
    install_fake(site, "poissonkit-demo", "0.1.0", {"demo": "poissonkit_demo.hooks"}, {})
    shutil.copytree(pkg / "src" / "poissonkit_demo", site / "poissonkit_demo")
    reset()
    try:
        from poissonkit.testing import plugin_checks

        cases = plugin_checks("demo")
        assert {c.kind for c in cases} == {"potential", "scene"}
        for case in cases:
            if not case.slow:
                case()
    finally:
        reset()
        for name in [m for m in sys.modules if m.startswith("poissonkit_demo")]:
            del sys.modules[name]


@pytest.mark.slow
def test_the_generated_plugin_installs_in_a_fresh_venv_and_its_tests_pass(tmp_path):
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(venv)], check=True)
    python = venv / ("Scripts" if os.name == "nt" else "bin") / "python"
    pkg = new_plugin("demo", tmp_path)
    got = subprocess.run([str(python), "-m", "pip", "install", "--quiet", "--no-deps",
                          "--no-build-isolation", str(pkg)], capture_output=True, text=True,
                         cwd=tmp_path, check=False)
    if got.returncode and "wheel" in got.stderr:
        pytest.skip("building needs the `wheel` package here (setuptools < 70.1)")
    assert got.returncode == 0, got.stderr[-3000:]
    shutil.rmtree(pkg / "src")  # the tests must run against the installed package
    env = {k: v for k, v in os.environ.items() if not k.startswith("POISSONKIT_")}
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), str(ROOT / "plugins")])
    env["POISSONKIT_CACHE_DIR"] = str(tmp_path / "cache")
    listed = subprocess.run([str(python), "-m", "poissonkit", "plugins"], capture_output=True,
                            text=True, env=env, cwd=tmp_path, check=True).stdout
    assert f"demo 0.1.0 (poissonkit-demo) [plugin API {PLUGIN_API_VERSION}]" in listed
    run = subprocess.run([str(python), "-m", "pytest", "-p", "no:cacheprovider", "-q",
                          "-m", "slow or not slow", "-W", "ignore::UserWarning"],
                         capture_output=True, text=True, env=env, cwd=pkg, check=False)
    assert run.returncode == 0, run.stdout[-4000:] + run.stderr[-2000:]
    assert " passed" in run.stdout and "failed" not in run.stdout
