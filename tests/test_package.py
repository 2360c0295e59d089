"""The package as a user first meets it: import, version, CLI dispatch, error hierarchy."""

from __future__ import annotations

import inspect
import subprocess
import sys

import pytest

import poissonkit
from poissonkit import errors
from poissonkit.cli import COMMANDS, main


def test_version_comes_from_installed_metadata():
    from importlib.metadata import version

    assert poissonkit.__version__ == version("poissonkit")


def test_every_public_error_derives_from_poissonkit_error():
    classes = [c for _, c in inspect.getmembers(errors, inspect.isclass)
               if c.__module__ == errors.__name__]
    assert len(classes) > 5
    for cls in classes:
        assert issubclass(cls, errors.PoissonkitError), cls


def test_unknown_name_error_lists_available_names():
    exc = errors.UnknownNameError("integrator", "rk99", ["midpoint", "splitting4"])
    assert "rk99" in str(exc) and "midpoint, splitting4" in str(exc)
    assert isinstance(exc, KeyError)


def test_cli_without_command_prints_help_and_fails(capsys):
    assert main([]) == 2
    assert "run" in capsys.readouterr().out


def test_every_cli_command_module_exists():
    import importlib

    for name, (module, _) in COMMANDS.items():
        mod = importlib.import_module(module)
        assert callable(mod.main) and callable(mod.add_arguments), name


def test_python_dash_m_runs_the_cli():
    out = subprocess.run([sys.executable, "-m", "poissonkit", "--version"],
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0
    assert poissonkit.__version__ in out.stdout


def test_public_api_names_resolve():
    for name in poissonkit.__all__:
        assert getattr(poissonkit, name) is not None, name
    with pytest.raises(AttributeError):
        poissonkit.does_not_exist  # noqa: B018
