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
    own = [c for _, c in inspect.getmembers(errors, inspect.isclass)
           if c.__module__ == errors.__name__]
    classes = [c for c in own if issubclass(c, Exception)]
    assert len(classes) > 5
    # the others: the typed state an aborted run carries (IntegrationError.abort), and a second
    # Ctrl-C in a time loop, which stays a KeyboardInterrupt that `except Exception` passes by
    assert {c.__name__ for c in own if c not in classes} == {"AbortState", "InterruptedRun"}
    assert issubclass(errors.InterruptedRun, KeyboardInterrupt)
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


def test_public_surface_has_the_everyday_api_and_stays_lazy():
    everyday = {"Bivector", "HamiltonianSystem", "canonical", "e3", "so3", "direct_sum",
                "check_jacobi", "find_casimirs", "rank", "verify", "pair_interaction",
                "load_scene", "build_run", "solve", "Solution", "integrators", "integrator"}
    assert everyday <= set(poissonkit.__all__)
    assert len(poissonkit.__all__) == len(set(poissonkit.__all__))
    assert set(poissonkit.__all__) <= set(dir(poissonkit))
    # the numerics are imported on first use, not by `import poissonkit`
    code = ("import sys, poissonkit; print('poissonkit.numerics.solver' in sys.modules); "
            "poissonkit.solve; print('poissonkit.numerics.solver' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120)
    assert out.stdout.split() == ["False", "True"], out.stderr


def test_integrator_registry_is_reachable_from_the_top_level():
    reg = poissonkit.integrators()
    assert {"splitting2", "splitting4", "splitting6", "splitting8", "midpoint"} <= set(reg)
    assert poissonkit.integrator("splitting6").order == 6
    assert reg["splitting4"].order == 4


def test_version_option_prints_the_version(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0
    assert capsys.readouterr().out.strip() == f"poissonkit {poissonkit.__version__}"
